/* isoterra — where finished frames go: sinks behind one small interface.
 *
 *   PNG            one file, written for the run's last frame   (sink_file.c)
 *   PNG sequence   one file per frame: %d / %0Nd in the name    (sink_file.c)
 *   Y4M            a YUV4MPEG2 stream to a file or stdout       (sink_file.c)
 *
 * Files are written to temp files beside their targets and renamed onto
 * them only at the end of a run that went well, all together (stdout stays
 * a stream).
 *   memory         the last frame into an image (render_to_image)  (sink_file.c)
 *   V4L2           hal's video output (hal/v4l2_out.h)          (sink_v4l2.c)
 *   display        blit, present, window events, fps reports    (display.c)
 *   mesh export    the scene's mesh as PLY at the end of the run (sink_mesh.c)
 *
 * The frame loop hands every finished frame to each sink in turn, then
 * finishes them (GL context still current), and destroys them once the
 * platform is closed. */
#ifndef ISOTERRA_SINK_H
#define ISOTERRA_SINK_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"
#include "core.h"

struct renderer;
struct platform;
struct scene;

/* A finished frame, drawn into r's target. */
struct sink_frame {
	struct renderer *r; /* a display's resize re-creates the renderer: r, w, h follow */
	int w, h;
	int index;          /* 0, 1, ... */
	int number;         /* what a %d in --out takes: index, or with the
	                     * realtime clock the frame's tick within its period
	                     * (the same instant has the same number on every
	                     * board of a wall) */
	int count;          /* frames the run renders, 0 = until stopped */
	bool last;          /* the run's last frame */
	char status[192];   /* the scene's state for the frame rate reports (or "") */
	double update_ms, draw_ms; /* the scene's split, when the loop times it (results) */
	bool screenshot;    /* the controls asked for a screenshot of this frame */
	/* power (app/power.h): the battery (percent -1: none), the low-power
	 * profile, the frame cap in force (0: none) */
	int battery_percent;
	char battery_status[16];
	bool low_power;
	double cap_fps;
	/* out: what the sinks spent waiting for the display, not working
	 * (a vertical blank, a page flip), ms: the frame's work is its time
	 * less this (the governor, app/run.c) */
	double wait_ms;
};

/* The end of the run. */
struct sink_end {
	bool ok;             /* every frame went well (else the sinks only close) */
	int frames;          /* frames finished */
	struct scene *scene; /* what the mesh export reads */
	struct renderer *r;
};

struct sink;
struct sink_ops {
	/* 0 go on, 1 stop (window closed, SIGINT/SIGTERM: reported), -1 error
	 * with err ("" when already reported). */
	int (*frame)(struct sink *s, struct sink_frame *fr, char *err, size_t errlen);
	/* After the last frame (or an error), the GL context still current:
	 * close files, drain read-backs, export.  Files are left staged (temp
	 * files beside their targets).  0, or -1 with err. */
	int (*finish)(struct sink *s, const struct sink_end *end, char *err, size_t errlen);
	/* Once every sink finished well: the staged files renamed onto their
	 * targets (NULL: nothing staged).  0, or -1 with err. */
	int (*commit)(struct sink *s, char *err, size_t errlen);
	/* After the platform is closed: final reports, free; staged files not
	 * committed are removed. */
	void (*destroy)(struct sink *s);
};

struct sink {
	const struct sink_ops *ops;
	/* What the run's summary names as where the frames went (the --out
	 * name once it holds them), NULL: nothing. */
	const char *dest;
};

/* ---- the sinks ----------------------------------------------------------- */
/* PNG, PNG sequence or Y4M, as p->out names it (cli_parse_out): frames of
 * w x h at p->fps, a progress bar on a terminal.  NULL with err. */
struct sink *sink_file_open(const struct params *p, int w, int h, char *err, size_t errlen);
/* The last frame read back into *img (the caller frees it). */
struct sink *sink_memory_open(struct image *img, char *err, size_t errlen);
/* hal's V4L2 output (p->v4l2).  NULL with err[0] == 0 when none is
 * configured, NULL with err for bad configuration. */
struct sink *sink_v4l2_open(const struct params *p, int w, int h, char *err, size_t errlen);
/* Screenshots: the frames asked for (sink_frame.screenshot) as PNG files
 * numbered from p->screenshot ("name.png", at most one %d or %0Nd).  NULL
 * with err for a name that cannot number them. */
struct sink *sink_shot_open(const struct params *p, char *err, size_t errlen);
/* The scene's mesh as binary PLY to path at the end of a run that went well. */
struct sink *sink_mesh_open(const char *path, char *err, size_t errlen);
/* A display platform (gbm, wayland, x11): each frame blitted to the window
 * and presented, window events handled, SIGINT/SIGTERM end the run (the
 * platform restores the display), the frame rate reported on SIGUSR1 and
 * every p->fps_report seconds, counted from this call: open it with the
 * platform (display.c). */
struct sink *sink_display_open(struct platform *plat, const struct params *p, char *err, size_t errlen);
/* --outputs (gbm): the connectors, and how the platform lays them out
 * (platform.h): with a wall, side by side along the row with the wall's
 * horizontal bezel between them, else one picture each (mirror); into
 * po before platform_open.  sink_display_open then checks that the
 * outputs' tiles fit the wall. */
struct platform_options;
void sink_display_outputs(const struct params *p, struct platform_options *po);
/* The frame loop's tiles (run.h: tile_w, tile_h, across) for the
 * platform's outputs: a row of n outputs of a wall is n tiles of the
 * outputs' size; else one tile (across 1, tile size 0: the frame's). */
void sink_display_tiles(const struct platform *plat, int *tile_w, int *tile_h, int *across);

/* The run's results as JSON to p->results ("-": stdout; "": none) at the
 * end of a run that went well, and, headless, the frame rate every
 * p->fps_report seconds.  NULL with err. */
struct sink *sink_results_open(const struct params *p, bool headless, char *err, size_t errlen);

/* ---- every sink a run asks for ------------------------------------------------ */
#define SINK_MAX 8
struct sink_set {
	struct sink *s[SINK_MAX];
	int n;
};
/* The sinks p asks for, in frame order: V4L2, mesh export, the --out file
 * (frames of w x h), screenshots.  A display sink, opened with the platform, is added
 * after them: it may re-create the renderer.  0, or the exit code with err:
 * 2 bad configuration, 1 a file or device that cannot be opened. */
int sinks_open(struct sink_set *set, const struct params *p, int w, int h, char *err, size_t errlen);
/* Adds one (set full or s NULL: -1). */
int sinks_add(struct sink_set *set, struct sink *s);
/* One frame to every sink: 0 go on, 1 stop, -1 error with err. */
int sinks_frame(struct sink_set *set, struct sink_frame *fr, char *err, size_t errlen);
/* Finishes every sink (all of them, even after an error), then, when the
 * run went well (end->ok) and every sink finished well, commits them all:
 * a run that fails or stops early leaves every target as it was.  0, or -1
 * with the first error in err. */
int sinks_finish(struct sink_set *set, const struct sink_end *end, char *err, size_t errlen);
/* The destination the summary names: the first sink's that has one. */
const char *sinks_dest(const struct sink_set *set);
void sinks_destroy(struct sink_set *set);

#endif
