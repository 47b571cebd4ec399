/* isoterra — the controls (see controls.h): inputs (GPIO knobs, keys, a
 * gamepad) -> parameters, presets, the autopilot's toggle, pause clock,
 * OSD, screenshots, the knob log.  hal's configuration:
 * hal_config.c, v4l2_config.c. */
#include "controls.h"
#include "output.h"
#include "core.h"
#include "render.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---- knob mapping ------------------------------------------------------------ */
int knobs_init(struct knobs *k, const char *csv, char *err, size_t errlen)
{
	memset(k, 0, sizeof(*k));
	if (!csv || !csv[0]) {
		for (size_t i = 0; i < param_count && k->count < (int)ARRAY_SIZE(k->list); i++)
			if (param_table[i].flags & P_LIVE)
				k->list[k->count++] = &param_table[i];
		return 0;
	}
	char buf[PARAM_STR_MAX];
	snprintf(buf, sizeof(buf), "%s", csv);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ", ", &save); tok; tok = strtok_r(NULL, ", ", &save)) {
		const struct param_info *pi = params_find(tok);
		if (!pi) {
			snprintf(err, errlen, "knob_params: unknown parameter '%s'", tok);
			return -1;
		}
		if (pi->type == PT_STRING) {
			snprintf(err, errlen, "knob_params: '%s' is text, a knob needs a number", tok);
			return -1;
		}
		if (k->count == (int)ARRAY_SIZE(k->list)) {
			snprintf(err, errlen, "knob_params: too many parameters");
			return -1;
		}
		k->list[k->count++] = pi;
	}
	if (!k->count) {
		snprintf(err, errlen, "knob_params: no parameter named");
		return -1;
	}
	return 0;
}

/* A tenth of the decade of the default (of min(range, 10) for a zero
 * default), at most a twentieth of the range. */
double knob_step(const struct param_info *pi)
{
	if (pi->type != PT_FLOAT)
		return 1;
	double range = pi->hi - pi->lo;
	double base = pi->def != 0 ? fabs(pi->def) : fmin(range, 10.0);
	double step = pow(10.0, floor(log10(base))) / 10.0;
	while (step > range / 20.0)
		step /= 10.0;
	return step;
}

bool knob_change(const struct knobs *k, struct params *p, int delta)
{
	if (!k->count || !delta)
		return false;
	const struct param_info *pi = k->list[k->sel];
	double old = params_get_number(p, pi);
	double v;
	if (pi->type == PT_BOOL) {
		v = (delta % 2) ? !old : old;
	} else {
		double step = knob_step(pi);
		v = old + delta * step;
		if (pi->type == PT_FLOAT)
			v = round(v / step) * step;
	}
	params_set_number(p, pi, v);
	return params_get_number(p, pi) != old;
}

/* ---- the controls ------------------------------------------------------------- */
struct controls {
	struct hal_gpio *gpio;
	struct hal_keys *keys;
	struct hal_gamepad *pad;
	struct osd *osd;
	struct knobs knobs;
	struct params base;    /* the start-up values (reset, preset cycling) */
	int preset;            /* index of the last preset applied, -1 none */
	unsigned presets_applied; /* presses of the preset button that applied one */
	bool paused;
	bool shot;             /* a screenshot asked for (controls_take_screenshot) */
	FILE *knob_log;
	char osd_title[OSD_COLS + 1], osd_value[OSD_COLS + 1];
	float osd_bar;
	uint64_t osd_until, osd_fade;
	float fly[HAL_FLY_AXES]; /* manual camera: held input */
	uint64_t fly_until;      /* ... until this time (ns) */
	float stick[HAL_FLY_AXES]; /* a gamepad's sticks at the last poll (levels) */
};

/* The GPIO controls, the keys and the gamepad; err only for bad configuration. */
static int open_inputs(struct controls *c, const struct params *p, char *err, size_t errlen)
{
	struct hal_gpio_config gc;
	if (hal_config_gpio(p, &gc, err, errlen) < 0)
		return -1;
	c->gpio = hal_gpio_open(&gc, err, errlen);
	if (!c->gpio && err[0])
		return -1;
	struct hal_keys_config kc;
	hal_config_keys(p, &kc);
	c->keys = hal_keys_open(&kc, err, errlen);
	if (!c->keys && err[0])
		return -1;
	struct hal_gamepad_config pc;
	hal_config_gamepad(p, &pc);
	c->pad = hal_gamepad_open(&pc, err, errlen);
	return !c->pad && err[0] ? -1 : 0;
}

