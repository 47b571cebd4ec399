/* isoterra — the hardware layer's door: GPIO knobs and buttons (libgpiod
 * 1.6 or 2.x), development keys (terminal / evdev), a gamepad (evdev) and,
 * in v4l2_out.h, V4L2 video output of rendered frames.
 *
 * hal is a lower layer: it includes nothing of the application.  It takes
 * its configuration as the plain structs below (the application fills them
 * from its parameters), reports what happens through a struct hal_log and
 * hands the inputs back as counted events (struct hal_input): which
 * parameter they change, presets, the OSD, screenshots or the knob log are
 * the application's business.
 *
 * Nothing here blocks the caller: event fds are polled with a zero timeout.
 * A missing or vanished gpiochip / input device is reported once and
 * retried. */
#ifndef ISOTERRA_HAL_H
#define ISOTERRA_HAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define HAL_ENCODERS 2    /* rotary encoders: A, B and a push switch each */
#define HAL_BUTTONS 4     /* plain push buttons */
#define HAL_NO_LINE (-1)  /* a line that is not connected */
#define HAL_NAME_MAX 256  /* chip names and device paths, NUL included */

/* ---- reporting ------------------------------------------------------------ */
enum hal_level { HAL_ERROR, HAL_WARN, HAL_INFO, HAL_DEBUG };

/* Where hal's messages go: one line each, without a trailing newline.  A
 * NULL fn drops them. */
