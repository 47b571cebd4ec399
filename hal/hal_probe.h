/* isoterra — what the hardware layer can tell about this machine before a
 * run (isoterra --probe): the gpiochips, whether a configured line can be
 * requested (requested as the knobs request it, then released at once),
 * and the V4L2 video output devices with their formats. */
#ifndef ISOTERRA_HAL_PROBE_H
#define ISOTERRA_HAL_PROBE_H

#include <stdbool.h>
#include <stddef.h>

#include "hal.h"

#define HAL_PROBE_FORMATS 24

/* "libgpiod 1.6.3 (API v1)", or NULL when the knobs are built out. */
const char *hal_probe_gpiod(void);

struct hal_probe_chip {
	char path[HAL_NAME_MAX], name[64], label[64];
	unsigned lines;
	char err[160];               /* cannot open it, "" = fine */
};
/* The gpiochips in /dev (sorted): how many were written (<= max), or -1
 * when GPIO is built out. */
int hal_probe_gpiochips(struct hal_probe_chip *out, int max);

/* Looks chip up as the knobs do (number, label, path or name), requests
 * line offset as the knobs request it and releases it.  0, or -1 with err;
 * path gets the chip's device file when it was found ("" otherwise). */
int hal_probe_gpio_line(const char *chip, int offset, enum hal_bias bias, bool active_low, char *path,
			size_t pathlen, char *err, size_t errlen);

struct hal_probe_v4l2 {
	char path[HAL_NAME_MAX];
	char driver[32], card[64];
	bool output;                 /* single-planar video output (what the V4L2 sink writes) */
	bool output_mplane;          /* multi-planar output only (not supported) */
	int nfmt;
	char fmt[HAL_PROBE_FORMATS][8];  /* fourcc as text: "YUYV" */
	bool fmt_ok[HAL_PROBE_FORMATS];  /* the GPU conversion writes it (convert.h) */
	char err[160];               /* cannot open, not V4L2, ...; "" = fine */
};
/* One device: 0, or -1 with out->err. */
int hal_probe_v4l2_one(const char *path, struct hal_probe_v4l2 *out);
/* The /dev/video* devices (sorted): how many were written (<= max). */
int hal_probe_v4l2_list(struct hal_probe_v4l2 *out, int max);

#endif
