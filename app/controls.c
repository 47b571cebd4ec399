/* isoterra — the controls (see controls.h): hal's configuration from the
 * parameter table, inputs -> parameters, presets, pause clock, OSD,
 * screenshots, the knob log. */
#include "controls.h"
#include "abi.h"
#include "cli.h"
#include "gpu.h"
#include "log.h"
#include "osd.h"
#include "render.h"
#include "util.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* ---- the parameters' choices -> hal's enums ------------------------------- */
/* Explicit tables indexed by the generated enums of params_hal.def, so a
 * choice added or moved there cannot silently mean another action. */
static const enum hal_action action_of[] = {
	[BUTTON1_ACTION_NONE] = HAL_NONE,	    [BUTTON1_ACTION_PRESET] = HAL_PRESET,
	[BUTTON1_ACTION_SCREENSHOT] = HAL_SCREENSHOT, [BUTTON1_ACTION_PAUSE] = HAL_PAUSE,
	[BUTTON1_ACTION_RESET] = HAL_RESET,	    [BUTTON1_ACTION_QUIT] = HAL_QUIT,
	[BUTTON1_ACTION_NEXT] = HAL_NEXT,	    [BUTTON1_ACTION_PREV] = HAL_PREV,
};
_Static_assert(ARRAY_SIZE(action_of) == BUTTON1_ACTION_COUNT, "every button action choice maps to a hal action");
/* every button has the same choices; the encoders' switches the first six
 * (compared as int: they are distinct enum types) */
