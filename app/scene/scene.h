/* isoterra — what the frame loop draws: a scene behind one small interface.
 * The volume (one extracted box, orbit camera) and the streaming world
 * (blocks, levels of detail, autopilot or manual flight) implement it. */
#ifndef ISOTERRA_SCENE_H
#define ISOTERRA_SCENE_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"
#include "core.h"

struct renderer;

/* The frame to draw. */
struct scene_frame {
	int index;               /* 0, 1, ... */
	bool last;               /* the run's last frame (--count): what only
	                          * later frames would use may be let go */
	bool live;               /* on a display: wall-clock time, blocks stream
	                          * under their budget; else each frame is
	                          * complete and reproducible (time = index / fps) */
	float frame_time;        /* index / fps, the time paused taken out */
	double clock_time;       /* live: seconds since the first frame, else
	                          * index / fps; the time paused taken out */
	double flight_start;     /* the clock_time the autopilot's flight began:
	                          * 0, a playlist's show's start or the preset
	                          * key's press (each flies from its own spawn
	                          * over its own terrain) */
	float move[3], turn[2];  /* the manual camera's held flight keys (-1..1):
	                          * forward, right, up; yaw right, pitch up */
	struct renderer *r;      /* draw into it */
	int w, h;
	const struct wall_view *view; /* the frame's part of a video wall's
	                               * virtual screen (camera_window); NULL or
	                               * off: the whole screen, aspect w / h */
	double refresh_hz;       /* the display's refresh rate when known, else 0 */
	double cap_fps;          /* the frame cap in force (max_fps, or the
	                          * low-power profile's), 0: none; the governor
	                          * holds its budget when no target_fps is set */
	int min_quality;         /* the world holds at least this level of the
	                          * governor's ladder (the low-power profile) */
	double last_work_ms;     /* the frame before's whole work, ms: from the
	                          * top of the loop to its present done, less the
	                          * frame cap's sleep and the time the present
	                          * waited for the display (what the governor
	                          * holds); < 0: not known (the first frame, a
	                          * pause's idle wait) */
	struct scene_timing *timing; /* NULL, or the scene waits for the GPU after
	                              * its update and after its draw and says how
	                              * long each took (--results) */
};
struct scene_timing {
	double update_ms, draw_ms;
};
/* The camera's aspect for the frame: a wall's virtual screen's, else w / h. */
static inline float scene_frame_aspect(const struct scene_frame *fr)
{
	return fr->view && fr->view->on ? fr->view->aspect : (float)fr->w / (float)fr->h;
}

/* What a scene counts, for the results file. */
struct scene_counts {
	unsigned long long triangles;        /* the volume's mesh (0 for the world) */
	unsigned long long extractions;      /* the volume's frames that extracted the field
	                                      * (a static one: the first only; 0 for the world) */
	unsigned long long blocks_generated; /* the world's (0 for the volume) */
	unsigned long long blocks_evicted;
	int blocks_drawn;
	/* the world's coarse pre-pass: blocks it bounded, and those it proved
	 * all air or all rock (skipped: never generated) */
	unsigned long long blocks_probed, blocks_skipped;
	/* the world's governor, when it ran: the render scale and view
	 * distance it held on average, and its level at the end */
	bool governed;
	double held_scale, held_view, held_near_lod;
	int held_level;
};

struct scene;
struct scene_ops {
	/* Advances to frame fr->index (p->time, the camera), updates and
	 * draws into fr->r.  0, or -1 with err ("" when the cause is already
	 * logged, a GL error). */
	int (*frame)(struct scene *s, struct params *p, const struct scene_frame *fr, char *err, size_t errlen);
	/* The run's summary after "N frame(s) WxH, ": "grid 48^3: ..." or
	 * "world: ...", and a warning to give first (or "").  -1 when the
	 * statistics cannot be read (no summary). */
	int (*report)(struct scene *s, const struct params *p, char *line, size_t len, char *warn, size_t wlen);
	/* The mesh the scene shows now, in world space (--export-mesh).  0/-1. */
	int (*read_mesh)(struct scene *s, struct mesh *m);
	/* Optional: what the scene holds now, one short line for the frame
	 * rate reports ("" = nothing to say). */
	void (*status)(struct scene *s, char *line, size_t len);
	/* What it counts now (every scene).  0/-1. */
	int (*counts)(struct scene *s, struct scene_counts *c);
	void (*destroy)(struct scene *s);
};

struct scene {
	const struct scene_ops *ops;
};

/* The scenes.  p must outlive the scene: the world's autopilot reads the
 * parameters the controls change.  NULL with err. */
struct scene *scene_volume_create(const struct params *p, char *err, size_t errlen);
/* Within the scenes: the edit state's road map handed to the renderer for
 * this frame (scene_roads.c).  0, or -1 with err. */
struct edits;
int scene_roads(struct edits *ed, const struct params *p, struct renderer *r, char *err, size_t errlen);
struct scene *scene_world_create(const struct params *p, char *err, size_t errlen);
/* The scene p->scene names. */
static inline struct scene *scene_create(const struct params *p, char *err, size_t errlen)
{
	return p->scene == SCENE_WORLD ? scene_world_create(p, err, errlen) : scene_volume_create(p, err, errlen);
}
static inline void scene_destroy(struct scene *s)
{
	if (s)
		s->ops->destroy(s);
}

/* the streaming world, its camera and autopilot */
#include "world.h"

#endif
