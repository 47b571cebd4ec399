/* isoterra — --probe's hardware queries (hal_probe.h): gpiochips and their
 * lines through the knobs' own gpiod backend and chip lookup (gpio.c),
 * V4L2 output devices and the formats the conversion can write. */
#include "hal_probe.h"
#include "convert.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <linux/videodev2.h>

#ifdef HAVE_LIBGPIOD
#include "gpiod_backend.h"
#endif

static int entries(const char *prefix, char (*names)[HAL_NAME_MAX], int max)
{
	struct dirent **list;
	int n = scandir("/dev", &list, NULL, alphasort);
	if (n < 0)
		return 0;
	int k = 0;
	for (int i = 0; i < n; i++) {
		const char *d = list[i]->d_name;
		if (k < max && !strncmp(d, prefix, strlen(prefix)) && d[strlen(prefix)] >= '0' &&
		    d[strlen(prefix)] <= '9')
			snprintf(names[k++], HAL_NAME_MAX, "/dev/%.200s", d);
		free(list[i]);
	}
	free(list);
	return k;
}

#ifdef HAVE_LIBGPIOD
const char *hal_probe_gpiod(void)
{
	return hal_gpiod_version();
}

int hal_probe_gpiochips(struct hal_probe_chip *out, int max)
{
	char (*names)[HAL_NAME_MAX] = calloc((size_t)(max > 0 ? max : 1), HAL_NAME_MAX);
	if (!names)
		return 0;
	int n = entries("gpiochip", names, max);
	for (int i = 0; i < n; i++) {
		struct hal_probe_chip *c = &out[i];
		memset(c, 0, sizeof(*c));
		snprintf(c->path, sizeof(c->path), "%s", names[i]);
		struct hal_gpiod_chip *ch = hal_gpiod_chip_open(c->path);
		if (!ch) {
			snprintf(c->err, sizeof(c->err), "cannot open: %s", strerror(errno));
			continue;
		}
		snprintf(c->name, sizeof(c->name), "%s", hal_gpiod_chip_name(ch));
		snprintf(c->label, sizeof(c->label), "%s", hal_gpiod_chip_label(ch));
		c->lines = hal_gpiod_chip_lines(ch);
		hal_gpiod_chip_close(ch);
	}
	free(names);
	return n;
}

int hal_probe_gpio_line(const char *chip, int offset, enum hal_bias bias, bool active_low, char *path,
			size_t pathlen, char *err, size_t errlen)
{
	path[0] = 0;
	struct hal_gpiod_chip *c = hal_gpio_chip_lookup(chip);
	if (!c) {
		snprintf(err, errlen, "gpiochip '%s' not found: %s", chip, strerror(errno));
		return -1;
	}
	snprintf(path, pathlen, "/dev/%s", hal_gpiod_chip_name(c));
	int rc = -1;
	if (offset < 0 || (unsigned)offset >= hal_gpiod_chip_lines(c)) {
		snprintf(err, errlen, "%s (%s) has %u lines, no line %d", hal_gpiod_chip_name(c), hal_gpiod_chip_label(c),
			 hal_gpiod_chip_lines(c), offset);
	} else {
		struct hal_gpiod_line *l = hal_gpiod_line_request(c, (unsigned)offset, bias, active_low);
		if (l) {
			hal_gpiod_line_release(l);
			rc = 0;
		} else {
			int e = errno;
			snprintf(err, errlen, "%s line %d cannot be requested: %s%s", hal_gpiod_chip_name(c), offset,
				 strerror(e), e == EBUSY ? " (another program holds it)" : "");
		}
	}
	hal_gpiod_chip_close(c);
	return rc;
}
#else
const char *hal_probe_gpiod(void)
{
	return NULL;
}

int hal_probe_gpiochips(struct hal_probe_chip *out, int max)
{
	(void)out;
	(void)max;
	return -1;
}

int hal_probe_gpio_line(const char *chip, int offset, enum hal_bias bias, bool active_low, char *path,
			size_t pathlen, char *err, size_t errlen)
{
	(void)chip;
	(void)offset;
	(void)bias;
	(void)active_low;
	if (pathlen)
		path[0] = 0;
	snprintf(err, errlen, "GPIO knobs are built out (no libgpiod at build time)");
	return -1;
}
#endif

static int xioctl(int fd, unsigned long req, void *arg)
{
	int r;
	do
		r = ioctl(fd, req, arg);
	while (r < 0 && errno == EINTR);
	return r;
}

int hal_probe_v4l2_one(const char *path, struct hal_probe_v4l2 *out)
{
	memset(out, 0, sizeof(*out));
	snprintf(out->path, sizeof(out->path), "%s", path);
	int fd = open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0) {
		snprintf(out->err, sizeof(out->err), "cannot open: %s", strerror(errno));
		return -1;
	}
	struct v4l2_capability cap;
	memset(&cap, 0, sizeof(cap));
	if (xioctl(fd, VIDIOC_QUERYCAP, &cap) < 0) {
		snprintf(out->err, sizeof(out->err), "not a V4L2 device (VIDIOC_QUERYCAP: %s)", strerror(errno));
		close(fd);
		return -1;
	}
	snprintf(out->driver, sizeof(out->driver), "%.16s", (const char *)cap.driver);
	snprintf(out->card, sizeof(out->card), "%.32s", (const char *)cap.card);
	uint32_t caps = cap.capabilities & V4L2_CAP_DEVICE_CAPS ? cap.device_caps : cap.capabilities;
	out->output = caps & V4L2_CAP_VIDEO_OUTPUT;
	out->output_mplane = !out->output && (caps & V4L2_CAP_VIDEO_OUTPUT_MPLANE);
	if (out->output) {
		struct v4l2_fmtdesc d = { .type = V4L2_BUF_TYPE_VIDEO_OUTPUT };
		for (d.index = 0; out->nfmt < HAL_PROBE_FORMATS && xioctl(fd, VIDIOC_ENUM_FMT, &d) == 0; d.index++) {
			snprintf(out->fmt[out->nfmt], sizeof(out->fmt[0]), "%.4s", (const char *)&d.pixelformat);
			out->fmt_ok[out->nfmt] = conv_fmt_from_fourcc(d.pixelformat) >= 0;
			out->nfmt++;
		}
	}
	close(fd);
	return 0;
}

int hal_probe_v4l2_list(struct hal_probe_v4l2 *out, int max)
{
	char (*names)[HAL_NAME_MAX] = calloc((size_t)(max > 0 ? max : 1), HAL_NAME_MAX);
	if (!names)
		return 0;
	int n = entries("video", names, max);
	for (int i = 0; i < n; i++)
		hal_probe_v4l2_one(names[i], &out[i]);
	free(names);
	return n;
}
