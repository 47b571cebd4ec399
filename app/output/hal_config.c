/* isoterra — hal's configuration from the parameter table (hal_config.h):
 * the parameters' choices mapped to hal's enums, the GPIO encoders and
 * buttons, the keys, the gamepad, and hal's seams (its messages into the log, the V4L2
 * conversion's program through the shader loader). */
#include "hal_config.h"
#include "gpu.h"
#include "core.h"

#include <stdio.h>
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

/* ---- hal's seams: messages and the conversion's program ----------------- */
static void hal_to_log(void *user, enum hal_level level, const char *msg)
{
	static const enum log_level lv[] = {
		[HAL_ERROR] = LOG_ERROR, [HAL_WARN] = LOG_WARN, [HAL_INFO] = LOG_INFO, [HAL_DEBUG] = LOG_DEBUG,
	};
	(void)user;
	log_msg(lv[hal_choice((int)level, ARRAY_SIZE(lv))], "%s", msg);
}

struct hal_log hal_config_log(void)
{
	return (struct hal_log){ .fn = hal_to_log };
}

static GLuint compile_hal_program(void *user, const char *file, const char *defines, char *err, size_t errlen)
{
	(void)user;
	return gpu_compute_program(file, defines, err, errlen);
}

const struct hal_gpu *hal_config_gpu(void)
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
	ec->bias = bias_of[hal_choice(bias, ARRAY_SIZE(bias_of))];
	ec->steps_per_detent = (int)spd;
	ec->turn = e == 0 ? HAL_TURN_SELECT : HAL_TURN_CHANGE;
	ec->sw_action = action_of[hal_choice(action, ARRAY_SIZE(action_of))];
	return 0;
}

int hal_config_gpio(const struct params *p, struct hal_gpio_config *cfg, char *err, size_t errlen)
{
	memset(cfg, 0, sizeof(*cfg));
	cfg->chip = p->gpio_chip;
	cfg->retry_s = p->gpio_retry;
	cfg->enc_debounce_ms = p->enc_debounce_ms;
	cfg->enc_accel_ms = p->enc_accel_ms;
	cfg->enc_accel_max = p->enc_accel_max;
	cfg->button_chip = p->button_chip;
	cfg->button_active_low = p->button_active_low;
	cfg->button_bias = bias_of[hal_choice(p->button_bias, ARRAY_SIZE(bias_of))];
	cfg->button_debounce_ms = p->button_debounce_ms;
	cfg->log = hal_config_log();
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
		cfg->button[b].action = action_of[hal_choice(action, ARRAY_SIZE(action_of))];
	}
	return 0;
}

void hal_config_gamepad(const struct params *p, struct hal_gamepad_config *cfg)
{
	*cfg = (struct hal_gamepad_config){ .enabled = p->gamepad == GAMEPAD_AUTO,
					    .device = p->gamepad_device,
					    .retry_s = p->gpio_retry,
					    .deadzone = p->gamepad_deadzone,
					    .trigger_deadzone = p->gamepad_trigger_deadzone,
					    .curve = p->gamepad_curve,
					    .repeat_delay_ms = 400.0,
					    .repeat_ms = p->gamepad_repeat_ms,
					    .map = p->gamepad_map,
					    .log = hal_config_log() };
}

void hal_config_keys(const struct params *p, struct hal_keys_config *cfg)
{
	*cfg = (struct hal_keys_config){ .mode = keys_of[hal_choice(p->keyboard, ARRAY_SIZE(keys_of))],
					 .evdev = p->keyboard_evdev,
					 .log = hal_config_log() };
}