struct controls *controls_create(const struct params *p, char *err, size_t errlen)
{
	struct controls *c = calloc(1, sizeof(*c));
	if (!c) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	err[0] = 0;
	c->base = *p;
	c->preset = -1;
	if (knobs_init(&c->knobs, p->knob_params, err, errlen) < 0 ||
	    open_inputs(c, p, err, errlen) < 0)
		goto fail;
	if (p->knob_log[0]) {
		c->knob_log = fopen(p->knob_log, "a");
		if (!c->knob_log) {
			snprintf(err, errlen, "knob_log: cannot open '%s': %s", p->knob_log, strerror(errno));
			goto fail;
		}
	}
	if (p->osd && (c->gpio || c->keys || c->pad || p->shader_dir[0])) { /* knobs; live shader errors */
		c->osd = osd_create(err, errlen);
		if (!c->osd)
			goto fail;
	}
	if (c->gpio || c->keys || c->pad)
		log_info("knobs: %d parameters (%s first)", c->knobs.count, c->knobs.count ? c->knobs.list[0]->name : "-");
	return c;
fail:
	controls_destroy(c);
	return NULL;
}

void controls_destroy(struct controls *c)
{
	if (!c)
		return;
	hal_gpio_close(c->gpio);
	hal_keys_close(c->keys);
	hal_gamepad_close(c->pad);
	osd_destroy(c->osd);
	if (c->knob_log)
		fclose(c->knob_log);
	free(c);
}

/* One line of the knob log (tests, kiosks): "name value", "select name", ... */
static void knob_log(struct controls *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void knob_log(struct controls *c, const char *fmt, ...)
{
	if (!c->knob_log)
		return;
	va_list ap;
	va_start(ap, fmt);
	vfprintf(c->knob_log, fmt, ap);
	va_end(ap);
	fputc('\n', c->knob_log);
	fflush(c->knob_log);
}

static void show(struct controls *c, const struct params *p, const char *title, const char *value, float bar)
{
	snprintf(c->osd_title, sizeof(c->osd_title), "%s", title);
	snprintf(c->osd_value, sizeof(c->osd_value), "%s", value);
	c->osd_bar = bar;
	c->osd_until = hal_now_ns() + (uint64_t)(p->osd_seconds * 1e9);
	c->osd_fade = (uint64_t)(fmin(0.5, p->osd_seconds / 2) * 1e9);
}

void controls_notice(struct controls *c, const struct params *p, const char *title, const char *text)
{
	if (c)
		show(c, p, title, text, -1.0f);
}

static void show_param(struct controls *c, const struct params *p, const char *prefix)
{
	if (!c->knobs.count)
		return;
	const struct param_info *pi = c->knobs.list[c->knobs.sel];
	char val[64], title[OSD_COLS + 1];
	params_format(p, pi, val, sizeof(val));
	float bar = -1;
	if (pi->type == PT_FLOAT || pi->type == PT_INT)
		bar = (float)((params_get_number(p, pi) - pi->lo) / (pi->hi - pi->lo));
	snprintf(title, sizeof(title), "%s%s", prefix, pi->name);
	show(c, p, title, val, bar);
}

static void log_change(struct controls *c, const struct params *p, const struct param_info *pi, const char *what)
{
	char val[64];
	params_format(p, pi, val, sizeof(val));
	log_info("knob: %s = %s%s", pi->name, val, what);
	knob_log(c, "%s %s", pi->name, val);
}

static void apply_preset(struct controls *c, struct params *p)
{
	c->preset = (c->preset + 1) % (int)preset_count;
	struct params q;
	char e[256];
	params_defaults(&q);
	if (params_apply_preset(&q, presets[c->preset].name, e, sizeof(e)) < 0) {
		log_warn("preset: %s", e);
		return;
	}
	/* the terrain from the preset; application settings stay */
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if ((pi->flags & P_SHADER) && pi->type != PT_STRING && strcmp(pi->name, "time"))
			params_set_number(p, pi, params_get_number(&q, pi));
	}
	c->presets_applied++;
	log_info("knob: preset %s", presets[c->preset].name);
	knob_log(c, "preset %s", presets[c->preset].name);
	show(c, p, "preset", presets[c->preset].name, -1);
}

/* The keys held lately plus the gamepad's sticks, each axis within -1..1. */
void controls_flight(struct controls *c, float move[3], float turn[2])
{
	bool on = c && hal_now_ns() < c->fly_until;
	float v[HAL_FLY_AXES];
	for (int i = 0; i < HAL_FLY_AXES; i++)
		v[i] = c ? fmaxf(-1.0f, fminf(1.0f, (on ? c->fly[i] : 0.0f) + c->stick[i])) : 0.0f;
	for (int i = 0; i < 3; i++)
		move[i] = v[HAL_FLY_FORWARD + i];
	for (int i = 0; i < 2; i++)
		turn[i] = v[HAL_FLY_YAW + i];
}

