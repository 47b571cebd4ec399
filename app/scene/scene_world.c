/* isoterra — the world scene: the streaming world (world.c) seen from the
 * autopilot's camera, or steered by the flight keys (camera=manual). */
#include "scene.h"
#include "core.h"
#include "render.h"
#include "world.h"
#include "edit.h"
#include "governor.h"
#include "gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

struct world_scene {
	struct scene base;
	struct edits *ed; /* the curves and heightmap the terrain carves */
	struct world *w;
	struct autopilot ap;
	bool ap_ready;
	double show_start;   /* the last frame's flight_start (a show's start, a preset's press) */
	double flight_t0;    /* the clock_time the flight began at */
	struct params blocks_p; /* what the world's blocks were made for (params_same_blocks) */
	float t0;  /* p->time: the world does not scroll, the camera moves */
	float far; /* the camera's far plane */
	bool governed;             /* the frame-time governor runs (live frames) */
	struct governor gov;
	struct governor_quality q; /* what it holds for the next frame */
	double last_work_ms;
	/* the finer levels' range as it moves to what the governor holds
	 * (governor_quality.near_lod), and when it last moved (clock_ms) */
	float near_lod;
	double near_at;
	double empty_since;        /* scene time since when no terrain is drawn (< 0: some is) */
	bool empty_said;
};

/* A flight that sees no terrain for this long is said once. */
#define EMPTY_VIEW_S 3.0
/* Seconds the finer levels' range takes to move between the governor's
 * two (its step's settle, governor.c SETTLE_S, then reads what it saved) */
#define NEAR_LOD_S 0.4

/* The frame rate the governor holds: target_fps; else the frame cap's (a
 * power target: quality stepped down to keep the frame within the cap's
 * budget), at most the refresh rate; else the refresh rate, else 30. */
static double governor_fps(const struct params *p, const struct scene_frame *fr)
{
	if (p->target_fps > 0)
		return p->target_fps;
	if (fr->cap_fps > 0)
		return fr->refresh_hz > 0 && fr->refresh_hz < fr->cap_fps ? fr->refresh_hz : fr->cap_fps;
	return fr->refresh_hz > 0 ? fr->refresh_hz : 30.0;
}

/* Live frames under the governor: the frame's parameters and render scale
 * from what it holds.  0, or -1 with err. */
static int governed_params(struct world_scene *ws, const struct params *p, const struct scene_frame *fr,
			   struct params *eff, char *err, size_t errlen)
{
	*eff = *p;
	/* offline frames, a governor turned off, a wall (its tiles must not
	 * differ): the configured level of the ladder, the same every frame */
	if (!fr->live || p->governor == GOVERNOR_OFF || (fr->view && fr->view->on)) {
		ws->governed = false;
		int level = p->quality > fr->min_quality ? p->quality : fr->min_quality;
		if (level == 0 && ws->q.level == 0) /* full quality, as ever (byte for byte) */
			return 0;
		ws->q = governor_level(level);
		ws->near_lod = ws->q.near_lod;
		return world_hold_quality(ws->w, fr->r, &ws->q, p, eff, err, errlen);
	}
	if (!ws->governed) {
		governor_init(&ws->gov, 1000.0 / governor_fps(p, fr));
		ws->q = governor_level(0);
		ws->near_lod = ws->q.near_lod;
		ws->near_at = -1.0;
		ws->governed = true;
	}
	ws->gov.target_ms = 1000.0 / governor_fps(p, fr); /* a cap that changed: its budget */
	/* the frame before, whole: update, draw, the passes after it, the
	 * overlays and the present, not the display's waits (app/run.c); the
	 * first frame fills the view: not a frame time */
	if (fr->index >= 2 && fr->last_work_ms >= 0) {
		ws->last_work_ms = fr->last_work_ms;
		ws->q = governor_update(&ws->gov, fr->last_work_ms, clock_ms() / 1e3);
	}
	if (ws->q.level < fr->min_quality) /* the low-power profile's floor */
		ws->q = governor_level(fr->min_quality);
	if (world_hold_quality(ws->w, fr->r, &ws->q, p, eff, err, errlen) < 0)
		return -1;
	/* the finer levels' range moves there over NEAR_LOD_S, not at once:
	 * the finer blocks near its end sink behind the coarser surface as
	 * the end passes them (world.c's fade), none pops */
	double now = clock_ms() / 1e3, dt = ws->near_at > 0 ? now - ws->near_at : 0.0;
	ws->near_at = now;
	float step = (float)(dt / NEAR_LOD_S) * (1.0f - governor_level(GOVERNOR_LEVELS - 1).near_lod);
	ws->near_lod = ws->q.near_lod < ws->near_lod ? fmaxf(ws->q.near_lod, ws->near_lod - step)
						     : fminf(ws->q.near_lod, ws->near_lod + step);
	eff->lod_distance = p->lod_distance * ws->near_lod;
	return 0;
}