#define SAME_ACTION(x)                                                                                            \
	_Static_assert((int)BUTTON2_ACTION_##x == (int)BUTTON1_ACTION_##x &&                                      \
			       (int)BUTTON3_ACTION_##x == (int)BUTTON1_ACTION_##x &&                              \
			       (int)BUTTON4_ACTION_##x == (int)BUTTON1_ACTION_##x,                                \
		       "button actions differ: " #x)
#define SAME_SW_ACTION(x)                                                                                         \
	_Static_assert((int)ENC1_SW_ACTION_##x == (int)BUTTON1_ACTION_##x &&                                      \
			       (int)ENC2_SW_ACTION_##x == (int)BUTTON1_ACTION_##x,                                \
		       "switch actions differ: " #x)
SAME_ACTION(NONE); SAME_ACTION(PRESET); SAME_ACTION(SCREENSHOT); SAME_ACTION(PAUSE);
SAME_ACTION(RESET); SAME_ACTION(QUIT); SAME_ACTION(NEXT); SAME_ACTION(PREV);
SAME_SW_ACTION(NONE); SAME_SW_ACTION(PRESET); SAME_SW_ACTION(SCREENSHOT); SAME_SW_ACTION(PAUSE);
SAME_SW_ACTION(RESET); SAME_SW_ACTION(QUIT);
_Static_assert((int)ENC1_SW_ACTION_COUNT <= (int)BUTTON1_ACTION_COUNT &&
		       (int)ENC2_SW_ACTION_COUNT == (int)ENC1_SW_ACTION_COUNT,
	       "the switches' actions are a prefix of the buttons'");

static const enum hal_bias bias_of[] = {
	[BUTTON_BIAS_AS_IS] = HAL_BIAS_AS_IS, [BUTTON_BIAS_DISABLE] = HAL_BIAS_DISABLE,
	[BUTTON_BIAS_PULL_UP] = HAL_BIAS_PULL_UP, [BUTTON_BIAS_PULL_DOWN] = HAL_BIAS_PULL_DOWN,
};
_Static_assert(ARRAY_SIZE(bias_of) == BUTTON_BIAS_COUNT, "every bias choice maps");
#define SAME_BIAS(x)                                                                                              \
	_Static_assert((int)ENC1_BIAS_##x == (int)BUTTON_BIAS_##x && (int)ENC2_BIAS_##x == (int)BUTTON_BIAS_##x,  \
		       "biases differ: " #x)
SAME_BIAS(AS_IS); SAME_BIAS(DISABLE); SAME_BIAS(PULL_UP); SAME_BIAS(PULL_DOWN);

static const enum hal_keys_mode keys_of[] = {
	[KEYBOARD_AUTO] = HAL_KEYS_AUTO, [KEYBOARD_OFF] = HAL_KEYS_OFF,
	[KEYBOARD_TTY] = HAL_KEYS_TTY, [KEYBOARD_EVDEV] = HAL_KEYS_EVDEV,
};
_Static_assert(ARRAY_SIZE(keys_of) == KEYBOARD_COUNT, "every keyboard choice maps");

static const int format_of[] = {
	[V4L2_FORMAT_AUTO] = -1,	  [V4L2_FORMAT_YUYV] = CF_YUYV, [V4L2_FORMAT_UYVY] = CF_UYVY,
	[V4L2_FORMAT_NV12] = CF_NV12,	  [V4L2_FORMAT_NV21] = CF_NV21, [V4L2_FORMAT_YU12] = CF_YU12,
	[V4L2_FORMAT_RGB24] = CF_RGB24, [V4L2_FORMAT_BGR24] = CF_BGR24,
};
_Static_assert(ARRAY_SIZE(format_of) == V4L2_FORMAT_COUNT, "every V4L2 format choice maps");
static const enum conv_matrix matrix_of[] = { [V4L2_MATRIX_BT601] = CM_BT601, [V4L2_MATRIX_BT709] = CM_BT709 };
_Static_assert(ARRAY_SIZE(matrix_of) == V4L2_MATRIX_COUNT, "every matrix choice maps");
static const enum hal_v4l2_io io_of[] = {
	[V4L2_IO_AUTO] = HAL_V4L2_IO_AUTO, [V4L2_IO_WRITE] = HAL_V4L2_IO_WRITE, [V4L2_IO_MMAP] = HAL_V4L2_IO_MMAP,
};
_Static_assert(ARRAY_SIZE(io_of) == V4L2_IO_COUNT, "every V4L2 I/O choice maps");

static int choice(int v, size_t n)
{
	return v >= 0 && (size_t)v < n ? v : 0;
}

/* ---- hal's seams: messages and the conversion's program ----------------- */
static void hal_to_log(void *user, enum hal_level level, const char *msg)
{
	static const enum log_level lv[] = {
		[HAL_ERROR] = LOG_ERROR, [HAL_WARN] = LOG_WARN, [HAL_INFO] = LOG_INFO, [HAL_DEBUG] = LOG_DEBUG,
	};
	(void)user;
	log_msg(lv[choice((int)level, ARRAY_SIZE(lv))], "%s", msg);
}

struct hal_log controls_hal_log(void)
{
	return (struct hal_log){ .fn = hal_to_log };
}

static GLuint compile_hal_program(void *user, const char *file, const char *defines, char *err, size_t errlen)
{
	(void)user;
	return gpu_compute_program(file, defines, err, errlen);
}

const struct hal_gpu *controls_hal_gpu(void)
{
	static const struct hal_gpu gpu = {
		.compile = compile_hal_program,
		.tex_frame = TEX_FRAME,
		.img_out = IMG_CONVERT_OUT,
		.log = { .fn = hal_to_log },
	};
	return &gpu;
}

/* ---- hal's configuration ------------------------------------------------------ */
/* The parameter named fmt with %d = i; NULL (and err) when the table has none. */
static const struct param_info *key(const char *fmt, int i, char *err, size_t errlen)
{
	char name[64];
	snprintf(name, sizeof(name), fmt, i);
	const struct param_info *pi = params_find(name);
	if (!pi)
		snprintf(err, errlen, "no parameter '%s' for the controls (params_hal.def)", name);
	return pi;
}

static int number(const struct params *p, const char *fmt, int i, double *v, char *err, size_t errlen)
{
	const struct param_info *pi = key(fmt, i, err, errlen);
	if (!pi)
		return -1;
	*v = params_get_number(p, pi);
	return 0;
}

static int text(const struct params *p, const char *fmt, int i, const char **s, char *err, size_t errlen)
{
	const struct param_info *pi = key(fmt, i, err, errlen);
	if (!pi || pi->type != PT_STRING) {
		if (pi)
			snprintf(err, errlen, "parameter '%s' is not text", pi->name);
		return -1;
	}
	*s = (const char *)p + pi->offset;
	return 0;
}

/* An enum key read by its index into a table of ref's choices: its choices
 * must be ref's (or the first of them), checked here for keys the static
 * assertions above do not name (another encoder). */
static int same_choices(const struct params *p, const char *fmt, int i, const char *ref, int *v, char *err,
			size_t errlen)
{
	const struct param_info *pi = key(fmt, i, err, errlen), *r = params_find(ref);
	if (!pi)
		return -1;
	size_t n = pi->choices ? strlen(pi->choices) : 0;
	if (pi->type != PT_ENUM || !r || !r->choices || strncmp(pi->choices, r->choices, n) ||
	    (r->choices[n] && r->choices[n] != '|')) {
		snprintf(err, errlen, "parameter '%s': its choices are not those of '%s'", pi->name, ref);
		return -1;
	}
	*v = (int)params_get_number(p, pi);
	return 0;
}

static int encoder_config(const struct params *p, int e, struct hal_encoder_config *ec, char *err, size_t errlen)
{
	double a, b, sw, al, spd;
	int bias, action, n = e + 1;
	if (text(p, "enc%d_chip", n, &ec->chip, err, errlen) < 0 || number(p, "enc%d_a", n, &a, err, errlen) < 0 ||
	    number(p, "enc%d_b", n, &b, err, errlen) < 0 || number(p, "enc%d_sw", n, &sw, err, errlen) < 0 ||
	    number(p, "enc%d_active_low", n, &al, err, errlen) < 0 ||
	    same_choices(p, "enc%d_bias", n, "button_bias", &bias, err, errlen) < 0 ||
	    number(p, "enc%d_steps_per_detent", n, &spd, err, errlen) < 0 ||
	    same_choices(p, "enc%d_sw_action", n, "button1_action", &action, err, errlen) < 0)
		return -1;
	ec->a = (int)a;
	ec->b = (int)b;
	ec->sw = (int)sw;
	ec->active_low = al != 0;
	ec->bias = bias_of[choice(bias, ARRAY_SIZE(bias_of))];
	ec->steps_per_detent = (int)spd;
	ec->turn = e == 0 ? HAL_TURN_SELECT : HAL_TURN_CHANGE;
	ec->sw_action = action_of[choice(action, ARRAY_SIZE(action_of))];
	return 0;
}

int controls_gpio_config(const struct params *p, struct hal_gpio_config *cfg, char *err, size_t errlen)
{
	memset(cfg, 0, sizeof(*cfg));
	cfg->chip = p->gpio_chip;
	cfg->retry_s = p->gpio_retry;
	cfg->enc_debounce_ms = p->enc_debounce_ms;
	cfg->enc_accel_ms = p->enc_accel_ms;
	cfg->enc_accel_max = p->enc_accel_max;
	cfg->button_chip = p->button_chip;
	cfg->button_active_low = p->button_active_low;
	cfg->button_bias = bias_of[choice(p->button_bias, ARRAY_SIZE(bias_of))];
	cfg->button_debounce_ms = p->button_debounce_ms;
	cfg->log = controls_hal_log();
	for (int e = 0; e < HAL_ENCODERS; e++)
		if (encoder_config(p, e, &cfg->enc[e], err, errlen) < 0)
			return -1;
	for (int b = 0; b < HAL_BUTTONS; b++) {
		double line;
		int action;
		if (number(p, "button%d_line", b + 1, &line, err, errlen) < 0 ||
		    same_choices(p, "button%d_action", b + 1, "button1_action", &action, err, errlen) < 0)
			return -1;
		cfg->button[b].line = (int)line;
		cfg->button[b].action = action_of[choice(action, ARRAY_SIZE(action_of))];
	}
	return 0;
}

void controls_keys_config(const struct params *p, struct hal_keys_config *cfg)
{
	*cfg = (struct hal_keys_config){ .mode = keys_of[choice(p->keyboard, ARRAY_SIZE(keys_of))],
					 .evdev = p->keyboard_evdev,
					 .log = controls_hal_log() };
}

void controls_v4l2_config(const struct params *p, int width, int height, struct hal_v4l2_config *cfg)
{
	*cfg = (struct hal_v4l2_config){ .device = p->v4l2,
					 .format = format_of[choice(p->v4l2_format, ARRAY_SIZE(format_of))],
					 .matrix = matrix_of[choice(p->v4l2_matrix, ARRAY_SIZE(matrix_of))],
					 .io = io_of[choice(p->v4l2_io, ARRAY_SIZE(io_of))],
					 .fps = p->v4l2_fps,
					 .width = width,
					 .height = height,
					 .gpu = *controls_hal_gpu(),
					 .log = controls_hal_log() };
}

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
	struct osd *osd;
	struct knobs knobs;
	struct params base;    /* the start-up values (reset, preset cycling) */
	int preset;            /* index of the last preset applied, -1 none */
	bool paused, t_init;
	float t_raw, t_offset;
	bool shot;
	int shot_n;
	FILE *knob_log;
	char osd_title[OSD_COLS + 1], osd_value[OSD_COLS + 1];
	float osd_bar;
	uint64_t osd_until, osd_fade;
	float fly[HAL_FLY_AXES]; /* manual camera: held input */
	uint64_t fly_until;      /* ... until this time (ns) */
};

/* Screenshots: "name.png", at most one %d (or %0Nd) for a running number. */
static int check_screenshot(const char *name, char *err, size_t errlen)
{
	char buf[PATH_MAX];
	size_t sl = strlen(name);
	if (cli_numbered_name(name, 0, buf, sizeof(buf)) == -1 || sl < 5 || strcmp(name + sl - 4, ".png")) {
		snprintf(err, errlen, "screenshot: '%s' must end in .png with at most one %%d (or %%0Nd)", name);
		return -1;
	}
	return 0;
}

/* The GPIO controls and the keys; err only for bad configuration. */
static int open_inputs(struct controls *c, const struct params *p, char *err, size_t errlen)
{
	struct hal_gpio_config gc;
	if (controls_gpio_config(p, &gc, err, errlen) < 0)
		return -1;
	c->gpio = hal_gpio_open(&gc, err, errlen);
	if (!c->gpio && err[0])
		return -1;
	struct hal_keys_config kc;
	controls_keys_config(p, &kc);
	c->keys = hal_keys_open(&kc, err, errlen);
	return !c->keys && err[0] ? -1 : 0;
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
	if (check_screenshot(p->screenshot, err, errlen) < 0 || knobs_init(&c->knobs, p->knob_params, err, errlen) < 0 ||
	    open_inputs(c, p, err, errlen) < 0)
		goto fail;
	if (p->knob_log[0]) {
		c->knob_log = fopen(p->knob_log, "a");
		if (!c->knob_log) {
			snprintf(err, errlen, "knob_log: cannot open '%s': %s", p->knob_log, strerror(errno));
			goto fail;
		}
	}
	if (p->osd && (c->gpio || c->keys || p->shader_dir[0])) { /* knobs; live shader errors */
		c->osd = osd_create(err, errlen);
		if (!c->osd)
			goto fail;
	}
	if (c->gpio || c->keys)
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
	log_info("knob: preset %s", presets[c->preset].name);
	knob_log(c, "preset %s", presets[c->preset].name);
	show(c, p, "preset", presets[c->preset].name, -1);
}

void controls_flight(struct controls *c, float move[3], float turn[2])
{
	bool on = c && hal_now_ns() < c->fly_until;
	for (int i = 0; i < 3; i++)
		move[i] = on ? c->fly[HAL_FLY_FORWARD + i] : 0.0f;
	for (int i = 0; i < 2; i++)
		turn[i] = on ? c->fly[HAL_FLY_YAW + i] : 0.0f;
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
	if (in.actions[HAL_SCREENSHOT])
		c->shot = true;
	return in.actions[HAL_QUIT] != 0;
}

float controls_time(struct controls *c, float t)
{
	if (!c)
		return t;
	if (!c->t_init) {
		c->t_init = true;
		c->t_raw = t;
	}
	if (c->paused)
		c->t_offset += t - c->t_raw;
	c->t_raw = t;
	return t - c->t_offset;
}

static int screenshot(struct controls *c, struct renderer *r, const struct params *p, char *err, size_t errlen)
{
	struct image img = { 0 };
	char name[PATH_MAX], e[512];
	if (cli_numbered_name(p->screenshot, c->shot_n++, name, sizeof(name)) < 0) {
		log_warn("screenshot: no room for number %d in '%s'", c->shot_n - 1, p->screenshot);
		return 0;
	}
	if (renderer_read(r, &img) < 0) {
		snprintf(err, errlen, "screenshot: reading the frame back failed");
		return -1;
	}
	if (image_write_png(&img, name, e, sizeof(e)) < 0)
		log_warn("screenshot: %s", e);
	else
		log_info("screenshot: %s", name);
	image_free(&img);
	return 0;
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
	if (c->shot) {
		c->shot = false;
		return screenshot(c, r, p, err, errlen);
	}
	return 0;
}
