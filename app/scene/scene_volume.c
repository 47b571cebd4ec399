/* isoterra — the volume scene: one box of the field extracted every frame
 * (the pipeline), seen by the orbit camera. */
#include "scene.h"
#include "controls.h"
#include "pipeline.h"
#include "render.h"
#include "edits.h"
#include "terrain.h"
#include "clock.h"

#include <stdio.h>
#include <stdlib.h>

struct volume_scene {
	struct scene base;
	struct grid g;
	struct edits *ed;      /* the curves and heightmap the terrain carves */
	struct terrain *tr;    /* the field the pipeline extracts */
	struct pipeline *pl;
	float t0; /* p->time at the start: time advances from there */
};

/* A grid of another size (a knob turned --grid or vol_height): the
 * pipeline made again for it, its buffers sized for the new grid.  On
 * failure the old one stays.  0 or -1 with err. */
static int follow_grid(struct volume_scene *vs, const struct params *p, char *err, size_t errlen)
{
	struct grid g;
	grid_from_params(&g, p);
	if (g.nx == vs->g.nx && g.ny == vs->g.ny && g.nz == vs->g.nz)
		return 0;
	struct pipeline *pl = pipeline_create(&g, p, terrain_field(vs->tr), err, errlen);
	if (!pl)
		return -1;
	pipeline_destroy(vs->pl);
	vs->pl = pl;
	vs->g = g;
	return 0;
}

static int volume_frame(struct scene *s, struct params *p, const struct scene_frame *fr, char *err, size_t errlen)
{
	struct volume_scene *vs = (struct volume_scene *)s;
	float t = controls_time(fr->ctl, (float)fr->index / p->fps);
	p->time = vs->t0 + t;
	err[0] = 0;
	double t0 = clock_ms();
	if (follow_grid(vs, p, err, errlen) < 0 || pipeline_run(vs->pl, p, err, errlen) < 0)
		return -1;
	if (fr->timing) {
		glFinish();
		fr->timing->update_ms = clock_ms() - t0;
		t0 = clock_ms();
	}
	struct pipeline_draw d;
	struct camera cam;
	pipeline_draw_info(vs->pl, &d);
	camera_orbit(&cam, p, &vs->g, t, (float)fr->w / (float)fr->h);
	if (renderer_draw(fr->r, &d, &cam, p) < 0)
		return -1;
	if (fr->timing) {
		glFinish();
		fr->timing->draw_ms = clock_ms() - t0;
	}
	return 0;
}

static int volume_counts(struct scene *s, struct scene_counts *c)
{
	struct extract_stats st;
	if (pipeline_read_stats(((struct volume_scene *)s)->pl, &st) < 0)
		return -1;
	*c = (struct scene_counts){ .triangles = st.triangles };
	return 0;
}

static int volume_report(struct scene *s, const struct params *p, char *line, size_t len, char *warn, size_t wlen)
{
	struct volume_scene *vs = (struct volume_scene *)s;
	struct extract_stats st;
	if (pipeline_read_stats(vs->pl, &st) < 0)
		return -1;
	warn[0] = 0;
	if (st.overflow)
		snprintf(warn, wlen,
			 "mesh capacity exceeded: the field needs %llu triangles / %llu vertices, capacity %u / %u; "
			 "output clamped (raise --max-triangles / --max-vertices)",
			 (unsigned long long)st.triangles_needed, (unsigned long long)st.vertices_needed,
			 st.triangle_capacity, st.vertex_capacity);
	snprintf(line, len, "grid %d^3: %u triangles, %u vertices", p->grid, st.triangles, st.vertices);
	return 0;
}

static int volume_read_mesh(struct scene *s, struct mesh *m)
{
	return pipeline_read_mesh(((struct volume_scene *)s)->pl, m);
}

static void volume_destroy(struct scene *s)
{
	struct volume_scene *vs = (struct volume_scene *)s;
	pipeline_destroy(vs->pl);
	terrain_destroy(vs->tr);
	edits_destroy(vs->ed);
	free(vs);
}

static const struct scene_ops volume_ops = {
	.frame = volume_frame,
	.report = volume_report,
	.read_mesh = volume_read_mesh,
	.counts = volume_counts,
	.destroy = volume_destroy,
};

struct scene *scene_volume_create(const struct params *p, char *err, size_t errlen)
{
	struct volume_scene *vs = calloc(1, sizeof(*vs));
	if (!vs) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	vs->base.ops = &volume_ops;
	vs->t0 = p->time;
	grid_from_params(&vs->g, p);
	vs->ed = edits_create();
	vs->tr = vs->ed ? terrain_create(vs->ed) : NULL;
	if (!vs->tr) {
		snprintf(err, errlen, "out of memory");
		volume_destroy(&vs->base);
		return NULL;
	}
	vs->pl = pipeline_create(&vs->g, p, terrain_field(vs->tr), err, errlen);
	if (!vs->pl) {
		volume_destroy(&vs->base);
		return NULL;
	}
	return &vs->base;
}
