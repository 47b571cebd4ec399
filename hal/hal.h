/* isoterra — the hardware layer's door: GPIO knobs and buttons (libgpiod
 * 1.6), development keys (terminal / evdev), the on-screen display of what a
 * knob changes, and V4L2 video output of the rendered frames.
 *
 * The frame loop calls, per frame:
 *     if (hal_poll(hal, &p)) break;          // inputs -> parameters; 1 = quit
 *     t = hal_time(hal, t);                  // animation clock (pause)
 *     ... render ...
 *     hal_frame(hal, renderer, &p);          // OSD, screenshots, V4L2 out
 * Nothing here blocks the loop: event fds are polled with a zero timeout,
 * frames are read back through a ring of pixel-pack buffers with fences.
 * A missing or vanished gpiochip / video device is reported once and
 * retried; the renderer keeps going. */
#ifndef ISOTERRA_HAL_H
#define ISOTERRA_HAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "params.h"

struct renderer;

/* Actions (indices match the *_action enums of app/params_hal.def). */
enum hal_action {
	HAL_NONE, HAL_PRESET, HAL_SCREENSHOT, HAL_PAUSE, HAL_RESET, HAL_QUIT, HAL_NEXT, HAL_PREV, HAL_ACTION_COUNT
};

/* What the inputs asked for since the last poll. */
struct hal_input {
	int select;                    /* detents: choose the parameter */
	int change;                    /* detents: change its value */
	int actions[HAL_ACTION_COUNT]; /* counts */
	int fly[5];                    /* key presses: forward, right, up, yaw right, pitch up (manual camera) */
};

struct hal;
/* Opens what the parameters configure (nothing configured: a cheap no-op
 * object).  NULL with err only for bad configuration (exit 2). */
struct hal *hal_open(const struct params *p, int width, int height, char *err, size_t errlen);
void hal_close(struct hal *h);
/* Reads the inputs without blocking and applies them to *p.  1 when the
 * user asked to quit (key q, a quit button), else 0 (SIGINT/SIGTERM: run.c). */
int hal_poll(struct hal *h, struct params *p);
/* Manual camera (camera=manual): the flight keys pressed since the last
 * call, as held inputs (-1..1): i/k forward/back, j/l turn, u/o up/down,
 * y/h pitch.  A terminal repeats a held key ~30 times a second, so a press
 * holds for 0.15 s.  All zero when no key is pressed. */
void hal_flight(struct hal *h, float move[3], float turn[2]);
/* The animation clock: t while running, frozen while paused. */
float hal_time(struct hal *h, float t);
/* After the frame is drawn into the renderer's target: OSD, screenshot,
 * V4L2 output (paced to v4l2_fps).  0, or -1 on a GL error. */
int hal_frame(struct hal *h, struct renderer *r, const struct params *p);

/* ---- parts, for tests and the benchmark ------------------------------ */
uint64_t hal_now_ns(void); /* CLOCK_MONOTONIC */

struct hal_gpio;
/* NULL with err[0] == 0 when no line is configured; NULL with err on bad
 * configuration.  Missing chips are reported and retried, not errors. */
struct hal_gpio *hal_gpio_open(const struct params *p, char *err, size_t errlen);
void hal_gpio_poll(struct hal_gpio *g, uint64_t now_ns, struct hal_input *in);
void hal_gpio_close(struct hal_gpio *g);

struct hal_keys;
struct hal_keys *hal_keys_open(const struct params *p, char *err, size_t errlen);
void hal_keys_poll(struct hal_keys *k, struct hal_input *in);
void hal_keys_close(struct hal_keys *k);
/* Feeds raw terminal bytes (tests): arrows, [ ] - + p s n r q. */
void hal_keys_feed_tty(const unsigned char *buf, size_t n, int *esc_state, struct hal_input *in);

/* Knob mapping: the parameters a knob cycles through and the step of one
 * detent. */
struct knobs {
	const struct param_info *list[128];
	int count, sel;
};
int knobs_init(struct knobs *k, const char *csv, char *err, size_t errlen);
double knob_step(const struct param_info *pi);
/* Applies delta detents to the selected parameter (clamped, snapped to the
 * step); returns true when the value changed. */
bool knob_change(const struct knobs *k, struct params *p, int delta);

#endif
