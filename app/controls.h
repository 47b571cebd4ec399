/* isoterra — the controls: hal's knobs, buttons and keys (hal/) mapped to
 * the parameters, and what they ask for besides: presets, reset, pause,
 * screenshots, the on-screen display of what changed (drawn by
 * render/osd.c) and the knob log.  Also where hal's configuration comes
 * from: the hal_*_config structs filled from the parameter table, hal's
 * messages routed to the log, and the V4L2 conversion's program built by the
 * shader loader.
 *
 * The frame loop calls, per frame:
 *     if (controls_poll(c, &p)) ...          // inputs -> parameters; 1 = quit
 *     t = controls_time(c, t);               // animation clock (pause)
 *     ... draw ...
 *     controls_frame(c, renderer, &p, ...);  // OSD, screenshot
 * A NULL struct controls * is valid everywhere and does nothing. */
#ifndef ISOTERRA_CONTROLS_H
#define ISOTERRA_CONTROLS_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"
#include "hal.h"
#include "convert.h"
#include "v4l2_out.h"

struct renderer;

/* ---- hal's configuration from the parameters ----------------------------- */
/* Encoder e (0-based) reads the keys enc<e+1>_*, button b button<b+1>_*:
 * another encoder is HAL_ENCODERS plus its keys in params_hal.def.  Encoder
 * 1 selects the parameter, the others change it.  -1 with err when a key is
 * missing from the table. */
int controls_gpio_config(const struct params *p, struct hal_gpio_config *cfg, char *err, size_t errlen);
void controls_keys_config(const struct params *p, struct hal_keys_config *cfg);
/* The V4L2 output of frames of width x height. */
void controls_v4l2_config(const struct params *p, int width, int height, struct hal_v4l2_config *cfg);
/* hal's messages into the log, as the program's own ("isoterra: warning: ..."). */
struct hal_log controls_hal_log(void);
/* The V4L2 conversion's program (the shader loader) and units (abi.h). */
const struct hal_gpu *controls_hal_gpu(void);

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
/* Opens the GPIO controls and keys the parameters configure (nothing
 * configured: a cheap object that does nothing).  Needs a current GL
 * context when the OSD is on.  NULL with err only for bad configuration
 * (exit 2). */
struct controls *controls_create(const struct params *p, char *err, size_t errlen);
void controls_destroy(struct controls *c);
/* Reads the inputs without blocking and applies them to *p.  1 when the
 * user asked to quit (key q, a quit button), else 0. */
int controls_poll(struct controls *c, struct params *p);
/* Manual camera: the flight keys pressed lately, as held inputs (-1..1):
 * forward, right, up; yaw right, pitch up.  A terminal repeats a held key
 * ~30 times a second, so a press holds for 0.15 s.  Zero when none. */
void controls_flight(struct controls *c, float move[3], float turn[2]);
/* The animation clock: t while running, frozen while paused. */
float controls_time(struct controls *c, float t);
/* A message on the OSD for osd_seconds (a broken shader edit).  NULL c or
 * no OSD: nothing. */
void controls_notice(struct controls *c, const struct params *p, const char *title, const char *text);
/* After the frame is drawn into r's target: the OSD over it, a screenshot
 * when one was asked for (reported).  0, or -1 with err. */
int controls_frame(struct controls *c, struct renderer *r, const struct params *p, char *err, size_t errlen);

#endif
