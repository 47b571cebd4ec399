/* isoterra — the hardware layer's frame hooks (see hal.h): inputs ->
 * parameters, pause clock, OSD, screenshots, V4L2 output. */
#include "hal.h"
#include "v4l2_out.h"
#include "osd.h"
#include "render.h"
#include "log.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct hal {
	struct hal_gpio *gpio;
	struct hal_keys *keys;
	struct v4l2_out *v4l2;
	struct osd *osd;
	struct knobs knobs;
	struct params base;    /* the start-up values (reset, preset cycling) */
	int preset;            /* index of the last preset applied, -1 none */
	bool paused, t_init;
	float t_raw, t_offset, t_frozen;
	bool shot;
	int shot_n;
	FILE *knob_log;
	char osd_title[OSD_COLS + 1], osd_value[OSD_COLS + 1];
	float osd_bar;
	uint64_t osd_until, osd_fade;
	float fly[5];          /* manual camera: held input */
	uint64_t fly_until;    /* ... until this time (ns) */
};

uint64_t hal_now_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

/* "shot%03d.png": exactly one %d or %0Nd. */
static int shot_name(const char *pattern, int n, char *buf, size_t len)
{
	const char *pc = strchr(pattern, '%');
	if (!pc) {
		snprintf(buf, len, "%s", pattern);
		return 0;
	}
	const char *q = pc + 1;
	int width = 0;
	while (*q >= '0' && *q <= '9' && width < 100)
		width = width * 10 + (*q++ - '0');
	if (*q != 'd' || strchr(q + 1, '%'))
		return -1;
	snprintf(buf, len, "%.*s%0*d%s", (int)(pc - pattern), pattern, width, n, q + 1);
	return 0;
}

struct hal *hal_open(const struct params *p, int width, int height, char *err, size_t errlen)
{
	struct hal *h = calloc(1, sizeof(*h));
	if (!h) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	h->base = *p;
	h->preset = -1;
	char name[PARAM_STR_MAX + 32];
	size_t sl = strlen(p->screenshot);
	if (shot_name(p->screenshot, 0, name, sizeof(name)) < 0 || sl < 5 || strcmp(p->screenshot + sl - 4, ".png")) {
		snprintf(err, errlen, "screenshot: '%s' must end in .png with at most one %%d (or %%0Nd)", p->screenshot);
		goto fail;
	}
	if (knobs_init(&h->knobs, p->knob_params, err, errlen) < 0)
		goto fail;
	h->gpio = hal_gpio_open(p, err, errlen);
	if (!h->gpio && err[0])
		goto fail;
	h->keys = hal_keys_open(p, err, errlen);
	if (!h->keys && err[0])
		goto fail;
	h->v4l2 = v4l2_out_open(p, width, height, err, errlen);
	if (!h->v4l2 && err[0])
		goto fail;
	if (p->knob_log[0]) {
		h->knob_log = fopen(p->knob_log, "a");
		if (!h->knob_log) {
			snprintf(err, errlen, "knob_log: cannot open '%s': %s", p->knob_log, strerror(errno));
			goto fail;
		}
	}
	if (p->osd && (h->gpio || h->keys)) {
		h->osd = osd_create(err, errlen);
		if (!h->osd)
			goto fail;
	}
	if (h->gpio || h->keys)
		log_info("knobs: %d parameters (%s first)", h->knobs.count, h->knobs.count ? h->knobs.list[0]->name : "-");
	return h;
fail:
	hal_close(h);
	return NULL;
}

void hal_close(struct hal *h)
{
	if (!h)
		return;
	v4l2_out_close(h->v4l2);
	hal_gpio_close(h->gpio);
	hal_keys_close(h->keys);
	osd_destroy(h->osd);
	if (h->knob_log)
		fclose(h->knob_log);
	free(h);
}

static void show(struct hal *h, const struct params *p, const char *title, const char *value, float bar)
{
	snprintf(h->osd_title, sizeof(h->osd_title), "%s", title);
	snprintf(h->osd_value, sizeof(h->osd_value), "%s", value);
	h->osd_bar = bar;
	uint64_t now = hal_now_ns();
	h->osd_until = now + (uint64_t)(p->osd_seconds * 1e9);
	h->osd_fade = (uint64_t)(fmin(0.5, p->osd_seconds / 2) * 1e9);
}

static void show_param(struct hal *h, const struct params *p, const char *prefix)
{
	if (!h->knobs.count)
		return;
	const struct param_info *pi = h->knobs.list[h->knobs.sel];
	char val[64], title[OSD_COLS + 1];
	params_format(p, pi, val, sizeof(val));
	float bar = -1;
	if (pi->type == PT_FLOAT || pi->type == PT_INT)
		bar = (float)((params_get_number(p, pi) - pi->lo) / (pi->hi - pi->lo));
	snprintf(title, sizeof(title), "%s%s", prefix, pi->name);
	show(h, p, title, val, bar);
}

static void log_change(struct hal *h, const struct params *p, const struct param_info *pi, const char *what)
{
	char val[64];
	params_format(p, pi, val, sizeof(val));
	log_info("knob: %s = %s%s", pi->name, val, what);
	if (h->knob_log) {
		fprintf(h->knob_log, "%s %s\n", pi->name, val);
		fflush(h->knob_log);
	}
}

