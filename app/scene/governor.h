/* isoterra — the frame-time governor: holds a target frame time by trading
 * quality, in a fixed order (the edge smoothing after the frame and the
 * close-up detail's finer scale, the rest of the close-up detail, the
 * block generation budget, the finer levels of detail's range, the render
 * scale and with its first step the
 * composed start's view, then AO rays, sun shadow steps, far-LOD octaves,
 * view distance), and gives it back when there is
 * headroom.  It only sees frame times and a clock, so a test
 * drives it with a fake clock and a synthetic load.
 *
 * What it holds is the frame time most frames stay under: the smoothed
 * mean plus one smoothed deviation, so a frame time whose mean sits just
 * under the target while a third of the frames miss it is not held.
 *
 * Hysteresis: it steps down when that is over the target for a short
 * while (several levels at once while the mean frame is over 1.5
 * targets: governor.c far_steps), up only when the level above is
 * predicted to fit for longer, waits after every step for the frame time
 * to settle, and each step up
 * that has to be taken back doubles the wait before the next try (so a
 * load that sits between two steps does not make it oscillate), a step up
 * that holds halves it again.  The prediction: what it holds now times
 * what that step cost when it was last taken, either way (the frame time
 * held just after a step over the one just before it, the same view a
 * moment apart), under 90 % of the target.  A step not measured yet is
 * taken to cost 1.2 times (up only under 75 % of the target, the fixed
 * line it had before); a measured cost counts only where it is lower.  So
 * after a heavy stretch of the flight it climbs back as soon as the level
 * above fits, not only once the frame is under the fixed line.  A frame
 * held so far under the target that two levels more at the fixed line's
 * cost would fit (the view turned to the sky) climbs at once, as many
 * levels as that line allows, without the doubled wait. */
#ifndef ISOTERRA_GOVERNOR_H
#define ISOTERRA_GOVERNOR_H

#include <stdbool.h>

#include "params.h"

/* What it holds now: the world applies these each frame. */
struct governor_quality {
	float render_scale;   /* 0.5 .. 1: the 3D view is drawn this much smaller and upscaled */
	float gen_budget;     /* 0.25 .. 1: times the configured block generation budget */
	float ao_rays;        /* 0 .. 1: times the configured AO rays (new blocks) */
	float shadow_steps;   /* 0 .. 1: times the configured sun shadow steps (new blocks) */
	int far_octaves_drop; /* 0 .. 2: octaves left out of the coarsest level's blocks */
	float view_distance;  /* 0.55 .. 1: times the configured view distance */
	float framing;        /* 1: the autopilot's composed start (its view tilted down onto the
	                       * land); 0: the cruise's tilt, whose frames draw half the terrain */
	float smoothing;      /* 1: the edge smoothing after the frame as configured (--antialias:
	                       * the filter on a software rasterizer); 0: none */
	float detail;         /* 1: the close-up detail of the near meshes at both scales (render.frag's
	                       * DETAIL_NORMALS); 0.5: at the coarser only; 0: every mesh drawn with
	                       * the far meshes' program */
	float near_lod;       /* 1: the finer levels of detail out to lod_distance of their blocks; 2/3: out to
	                       * two thirds of that (the coarser level nearer the eye; docs/WORLD.md) */
	int level;            /* 0 = full quality .. GOVERNOR_LEVELS - 1 */
};

#define GOVERNOR_LEVELS 19

struct governor {
	double target_ms;
	double smooth_ms;       /* exponential average of the frame times */
	double smooth_var;      /* exponential average of their squared deviation from it */
	double over_since, under_since; /* clock when the current excursion began (< 0: none) */
	double settle_until;    /* no decision before this */
	double up_wait_s;       /* how long the level above must be predicted to fit before a step up */
	double last_up_s;       /* when the last step up was taken (< 0: none) */
	bool up_judged;         /* whether that step up was found to hold (or not) yet */
	bool last_up_sure;      /* whether it was a sure climb (governor.c sure_steps) */
	float up_cost[GOVERNOR_LEVELS]; /* [L]: the frame time held at L - 1 over that at L, measured
	                                 * across the last step between them (0: none yet) */
	int learn_from;         /* the level a step just left, until the time held after it is read (-1) */
	double learn_held;      /* the time held there, just before the step */
	int level;
	unsigned steps_down, steps_up;
	double scale_sum;       /* for the mean render scale / view distance held */
	double view_sum;
	double near_sum;        /* ... and the near LOD's range */
	unsigned frames;
};

/* target_ms > 0: the frame time to hold (1000 / target fps). */
void governor_init(struct governor *g, double target_ms);
/* One finished frame that took frame_ms, at clock now_s (seconds, any
 * origin, never decreasing); the quality for the next frame. */
struct governor_quality governor_update(struct governor *g, double frame_ms, double now_s);
/* The close-up detail's scales q holds (renderer_set_detail): 2, 1 or 0. */
int governor_detail_scales(const struct governor_quality *q);
/* The quality of a level (0 .. GOVERNOR_LEVELS - 1). */
struct governor_quality governor_level(int level);
/* The parameters a frame runs with under quality q (the render scale is
 * the renderer's, the far octaves the world's: not parameters). */
void governor_apply(const struct governor_quality *q, const struct params *p, struct params *eff);
/* What it compares with the target: the smoothed frame time plus one
 * smoothed deviation (ms; -1 before the first frame). */
double governor_held_ms(const struct governor *g);
/* Means over every update so far (1 before the first). */
double governor_mean_scale(const struct governor *g);
double governor_mean_view(const struct governor *g);
double governor_mean_near_lod(const struct governor *g);

#endif
