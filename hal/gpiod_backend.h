/* isoterra — the GPIO knobs' seam to libgpiod: the little gpio.c needs of a
 * gpiochip, implemented once per libgpiod API.  hal/meson.build builds one:
 *
 *   gpiod_v1.c   libgpiod 1.5 / 1.6 (Debian 12)          line API, uAPI v1
 *   gpiod_v2.c   libgpiod 2.x (Debian 13, Raspberry Pi OS) request API, uAPI v2
 *
 * Everything else (finding a chip by name, path, label or number, the merge
 * of all lines' edges by kernel timestamp, decoding, debounce, the retries
 * when a chip vanishes) is gpio.c's and the same on both.  Each line is
 * requested on its own (its own request, event queue and fd), so a failure
 * names the line and both APIs see the same per-line kernel queues.
 *
 * Every function that can fail returns NULL or -1 with errno set. */
#ifndef ISOTERRA_HAL_GPIOD_BACKEND_H
#define ISOTERRA_HAL_GPIOD_BACKEND_H

#include "hal.h"

#include <stdbool.h>
#include <stdint.h>

#define HAL_GPIOD_EVENTS 16 /* most edges one read returns (the kernel queues 16 a line) */

struct hal_gpiod_chip; /* an open gpiochip */
struct hal_gpiod_line; /* one line requested for edge events */

struct hal_gpiod_edge {
	unsigned offset;
	uint64_t ts_ns;     /* the kernel's timestamp (CLOCK_MONOTONIC on kernels >= 5.7) */
	bool rising;        /* to the active level (active-low applied) */
};

/* "libgpiod 1.6.3 (API v1)": for the log */
const char *hal_gpiod_version(void);

/* The chip at a path (/dev/gpiochipN or a link to it). */
struct hal_gpiod_chip *hal_gpiod_chip_open(const char *path);
const char *hal_gpiod_chip_name(const struct hal_gpiod_chip *c);  /* "gpiochip3" */
const char *hal_gpiod_chip_label(const struct hal_gpiod_chip *c); /* "pinctrl-bcm2835" */
unsigned hal_gpiod_chip_lines(const struct hal_gpiod_chip *c);
/* Asks the kernel for the line's info: 0, or -1 (ENODEV: the chip is gone). */
int hal_gpiod_chip_check(struct hal_gpiod_chip *c, unsigned offset);
void hal_gpiod_chip_close(struct hal_gpiod_chip *c);

/* Requests line offset (< hal_gpiod_chip_lines) as an input with both-edge
 * events, the bias and active-low, for consumer "isoterra".  EBUSY: another
 * program holds it. */
struct hal_gpiod_line *hal_gpiod_line_request(struct hal_gpiod_chip *c, unsigned offset, enum hal_bias bias,
					      bool active_low);
int hal_gpiod_line_fd(const struct hal_gpiod_line *l);    /* readable when edges are queued */
int hal_gpiod_line_value(struct hal_gpiod_line *l);       /* 0 / 1 (active-low applied) or -1 */
/* Reads up to max (<= HAL_GPIOD_EVENTS) queued edges into ev: their number,
 * or -1.  Call when the fd is readable (it blocks on an empty queue). */
int hal_gpiod_line_read(struct hal_gpiod_line *l, struct hal_gpiod_edge *ev, int max);
void hal_gpiod_line_release(struct hal_gpiod_line *l);

/* gpio.c: the chip named descr, looked up as the knobs look it up (a
 * number, a label, a path or a name in /dev; also for hal/probe.c).  NULL
 * with errno. */
struct hal_gpiod_chip *hal_gpio_chip_lookup(const char *descr);

#endif