static void apply_preset(struct hal *h, struct params *p)
{
	h->preset = (h->preset + 1) % (int)preset_count;
	struct params q;
	char e[256];
	params_defaults(&q);
	if (params_apply_preset(&q, presets[h->preset].name, e, sizeof(e)) < 0) {
		log_warn("preset: %s", e);
		return;
	}
	/* the terrain from the preset; application settings stay */
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if ((pi->flags & P_SHADER) && pi->type != PT_STRING && strcmp(pi->name, "time"))
			params_set_number(p, pi, params_get_number(&q, pi));
	}
	log_info("knob: preset %s", presets[h->preset].name);
	if (h->knob_log) {
		fprintf(h->knob_log, "preset %s\n", presets[h->preset].name);
		fflush(h->knob_log);
	}
	show(h, p, "preset", presets[h->preset].name, -1);
}

void hal_flight(struct hal *h, float move[3], float turn[2])
{
	bool on = h && hal_now_ns() < h->fly_until;
	for (int i = 0; i < 3; i++)
		move[i] = on ? h->fly[i] : 0.0f;
	for (int i = 0; i < 2; i++)
		turn[i] = on ? h->fly[3 + i] : 0.0f;
}

int hal_poll(struct hal *h, struct params *p)
{
	if (!h)
		return 0;
	struct hal_input in;
	memset(&in, 0, sizeof(in));
	hal_gpio_poll(h->gpio, hal_now_ns(), &in);
	hal_keys_poll(h->keys, &in);
	bool flying = false;
	for (int i = 0; i < 5; i++)
		flying |= in.fly[i] != 0;
	if (flying) {
		for (int i = 0; i < 5; i++)
			h->fly[i] = in.fly[i] > 0 ? 1.0f : in.fly[i] < 0 ? -1.0f : 0.0f;
		h->fly_until = hal_now_ns() + 150000000ull;
	}
	struct knobs *k = &h->knobs;
	in.select += in.actions[HAL_NEXT] - in.actions[HAL_PREV];
	if (in.select && k->count) {
		k->sel = ((k->sel + in.select) % k->count + k->count) % k->count;
		show_param(h, p, "> ");
		log_info("knob: selected %s", k->list[k->sel]->name);
		if (h->knob_log) {
			fprintf(h->knob_log, "select %s\n", k->list[k->sel]->name);
			fflush(h->knob_log);
		}
	}
	if (in.change && knob_change(k, p, in.change)) {
		log_change(h, p, k->list[k->sel], "");
		show_param(h, p, "");
	}
	if (in.actions[HAL_RESET] && k->count) {
		const struct param_info *pi = k->list[k->sel];
		params_set_number(p, pi, params_get_number(&h->base, pi));
		log_change(h, p, pi, " (reset)");
		show_param(h, p, "reset ");
	}
	for (int i = 0; i < in.actions[HAL_PRESET]; i++)
		apply_preset(h, p);
	if (in.actions[HAL_PAUSE] % 2) {
		h->paused = !h->paused;
		log_info("knob: %s", h->paused ? "paused" : "running");
		if (h->knob_log) {
			fprintf(h->knob_log, "%s\n", h->paused ? "paused" : "running");
			fflush(h->knob_log);
		}
		show(h, p, h->paused ? "paused" : "running", "", -1);
	}
	if (in.actions[HAL_SCREENSHOT])
		h->shot = true;
	return in.actions[HAL_QUIT] != 0;
}

float hal_time(struct hal *h, float t)
{
	if (!h)
		return t;
	if (!h->t_init) {
		h->t_init = true;
		h->t_raw = t;
	}
	if (h->paused)
		h->t_offset += t - h->t_raw;
	h->t_raw = t;
	return t - h->t_offset;
}

int hal_frame(struct hal *h, struct renderer *r, const struct params *p)
{
	if (!h)
		return 0;
	GLuint fbo;
	int w, hh;
	renderer_target(r, &fbo, &w, &hh);
	uint64_t now = hal_now_ns();
	if (h->osd && p->osd && now < h->osd_until) {
		uint64_t left = h->osd_until - now;
		float alpha = h->osd_fade && left < h->osd_fade ? (float)left / (float)h->osd_fade : 1.0f;
		if (osd_draw(h->osd, fbo, w, hh, h->osd_title, h->osd_value, h->osd_bar, p->osd_scale, alpha) < 0)
			return -1;
	}
	if (h->shot) {
		h->shot = false;
		struct image img = { 0 };
		char name[PARAM_STR_MAX + 32], e[512];
		shot_name(p->screenshot, h->shot_n++, name, sizeof(name));
		if (renderer_read(r, &img) < 0) {
			log_error("screenshot: reading the frame back failed");
			return -1;
		}
		if (image_write_png(&img, name, e, sizeof(e)) < 0)
			log_warn("screenshot: %s", e);
		else
			log_info("screenshot: %s", name);
		image_free(&img);
	}
	return v4l2_out_frame(h->v4l2, fbo, w, hh);
}