struct hal_log {
	void (*fn)(void *user, enum hal_level level, const char *msg);
	void *user;
};
void hal_logf(const struct hal_log *log, enum hal_level level, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

uint64_t hal_now_ns(void); /* CLOCK_MONOTONIC */

/* ---- input events ------------------------------------------------------- */
/* What a button, an encoder's push switch or a key asks for. */
enum hal_action {
	HAL_NONE, HAL_PRESET, HAL_SCREENSHOT, HAL_PAUSE, HAL_RESET, HAL_QUIT, HAL_NEXT, HAL_PREV,
	HAL_AUTOPILOT, /* the camera: autopilot <-> manual flight (a gamepad's button) */
	HAL_ACTION_COUNT
};
/* What turning an encoder does. */
enum hal_turn { HAL_TURN_SELECT, HAL_TURN_CHANGE };
/* Flight keys (a manually steered camera): one axis each. */
enum hal_fly { HAL_FLY_FORWARD, HAL_FLY_RIGHT, HAL_FLY_UP, HAL_FLY_YAW, HAL_FLY_PITCH, HAL_FLY_AXES };

/* What the inputs asked for since the last poll (counts; add up). */
struct hal_input {
	int select;                    /* detents: choose the parameter */
	int change;                    /* detents: change its value */
	int actions[HAL_ACTION_COUNT]; /* presses */
	int fly[HAL_FLY_AXES];         /* key presses, signed (forward minus back, ...) */
	float stick[HAL_FLY_AXES];     /* a gamepad's sticks and triggers now, -1..1 after the dead
	                                  zone and the curve (levels, not counts; up = climb - descend) */
};

/* ---- GPIO: encoders and buttons (gpio.c, rotary.c) ------------------------ */
enum hal_bias { HAL_BIAS_AS_IS, HAL_BIAS_DISABLE, HAL_BIAS_PULL_UP, HAL_BIAS_PULL_DOWN };

struct hal_encoder_config {
	const char *chip;          /* "" or NULL: the default chip */
	int a, b, sw;              /* line offsets; HAL_NO_LINE = not connected */
	bool active_low;
	enum hal_bias bias;
	int steps_per_detent;      /* quarter steps per detent: 1, 2 or 4 */
	enum hal_turn turn;        /* a detent selects or changes */
	enum hal_action sw_action; /* the push switch */
};

struct hal_button_config {
	int line;                  /* HAL_NO_LINE = not connected */
	enum hal_action action;
};

/* Chips are named as libgpiod 1.6 looks them up (gpio.c does it on either
 * API): number, label, path or name.  Strings are copied by hal_gpio_open. */
struct hal_gpio_config {
	const char *chip;          /* the default chip of every control */
	double retry_s;            /* a missing or vanished chip: retried this often */
	struct hal_encoder_config enc[HAL_ENCODERS];
	double enc_debounce_ms;    /* an edge counts once its line is stable this long */
	double enc_accel_ms;       /* detents closer than this accelerate (0 = off) */
	int enc_accel_max;
	const char *button_chip;   /* "" or NULL: the default chip */
	bool button_active_low;
	enum hal_bias button_bias;
	double button_debounce_ms;
	struct hal_button_config button[HAL_BUTTONS];
	struct hal_log log;
};

struct hal_gpio;
/* NULL with err[0] == 0 when no line is configured; NULL with err on bad
 * configuration.  Missing chips are reported and retried, not errors. */
struct hal_gpio *hal_gpio_open(const struct hal_gpio_config *cfg, char *err, size_t errlen);
/* Adds the events since the last poll to *in (never blocks). */
void hal_gpio_poll(struct hal_gpio *g, uint64_t now_ns, struct hal_input *in);
void hal_gpio_close(struct hal_gpio *g);

/* ---- development keys (keys.c) --------------------------------------------- */
/*   left/right or [ ]   select          up/down or - +   change
 *   p pause   s screenshot   n preset   r reset   q / Esc quit
 *   flight: i/k forward/back, j/l turn, u/o up/down, y/h pitch */
enum hal_keys_mode { HAL_KEYS_AUTO, HAL_KEYS_OFF, HAL_KEYS_TTY, HAL_KEYS_EVDEV };

struct hal_keys_config {
	enum hal_keys_mode mode;   /* auto: the terminal when stdin is one */
	const char *evdev;         /* HAL_KEYS_EVDEV: /dev/input/eventN (copied) */
	struct hal_log log;
};

struct hal_keys;
/* NULL with err[0] == 0 when keys are off (or auto without a terminal);
 * NULL with err on bad configuration.  A terminal is put in raw mode until
 * hal_keys_close, which the owner must call on every path. */
struct hal_keys *hal_keys_open(const struct hal_keys_config *cfg, char *err, size_t errlen);
void hal_keys_poll(struct hal_keys *k, struct hal_input *in);
void hal_keys_close(struct hal_keys *k);
/* Decodes raw terminal bytes (tests): arrows, [ ] - + p s n r q, flight keys.
 * *esc_state carries an escape sequence split across reads (start at 0). */
void hal_keys_feed_tty(const unsigned char *buf, size_t n, int *esc_state, struct hal_input *in);
/* Decodes raw evdev bytes (struct input_event records: key presses and
 * auto-repeats): the number of events, or -1 (nothing decoded) when n is not
 * a whole number of them. */
int hal_keys_feed_evdev(const void *buf, size_t n, struct hal_input *in);

/* ---- gamepad / joystick (gamepad.c over stick.c) ------------------------------ */
/* Any evdev node with ABS_X and ABS_Y and a gamepad or joystick button
 * (BTN_SOUTH / BTN_GAMEPAD, BTN_TRIGGER / BTN_JOYSTICK, ...), found by its
 * capabilities, not its name, when it is plugged in (inotify on the
 * device folder; a rescan every retry_s without it).  Left stick: forward
 * and strafe; right stick: yaw and pitch; triggers: climb and descend;
 * D-pad: select (left/right) and change (up/down) as the two encoders do;
 * select resets, start toggles the autopilot (stick.h: the defaults, the
 * map's syntax). */
struct hal_gamepad_config {
	bool enabled;
	const char *device;        /* "" or NULL: any gamepad; else only this node (copied) */
	const char *dir;           /* "" or NULL: /dev/input (tests) */
	double retry_s;            /* without inotify: a rescan this often */
	float deadzone, trigger_deadzone, curve;
	double repeat_delay_ms, repeat_ms; /* a held D-pad repeats (repeat_ms 0: never) */
	const char *map;           /* "role=input,..." over the defaults (stick.h) */
	struct hal_log log;
};

struct hal_gamepad;
/* NULL with err[0] == 0 when disabled; NULL with err on bad configuration
 * (the map).  No gamepad yet is no error: one is picked up when it comes. */
struct hal_gamepad *hal_gamepad_open(const struct hal_gamepad_config *cfg, char *err, size_t errlen);
/* Adds the presses since the last poll to *in and the sticks' levels to
 * in->stick (never blocks).  A device that goes away is reported once;
 * another one (or the same back) is opened when it appears. */
void hal_gamepad_poll(struct hal_gamepad *g, uint64_t now_ns, struct hal_input *in);
/* The open device's node ("" when none). */
const char *hal_gamepad_device(const struct hal_gamepad *g);
void hal_gamepad_close(struct hal_gamepad *g);

#endif
