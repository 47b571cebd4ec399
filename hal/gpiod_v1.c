/* isoterra — gpiod_backend.h on libgpiod 1.5 / 1.6 (the line API; the
 * kernel's uAPI v1).  A line belongs to its chip object here: gpio.c
 * releases every line before it closes the chip. */
#include "gpiod_backend.h"

#include <errno.h>
#include <gpiod.h>
#include <stdio.h>
#include <stdlib.h>

struct hal_gpiod_chip {
	struct gpiod_chip *chip;
	char name[40], label[40];
};

struct hal_gpiod_line {
	struct gpiod_line *line;
	int fd;
};

const char *hal_gpiod_version(void)
{
	return gpiod_version_string();
}

struct hal_gpiod_chip *hal_gpiod_chip_open(const char *path)
{
	struct hal_gpiod_chip *c = calloc(1, sizeof(*c));
	if (!c)
		return NULL;
	c->chip = gpiod_chip_open(path);
	if (!c->chip) {
		int e = errno;
		free(c);
		errno = e;
		return NULL;
	}
	const char *name = gpiod_chip_name(c->chip), *label = gpiod_chip_label(c->chip);
	snprintf(c->name, sizeof(c->name), "%s", name ? name : "");
	snprintf(c->label, sizeof(c->label), "%s", label ? label : "");
	return c;
}

const char *hal_gpiod_chip_name(const struct hal_gpiod_chip *c)
{
	return c->name;
}

const char *hal_gpiod_chip_label(const struct hal_gpiod_chip *c)
{
	return c->label;
}

unsigned hal_gpiod_chip_lines(const struct hal_gpiod_chip *c)
{
	return gpiod_chip_num_lines(c->chip);
}

int hal_gpiod_chip_check(struct hal_gpiod_chip *c, unsigned offset)
{
	struct gpiod_line *l = gpiod_chip_get_line(c->chip, offset);
	return l ? gpiod_line_update(l) : -1;
}

void hal_gpiod_chip_close(struct hal_gpiod_chip *c)
{
	if (!c)
		return;
	gpiod_chip_close(c->chip);
	free(c);
}

struct hal_gpiod_line *hal_gpiod_line_request(struct hal_gpiod_chip *c, unsigned offset, enum hal_bias bias,
					      bool active_low)
{
	int flags = (active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0) |
		    (bias == HAL_BIAS_DISABLE ? GPIOD_LINE_REQUEST_FLAG_BIAS_DISABLE : 0) |
		    (bias == HAL_BIAS_PULL_UP ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP : 0) |
		    (bias == HAL_BIAS_PULL_DOWN ? GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN : 0);
	struct hal_gpiod_line *l = calloc(1, sizeof(*l));
	if (!l)
		return NULL;
	l->line = gpiod_chip_get_line(c->chip, offset);
	if (!l->line || gpiod_line_request_both_edges_events_flags(l->line, "isoterra", flags) < 0) {
		int e = errno;
		free(l);
		errno = e;
		return NULL;
	}
	l->fd = gpiod_line_event_get_fd(l->line);
	if (l->fd < 0) {
		int e = errno;
		hal_gpiod_line_release(l);
		errno = e;
		return NULL;
	}
	return l;
}

int hal_gpiod_line_fd(const struct hal_gpiod_line *l)
{
	return l->fd;
}

int hal_gpiod_line_value(struct hal_gpiod_line *l)
{
	return gpiod_line_get_value(l->line);
}

int hal_gpiod_line_read(struct hal_gpiod_line *l, struct hal_gpiod_edge *ev, int max)
{
	struct gpiod_line_event e[HAL_GPIOD_EVENTS];
	if (max > HAL_GPIOD_EVENTS)
		max = HAL_GPIOD_EVENTS;
	int n = gpiod_line_event_read_fd_multiple(l->fd, e, (unsigned)max);
	if (n < 0)
		return -1;
	unsigned offset = gpiod_line_offset(l->line);
	for (int i = 0; i < n; i++)
		ev[i] = (struct hal_gpiod_edge){ .offset = offset,
						 .ts_ns = (uint64_t)e[i].ts.tv_sec * 1000000000ull + (uint64_t)e[i].ts.tv_nsec,
						 .rising = e[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE };
	return n;
}

void hal_gpiod_line_release(struct hal_gpiod_line *l)
{
	if (!l)
		return;
	gpiod_line_release(l->line);
	free(l);
}