static void world_status(struct scene *s, char *line, size_t len)
{
	struct world_scene *ws = (struct world_scene *)s;
	if (!ws->governed) {
		line[0] = 0;
		return;
	}
	struct governor_quality q = ws->q;
	/* held: the smoothed frame time plus its deviation (governor.h) */
	snprintf(line, len,
		 "governor %.1f ms held of %.1f (last %.1f): level %d, smoothing %s, detail %s, near LOD x%.2f, scale %.2f, "
		 "budget x%.2f, AO x%.2f, shadows x%.2f, far -%d oct, view x%.2f",
		 governor_held_ms(&ws->gov), ws->gov.target_ms, ws->last_work_ms, q.level, q.smoothing > 0.5f ? "on" : "off",
		 (const char *[]){ "off", "coarse", "on" }[governor_detail_scales(&q)], q.near_lod, q.render_scale, q.gen_budget,
		 q.ao_rays, q.shadow_steps, q.far_octaves_drop, q.view_distance);
}

/* A flight that sees no terrain for seconds (in empty sky above the
 * field, or under it): said once, with where the camera is and what to
 * change, instead of frames of sky without a word. */
static void empty_view(struct world_scene *ws, const struct params *p, const struct camera *cam, double t)
{
	struct world_stats st;
	world_get_stats(ws->w, &st);
	if (st.drawn_tris > 0) {
		ws->empty_since = -1.0;
		return;
	}
	if (ws->empty_since < 0.0)
		ws->empty_since = t;
	if (ws->empty_said || t - ws->empty_since < EMPTY_VIEW_S)
		return;
	ws->empty_said = true;
	log_warn("world: no terrain in view for %.1f s (the camera at %.1f, %.1f, %.1f, fly_height %g, camera %s): the "
		 "flight sees only sky; a lower --fly-height or another --seed or field brings the ground into view",
		 t - ws->empty_since, cam->eye[0], cam->eye[1], cam->eye[2], p->fly_height,
		 p->camera == CAMERA_MANUAL ? "manual" : "autopilot");
}

static int world_frame(struct scene *s, struct params *p, const struct scene_frame *fr, char *err, size_t errlen)
{
	struct world_scene *ws = (struct world_scene *)s;
	/* Offline (headless: PNG, Y4M, tests) every frame is complete and
	 * reproducible: time is frame / fps and each frame waits for its
	 * blocks.  On a display the world runs live: wall-clock time, and
	 * blocks stream in under the generation budget. */
	double t0 = clock_ms();
	double t = fr->clock_time;
	p->time = ws->t0;
	if (p->camera == CAMERA_MANUAL) /* manual: the keys and the pad steer, rock still stops */
		autopilot_steer(&ws->ap, fr->move, fr->turn);
	else if (ws->ap.manual) /* the autopilot again (the pad's start button) */
		autopilot_resume(&ws->ap);
	struct camera cam;
	/* a new flight (a playlist's show, the preset key) from its own spawn
	 * (its composed start) over its own terrain, not on from where the
	 * last one was (where the new terrain may wall it in); the realtime
	 * clock's period began again: so does the flight */
	bool new_show = fr->flight_start != ws->show_start;
	if (new_show || t - ws->flight_t0 + 0.5 / 60.0 < ws->ap.t) {
		/* from the show's start (0 without a playlist: every board of a
		 * wall the same flight), or from now when a pause held the clock
		 * back behind the show's (clock_time <= the show's time) */
		ws->show_start = fr->flight_start;
		ws->flight_t0 = fr->flight_start <= t ? fr->flight_start : t;
		autopilot_free(&ws->ap);
		ws->ap_ready = false;
		if (autopilot_init(&ws->ap, p, ws->ed) < 0) {
			snprintf(err, errlen, "out of memory");
			return -1;
		}
		ws->ap_ready = true;
	}
	ws->ap.framing = ws->q.framing; /* the quality held since the last frame */
	autopilot_advance(&ws->ap, t - ws->flight_t0);
	autopilot_camera(&ws->ap, &cam, p->fov, scene_frame_aspect(fr), ws->far);
	camera_window(&cam, fr->view);
	err[0] = 0;
	struct params eff;
	if (governed_params(ws, p, fr, &eff, err, errlen) < 0)
		return -1;
	/* the terrain changed (a playlist's show, a knob, a reload): every
	 * block is made again: live, each drawn as it was until its new mesh
	 * replaces it, under the generation budget; offline, all of the view's
	 * before this frame is drawn, as on the first frame.  Judged on the
	 * parameters, not the governed ones: the governor's AO and shadows are
	 * for new blocks only. */
	bool refill = false;
	if (!params_same_blocks(&ws->blocks_p, p)) {
		ws->blocks_p = *p;
		static const float everywhere[4] = { -1e30f, -1e30f, 1e30f, 1e30f };
		log_info("world: the terrain changed: %d blocks made again", world_invalidate(ws->w, &eff, everywhere));
		refill = !fr->live;
	}
	world_keep_terms(ws->w, p);
	int urc = fr->index == 0 || refill ? world_fill(ws->w, &eff, &cam, t) : world_update(ws->w, &eff, &cam, t, !fr->live);
	if (urc < 0)
		return -1;
	double td = clock_ms();
	if (fr->timing) {
		glFinish();
		td = clock_ms();
		fr->timing->update_ms = td - t0;
	}
	if (scene_roads(ws->ed, &eff, fr->r, err, errlen) < 0)
		return -1;
	if (world_draw(ws->w, fr->r, &cam, &eff, t) < 0)
		return -1;
	empty_view(ws, p, &cam, t);
	if (fr->timing) {
		glFinish();
		fr->timing->draw_ms = clock_ms() - td;
	}
	return 0;
}

