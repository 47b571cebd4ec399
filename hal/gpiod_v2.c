/* isoterra — gpiod_backend.h on libgpiod 2.x (the request API; the kernel's
 * uAPI v2, Linux >= 5.10).  One request per line: its own fd and event
 * queue, as in uAPI v1, so gpio.c reads and merges the same way on both. */
#include "gpiod_backend.h"

#include <errno.h>
#include <gpiod.h>
#include <stdio.h>
#include <stdlib.h>

struct hal_gpiod_chip {
	struct gpiod_chip *chip;
	char name[40], label[40];
	unsigned lines;
};

struct hal_gpiod_line {
	struct gpiod_line_request *req;
	struct gpiod_edge_event_buffer *buf;
	unsigned offset;
	int fd;
};

const char *hal_gpiod_version(void)
{
	return gpiod_api_version();
}

struct hal_gpiod_chip *hal_gpiod_chip_open(const char *path)
{
	struct hal_gpiod_chip *c = calloc(1, sizeof(*c));
	if (!c)
		return NULL;
	c->chip = gpiod_chip_open(path);
	struct gpiod_chip_info *info = c->chip ? gpiod_chip_get_info(c->chip) : NULL;
	if (!info) {
		int e = errno;
		if (c->chip)
			gpiod_chip_close(c->chip);
		free(c);
		errno = e;
		return NULL;
	}
	const char *name = gpiod_chip_info_get_name(info), *label = gpiod_chip_info_get_label(info);
	snprintf(c->name, sizeof(c->name), "%s", name ? name : "");
	snprintf(c->label, sizeof(c->label), "%s", label ? label : "");
	c->lines = (unsigned)gpiod_chip_info_get_num_lines(info);
	gpiod_chip_info_free(info);
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
	return c->lines;
}

int hal_gpiod_chip_check(struct hal_gpiod_chip *c, unsigned offset)
{
	struct gpiod_line_info *info = gpiod_chip_get_line_info(c->chip, offset);
	if (!info)
		return -1;
	gpiod_line_info_free(info);
	return 0;
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
	static const enum gpiod_line_bias bias_of[] = {
		[HAL_BIAS_AS_IS] = GPIOD_LINE_BIAS_AS_IS,
		[HAL_BIAS_DISABLE] = GPIOD_LINE_BIAS_DISABLED,
		[HAL_BIAS_PULL_UP] = GPIOD_LINE_BIAS_PULL_UP,
		[HAL_BIAS_PULL_DOWN] = GPIOD_LINE_BIAS_PULL_DOWN,
	};
	if ((unsigned)bias >= sizeof(bias_of) / sizeof(bias_of[0])) {
		errno = EINVAL;
		return NULL;
	}
	struct hal_gpiod_line *l = calloc(1, sizeof(*l));
	struct gpiod_line_settings *ls = gpiod_line_settings_new();
	struct gpiod_line_config *lc = gpiod_line_config_new();
	struct gpiod_request_config *rc = gpiod_request_config_new();
	bool ok = l && ls && lc && rc && (l->buf = gpiod_edge_event_buffer_new(HAL_GPIOD_EVENTS)) &&
		  gpiod_line_settings_set_direction(ls, GPIOD_LINE_DIRECTION_INPUT) == 0 &&
		  gpiod_line_settings_set_edge_detection(ls, GPIOD_LINE_EDGE_BOTH) == 0 &&
		  gpiod_line_settings_set_bias(ls, bias_of[bias]) == 0;
	if (ok) {
		gpiod_line_settings_set_active_low(ls, active_low);
		gpiod_request_config_set_consumer(rc, "isoterra");
		ok = gpiod_line_config_add_line_settings(lc, &offset, 1, ls) == 0 &&
		     (l->req = gpiod_chip_request_lines(c->chip, rc, lc));
	}
	int e = errno;
	if (rc)
		gpiod_request_config_free(rc);
	if (lc)
		gpiod_line_config_free(lc);
	if (ls)
		gpiod_line_settings_free(ls);
	if (!ok) {
		hal_gpiod_line_release(l);
		errno = e;
		return NULL;
	}
	l->offset = offset;
	l->fd = gpiod_line_request_get_fd(l->req);
	return l;
}

int hal_gpiod_line_fd(const struct hal_gpiod_line *l)
{
	return l->fd;
}

int hal_gpiod_line_value(struct hal_gpiod_line *l)
{
	enum gpiod_line_value v = gpiod_line_request_get_value(l->req, l->offset);
	return v == GPIOD_LINE_VALUE_ERROR ? -1 : v == GPIOD_LINE_VALUE_ACTIVE;
}

int hal_gpiod_line_read(struct hal_gpiod_line *l, struct hal_gpiod_edge *ev, int max)
{
	if (max > HAL_GPIOD_EVENTS)
		max = HAL_GPIOD_EVENTS;
	int n = gpiod_line_request_read_edge_events(l->req, l->buf, (size_t)max);
	if (n < 0)
		return -1;
	for (int i = 0; i < n; i++) {
		struct gpiod_edge_event *e = gpiod_edge_event_buffer_get_event(l->buf, (unsigned long)i);
		if (!e) {
			errno = EIO;
			return -1;
		}
		ev[i] = (struct hal_gpiod_edge){ .offset = gpiod_edge_event_get_line_offset(e),
						 .ts_ns = gpiod_edge_event_get_timestamp_ns(e),
						 .rising = gpiod_edge_event_get_event_type(e) == GPIOD_EDGE_EVENT_RISING_EDGE };
	}
	return n;
}

void hal_gpiod_line_release(struct hal_gpiod_line *l)
{
	if (!l)
		return;
	if (l->req)
		gpiod_line_request_release(l->req);
	if (l->buf)
		gpiod_edge_event_buffer_free(l->buf);
	free(l);
}