/* The autopilot on or off: the world's camera between auto and manual
 * (the scene steers by the flight input while it is manual; the
 * autopilot's guard keeps either out of rock). */
static void toggle_autopilot(struct controls *c, struct params *p)
{
	p->camera = p->camera == CAMERA_MANUAL ? CAMERA_AUTO : CAMERA_MANUAL;
	const char *cam = p->camera == CAMERA_MANUAL ? "manual" : "auto";
	log_info("knob: camera %s (autopilot %s)", cam, p->camera == CAMERA_MANUAL ? "off" : "on");
	knob_log(c, "camera %s", cam);
	show(c, p, "camera", cam, -1);
}

/* Flight keys: held for 0.15 s from the last press. */
static void hold_flight(struct controls *c, const struct hal_input *in)
{
	bool flying = false;
	for (int i = 0; i < HAL_FLY_AXES; i++)
		flying |= in->fly[i] != 0;
	if (!flying)
		return;
	for (int i = 0; i < HAL_FLY_AXES; i++)
		c->fly[i] = in->fly[i] > 0 ? 1.0f : in->fly[i] < 0 ? -1.0f : 0.0f;
	c->fly_until = hal_now_ns() + 150000000ull;
}

/* Select, change, reset: the knobs' parameter. */
static void apply_knobs(struct controls *c, struct params *p, const struct hal_input *in)
{
	struct knobs *k = &c->knobs;
	int select = in->select + in->actions[HAL_NEXT] - in->actions[HAL_PREV];
	if (select && k->count) {
		k->sel = ((k->sel + select) % k->count + k->count) % k->count;
		show_param(c, p, "> ");
		log_info("knob: selected %s", k->list[k->sel]->name);
		knob_log(c, "select %s", k->list[k->sel]->name);
	}
	if (in->change && knob_change(k, p, in->change)) {
		log_change(c, p, k->list[k->sel], "");
		show_param(c, p, "");
	}
	if (in->actions[HAL_RESET] && k->count) {
		const struct param_info *pi = k->list[k->sel];
		params_set_number(p, pi, params_get_number(&c->base, pi));
		log_change(c, p, pi, " (reset)");
		show_param(c, p, "reset ");
	}
}

int controls_poll(struct controls *c, struct params *p)
{
	if (!c)
		return 0;
	struct hal_input in;
	memset(&in, 0, sizeof(in));
	hal_gpio_poll(c->gpio, hal_now_ns(), &in);
	hal_keys_poll(c->keys, &in);
	hal_gamepad_poll(c->pad, hal_now_ns(), &in);
	memcpy(c->stick, in.stick, sizeof(c->stick));
	hold_flight(c, &in);
	apply_knobs(c, p, &in);
	for (int i = 0; i < in.actions[HAL_PRESET]; i++)
		apply_preset(c, p);
	if (in.actions[HAL_PAUSE] % 2) {
		c->paused = !c->paused;
		log_info("knob: %s", c->paused ? "paused" : "running");
		knob_log(c, "%s", c->paused ? "paused" : "running");
		show(c, p, c->paused ? "paused" : "running", "", -1);
	}
	if (in.actions[HAL_AUTOPILOT] % 2)
		toggle_autopilot(c, p);
	if (in.actions[HAL_SCREENSHOT])
		c->shot = true;
	return in.actions[HAL_QUIT] != 0;
}

unsigned controls_presets_applied(const struct controls *c)
{
	return c ? c->presets_applied : 0;
}

bool controls_paused(const struct controls *c)
{
	return c && c->paused;
}

float pause_clock_time(struct pause_clock *pc, float t, bool paused)
{
	if (!pc->init) {
		pc->init = true;
		pc->raw = t;
	}
	if (paused)
		pc->offset += t - pc->raw;
	pc->raw = t;
	return t - pc->offset;
}

bool controls_take_screenshot(struct controls *c)
{
	bool shot = c && c->shot;
	if (c)
		c->shot = false;
	return shot;
}

int controls_frame(struct controls *c, struct renderer *r, const struct params *p, char *err, size_t errlen)
{
	if (!c)
		return 0;
	GLuint fbo;
	int w, h;
	renderer_target(r, &fbo, &w, &h);
	uint64_t now = hal_now_ns();
	if (c->osd && p->osd && now < c->osd_until) {
		uint64_t left = c->osd_until - now;
		float alpha = c->osd_fade && left < c->osd_fade ? (float)left / (float)c->osd_fade : 1.0f;
		if (osd_draw(c->osd, fbo, w, h, c->osd_title, c->osd_value, c->osd_bar, p->osd_scale, alpha) < 0) {
			snprintf(err, errlen, "drawing the on-screen display failed");
			return -1;
		}
	}
	return 0;
}
