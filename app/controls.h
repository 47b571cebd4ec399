/* isoterra — the controls: hal's knobs, buttons, keys and gamepad (hal/) mapped to
 * the parameters, and what they ask for besides: presets, reset, pause,
 * screenshots, the on-screen display of what changed (drawn by
 * render/osd.c) and the knob log.  hal's configuration from the
 * parameters: hal_config.h.
 *
 * The frame loop calls, per frame:
 *     if (controls_poll(c, &p)) ...          // inputs -> parameters; 1 = quit
 *     paused = controls_paused(c);           // the loop's clocks stop
 *     ... draw ...
 *     controls_frame(c, renderer, &p, ...);  // OSD
 *     sink_frame.screenshot = controls_take_screenshot(c);
 * A NULL struct controls * is valid everywhere and does nothing. */
#ifndef ISOTERRA_CONTROLS_H
#define ISOTERRA_CONTROLS_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"
#include "hal.h"

struct renderer;

/* ---- knob mapping ---------------------------------------------------------- */
/* The parameters a knob cycles through (knob_params; "" = every P_LIVE
 * one) and the one selected. */
struct knobs {
	const struct param_info *list[128];
	int count, sel;
};
int knobs_init(struct knobs *k, const char *csv, char *err, size_t errlen);
/* One detent: integers, enums and booleans by 1; floats by a tenth of the
 * decade of their default, at most a twentieth of the range. */
double knob_step(const struct param_info *pi);
/* Applies delta detents to the selected parameter (clamped, snapped to the
 * step); returns true when the value changed. */
bool knob_change(const struct knobs *k, struct params *p, int delta);

/* ---- the controls ------------------------------------------------------------ */
struct controls;
/* Opens the GPIO controls, keys and gamepad the parameters configure (nothing
 * configured: a cheap object that does nothing).  Needs a current GL
 * context when the OSD is on.  NULL with err only for bad configuration
 * (exit 2). */
struct controls *controls_create(const struct params *p, char *err, size_t errlen);
void controls_destroy(struct controls *c);
/* Reads the inputs without blocking and applies them to *p.  1 when the
 * user asked to quit (key q, a quit button), else 0. */
int controls_poll(struct controls *c, struct params *p);
/* Manual camera: the flight keys pressed lately, as held inputs, plus a
 * gamepad's sticks (-1..1 each): forward, right, up; yaw right, pitch up.
 * A terminal repeats a held key ~30 times a second, so a press holds for
 * 0.15 s; the sticks are their levels at the last poll.  Zero when none.
 * A gamepad's autopilot button (controls_poll) toggles p->camera between
 * auto and manual. */
void controls_flight(struct controls *c, float move[3], float turn[2]);
/* Paused by a button or key (the frame loop's clocks stop). */
bool controls_paused(const struct controls *c);
/* How many presets the preset button has applied (0 for NULL): the loop
 * starts the world's flight again from the new preset's spawn. */
unsigned controls_presets_applied(const struct controls *c);

/* An animation clock that stops while paused: pause_clock_time(pc, t,
 * paused) is t while running, frozen while paused, the time paused taken
 * out for good.  The frame loop keeps one per time base; zero-initialized. */
struct pause_clock {
	bool init;
	float raw, offset;
};
float pause_clock_time(struct pause_clock *pc, float t, bool paused);
/* A message on the OSD for osd_seconds (a broken shader edit).  NULL c or
 * no OSD: nothing. */
void controls_notice(struct controls *c, const struct params *p, const char *title, const char *text);
/* A screenshot asked for since the last call (the screenshot sink takes
 * it: sink_frame.screenshot). */
bool controls_take_screenshot(struct controls *c);
/* After the frame is drawn into r's target: the OSD over it.  0, or -1
 * with err. */
int controls_frame(struct controls *c, struct renderer *r, const struct params *p, char *err, size_t errlen);

#endif
