/* isoterra — the frame loop and the runs built on it. */
#ifndef ISOTERRA_RUN_H
#define ISOTERRA_RUN_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"
#include "power.h"
#include "core.h"

struct scene;
struct controls;
struct sink_set;
struct renderer;
struct notify;
struct kiosk;

/* One frame loop for every scene and every destination: per frame the
 * controls are polled, the scene draws, the controls draw over it (OSD,
 * screenshot), and the frame goes to each sink. */
struct frame_loop {
	struct params *p;        /* the run's parameters: the controls change them */
	struct scene *scene;
	struct controls *ctl;    /* NULL: none */
	struct sink_set *sinks;
	struct renderer *r;      /* the frame's target; a display's resize replaces it */
	struct shader_watch *shaders; /* live shader editing; NULL: none */
	int w, h;
	int tile_w, tile_h;      /* a wall's tile when the frame spans several
	                          * (outputs of one board, `across` of them along
	                          * the row); 0: the frame is one tile, w x h */
	int across;              /* 0 or 1: one tile */
	bool live;               /* a display: wall-clock time, and its sink sees SIGINT/SIGTERM */
	bool watch_signals;      /* headless: SIGINT/SIGTERM end the loop (signals.h) */
	double refresh_hz;       /* the display's, when known (else 0) */
	bool timing;             /* the scene waits for the GPU and times update and draw (results) */
	struct notify *notify;   /* NULL: none; told of every finished frame (notify.h) */
	struct kiosk *kiosk;     /* NULL: none; SIGHUP reload, the playlist and its crossfade (kiosk.h) */
	struct power *power;     /* NULL: none; the battery and the low-power profile (power.h) */
	struct osd *battery_osd; /* made at the first frame with a battery (freed by the loop) */
	int frames;              /* out: frames finished */
};
/* Frames until p->count (0: until a sink stops), a quit from the controls
 * (that frame is the last) or, when watched, SIGINT/SIGTERM.  0, or -1
 * with err ("" when the cause is already reported). */
int frame_loop_run(struct frame_loop *lp, char *err, size_t errlen);

/* Renders p->count (>= 1) frames of p->scene with the current context
 * through the frame loop and returns the last one (tests, tools).  0 or -1
 * with err. */
int render_to_image(const struct params *p, struct image *img, char *err, size_t errlen);

/* The program's run: p->count frames (0 on a display: until closed) to
 * p->out, the display, the V4L2 device; the mesh to p->export_mesh.
 * Returns the process exit code. */
int run_program(const struct params *p);
/* The same, keeping the command line (not copied) for SIGHUP to parse
 * again (kiosk.h). */
int run_program_args(const struct params *p, int argc, char **argv);

#endif
