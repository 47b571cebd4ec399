/* isoterra — the world scene: the streaming world (world.c) seen from the
 * autopilot's camera, or steered by the flight keys (camera=manual). */
#include "scene.h"
#include "clock.h"
#include "controls.h"
#include "render.h"
#include "world.h"
#include "edits.h"

#include <stdio.h>
#include <stdlib.h>

struct world_scene {
	struct scene base;
	struct edits *ed; /* the curves and heightmap the terrain carves */
	struct world *w;
	struct autopilot ap;
	bool ap_ready;
	float t0;  /* p->time: the world does not scroll, the camera moves */
	float far; /* the camera's far plane */
};

static int world_frame(struct scene *s, struct params *p, const struct scene_frame *fr, char *err, size_t errlen)
{
	struct world_scene *ws = (struct world_scene *)s;
	/* Offline (headless: PNG, Y4M, tests) every frame is complete and
	 * reproducible: time is frame / fps and each frame waits for its
	 * blocks.  On a display the world runs live: wall-clock time, and
	 * blocks stream in under the generation budget. */
	double t = fr->live ? clock_ms() / 1e3 - fr->start_s : (double)fr->index / p->fps;
	t -= (double)((float)t - controls_time(fr->ctl, (float)t)); /* paused time */
	p->time = ws->t0;
	if (p->camera == CAMERA_MANUAL) { /* manual: the keys steer, rock still stops */
		float move[3], turn[2];
		controls_flight(fr->ctl, move, turn);
		autopilot_steer(&ws->ap, move, turn);
	}
	struct camera cam;
	autopilot_advance(&ws->ap, t);
	autopilot_camera(&ws->ap, &cam, p->fov, (float)fr->w / (float)fr->h, ws->far);
	err[0] = 0;
	int urc = fr->index == 0 ? world_fill(ws->w, p, &cam, t) : world_update(ws->w, p, &cam, t, !fr->live);
	if (urc < 0 || world_draw(ws->w, fr->r, &cam, p, t) < 0)
		return -1;
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
	snprintf(line, len, "world: %llu blocks generated (%llu empty, never regenerated), %d drawn, %llu evicted%s",
		 (unsigned long long)st.generated, (unsigned long long)st.empty_found, st.drawn,
		 (unsigned long long)st.evicted, st.overflowed ? ", some blocks over capacity (raise --block-tris)" : "");
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
	return &ws->base;
}