static int world_report(struct scene *s, const struct params *p, char *line, size_t len, char *warn, size_t wlen)
{
	struct world_scene *ws = (struct world_scene *)s;
	struct world_stats st;
	(void)p;
	(void)wlen;
	world_get_stats(ws->w, &st);
	warn[0] = 0; /* nothing to warn about first: an overflow is part of the line */
	char gov[128] = "";
	if (ws->governed)
		snprintf(gov, sizeof(gov), "; governor held render scale %.2f, view distance x%.2f, near LOD x%.2f on average",
			 governor_mean_scale(&ws->gov), governor_mean_view(&ws->gov), governor_mean_near_lod(&ws->gov));
	snprintf(line, len,
		 "world: %llu blocks generated (%llu empty, never regenerated), %llu skipped by the pre-pass (of %llu "
		 "bounded), %d drawn, %llu evicted%s%s",
		 (unsigned long long)st.generated, (unsigned long long)st.empty_found,
		 (unsigned long long)st.prepass_empty, (unsigned long long)st.prepass_probed, st.drawn,
		 (unsigned long long)st.evicted, st.overflowed ? ", some blocks over 200000 triangles (clamped)" : "",
		 gov);
	return 0;
}

static int world_counts(struct scene *s, struct scene_counts *c)
{
	struct world_stats st;
	world_get_stats(((struct world_scene *)s)->w, &st);
	const struct world_scene *ws = (const struct world_scene *)s;
	*c = (struct scene_counts){ .blocks_generated = st.generated, .blocks_evicted = st.evicted,
				    .blocks_drawn = st.drawn, .blocks_probed = st.prepass_probed,
				    .blocks_skipped = st.prepass_empty, .governed = ws->governed };
	if (ws->governed) {
		c->held_scale = governor_mean_scale(&ws->gov);
		c->held_view = governor_mean_view(&ws->gov);
		c->held_near_lod = governor_mean_near_lod(&ws->gov);
		c->held_level = ws->q.level;
	}
	return 0;
}

static int world_scene_mesh(struct scene *s, struct mesh *m)
{
	return world_read_mesh(((struct world_scene *)s)->w, m);
}

static void world_scene_destroy(struct scene *s)
{
	struct world_scene *ws = (struct world_scene *)s;
	if (ws->ap_ready)
		autopilot_free(&ws->ap);
	world_destroy(ws->w);
	edits_destroy(ws->ed);
	free(ws);
}

static const struct scene_ops world_ops = {
	.frame = world_frame,
	.report = world_report,
	.read_mesh = world_scene_mesh,
	.status = world_status,
	.counts = world_counts,
	.destroy = world_scene_destroy,
};

struct scene *scene_world_create(const struct params *p, char *err, size_t errlen)
{
	struct world_scene *ws = calloc(1, sizeof(*ws));
	if (!ws) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	ws->base.ops = &world_ops;
	ws->empty_since = -1.0;
	ws->t0 = p->time;
	ws->far = p->view_distance * 1.2f;
	ws->ed = edits_create();
	if (!ws->ed) {
		snprintf(err, errlen, "out of memory");
		free(ws);
		return NULL;
	}
	ws->w = world_create(p, ws->ed, err, errlen);
	if (!ws->w) {
		world_scene_destroy(&ws->base);
		return NULL;
	}
	if (autopilot_init(&ws->ap, p, ws->ed) < 0) {
		snprintf(err, errlen, "out of memory");
		world_scene_destroy(&ws->base);
		return NULL;
	}
	ws->ap_ready = true;
	ws->blocks_p = *p;
	ws->q = governor_level(0);
	return &ws->base;
}
