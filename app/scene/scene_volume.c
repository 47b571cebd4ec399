/* isoterra — the volume scene: one box of the field extracted (the
 * pipeline), seen by the orbit camera; extracted again only when what it
 * was made of changed (its parameters, time where the field scrolls, the
 * edit files, a live shader edit, the grid). */
#include "scene.h"
#include "extract.h"
#include "render.h"
#include "edit.h"
#include "terrain.h"
#include "core.h"
#include "gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct volume_scene {
	struct scene base;
	struct grid g;
	struct edits *ed;      /* the curves and heightmap the terrain carves */
	struct terrain *tr;    /* the field the pipeline extracts */
	struct pipeline *pl;
	float t0; /* p->time at the start: time advances from there */
	/* what the pipeline's mesh was made of: none yet, or the parameters
	 * (params_same_extraction) and the live shader edits' count then */
	bool made;
	struct params made_p;
	unsigned long made_rebuilt;
	unsigned long long extractions; /* frames that extracted (scene_counts) */
	/* the capacity the mesh grew to (follow_capacity; 0: the automatic
	 * one), and whether the GL's buffer limit stopped it */
	uint32_t grown_tris, grown_verts;
	bool cap_at_limit;
	bool inside; /* caves: the camera stands in a chamber, not outside the box */
	float eye[3], look[3]; /* ... there, looking along the longest tunnel */
};

/* Air along the ray from `from` in direction d (unit), to the first rock
 * or len, in steps of st. */
static float free_run(const struct params *p, const struct noise_set *ns, const struct edits *ed, const float from[3],
		      const float d[3], float len, float st)
{
	float t = st;
	for (; t < len; t += st)
		if (density_ref(p, ns, ed, from[0] + d[0] * t, from[1] + d[1] * t, from[2] + d[2] * t) > p->iso)
			break;
	return t;
}

/* Endless caves seen from inside: the most open point of a lattice over the
 * middle of the box (the most negative density: the field is about a
 * distance, so the widest chamber), looking level along the one of
 * 32 with the longest run of air (a tunnel).  false: no air anywhere. */
static bool cave_view(struct volume_scene *vs, const struct params *p)
{
	struct noise_set *ns = malloc(sizeof(*ns));
	if (!ns)
		return false;
	noise_set_init(ns, p->seed);
	const struct grid *g = &vs->g;
	float ext[3] = { g->cell * (float)g->nx, g->cell * (float)g->ny, g->cell * (float)g->nz }, best = p->iso;
	bool found = false;
	for (int i = 0; i < 12; i++)
		for (int j = 0; j < 6; j++)
			for (int k = 0; k < 12; k++) {
				float q[3] = { g->origin[0] + ext[0] * (0.25f + 0.5f * (float)i / 11.0f),
					       g->origin[1] + ext[1] * (0.3f + 0.4f * (float)j / 5.0f),
					       g->origin[2] + ext[2] * (0.25f + 0.5f * (float)k / 11.0f) };
				float d = density_ref(p, ns, vs->ed, q[0], q[1], q[2]);
				if (d < best)
					best = d, found = true, memcpy(vs->eye, q, sizeof(q));
			}
	float far = 0.0f;
	for (int a = 0; a < 32 && found; a++) {
		float ang = (float)a * (6.2831853f / 32.0f);
		float d[3] = { cosf(ang), 0.0f, sinf(ang) };
		/* to the box's side at most: a tunnel that leaves the box ends in
		 * sky, so one that ends in rock inside it counts three times more */
		float len = 1e30f;
		for (int k = 0; k < 3; k++)
			if (fabsf(d[k]) > 1e-6f) {
				float lo = (g->origin[k] - vs->eye[k]) / d[k], hi = (g->origin[k] + ext[k] - vs->eye[k]) / d[k];
				len = fminf(len, fmaxf(lo, hi));
			}
		float run = free_run(p, ns, vs->ed, vs->eye, d, len, 0.5f * g->cell);
		if (run >= len)
			run *= 0.33f;
		if (run > far)
			far = run, memcpy(vs->look, d, sizeof(d));
	}
	free(ns);
	return found;
}

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
	vs->made = false;
	vs->grown_tris = vs->grown_verts = 0;
	vs->cap_at_limit = false;
	return 0;
}

/* Room for `need` and an eighth more (the next frames' field may ask a
 * little more), within the parameters' range. */
static uint32_t with_headroom(uint64_t need)
{
	uint64_t c = need + need / 8 + 1024;
	return c > 100000000u ? 100000000u : (uint32_t)c;
}

/* The mesh's capacity follows the field: where the last run was clamped
 * and the capacity is automatic (max_triangles / max_vertices 0: sixteen
 * triangles a cell of the grid's largest face, which a terrain fills to a
 * third and endless caves overflow), the pipeline is made again with room
 * for what the field asked, and the mesh unmade.  Learnt through
 * pipeline_watch_stats, never by stalling a frame: live, a frame or more
 * after the run (those frames draw the clamped mesh); offline (wait), at
 * once.  An explicit capacity stays, as does one the GL's buffer limit
 * holds (pipeline_create clamps to it) or memory refused: the report
 * warns that the mesh is clamped.  1 when the pipeline was made again,
 * 0, or -1 with err. */
static int follow_capacity(struct volume_scene *vs, const struct params *p, bool wait, char *err, size_t errlen)
{
	struct extract_stats st;
	int got = pipeline_watched_stats(vs->pl, wait, &st);
	if (got < 0)
		log_warn("volume: the run's counts could not be read back: the mesh's capacity stays");
	if (got <= 0 || !st.overflow || vs->cap_at_limit)
		return 0;
	bool grow_t = !p->max_triangles && st.triangles_needed > st.triangle_capacity;
	bool grow_v = !p->max_vertices && st.vertices_needed > st.vertex_capacity;
	if (!grow_t && !grow_v)
		return 0;
	if ((vs->grown_tris && st.triangle_capacity < vs->grown_tris) ||
	    (vs->grown_verts && st.vertex_capacity < vs->grown_verts)) {
		vs->cap_at_limit = true; /* the last growth was clamped: the GL's limit */
		return 0;
	}
	struct params q = *p;
	q.max_triangles = grow_t ? with_headroom(st.triangles_needed) : st.triangle_capacity;
	q.max_vertices = grow_v ? with_headroom(st.vertices_needed) : st.vertex_capacity;
	struct pipeline *pl = pipeline_create(&vs->g, &q, terrain_field(vs->tr), err, errlen);
	if (!pl) {
		log_warn("volume: the mesh's capacity could not grow to %u triangles / %u vertices (%s): it stays clamped",
			 q.max_triangles, q.max_vertices, err);
		err[0] = 0;
		vs->cap_at_limit = true;
		return 0;
	}
	log_info("volume: the field asks %llu triangles / %llu vertices, over the capacity of %u / %u: grown to %u / %u",
		 (unsigned long long)st.triangles_needed, (unsigned long long)st.vertices_needed, st.triangle_capacity,
		 st.vertex_capacity, q.max_triangles, q.max_vertices);
	pipeline_destroy(vs->pl);
	vs->pl = pl;
	vs->made = false;
	vs->grown_tris = q.max_triangles;
	vs->grown_verts = q.max_vertices;
	return 1;
}

/* The field extracted again unless the mesh already is of it: a static
 * field seen by the orbiting camera is extracted once (the no-flag run on
 * a software rasterizer: 49-51 ms of a 1280x720 frame's 124-140).  0 or
 * -1 with err. */
static int extract(struct volume_scene *vs, const struct params *p, bool wait, char *err, size_t errlen)
{
	/* the edit files reloaded where they changed (as a run's program
	 * variant does), their change taken */
	if (edits_load(vs->ed, p, err, errlen) < 0)
		return -1;
	float box[4];
	bool edited = edits_take_changes(vs->ed, box);
	unsigned long rebuilt = gpu_programs_rebuilt();
	if (vs->made && !edited && rebuilt == vs->made_rebuilt && params_same_extraction(&vs->made_p, p))
		return 0;
	vs->made = false;
	/* wait (offline, and live the first extraction, which no frame has
	 * shown yet): a run the capacity clamped is run again at once, grown
	 * (the pipeline made again holds room for what the field asked: one
	 * growth is enough) */
	for (int tries = 0; tries < 4; tries++) {
		if (pipeline_run(vs->pl, p, err, errlen) < 0)
			return -1;
		if (pipeline_watch_stats(vs->pl) < 0)
			log_warn("volume: the run's counts cannot be watched: the mesh's capacity stays");
		int grown = wait ? follow_capacity(vs, p, true, err, errlen) : 0;
		if (grown < 0)
			return -1;
		if (!grown)
			break;
	}
	vs->made = true;
	vs->extractions++;
	vs->made_p = *p;
	vs->made_rebuilt = rebuilt;
	return 0;
}

static int volume_frame(struct scene *s, struct params *p, const struct scene_frame *fr, char *err, size_t errlen)
{
	struct volume_scene *vs = (struct volume_scene *)s;
	float t = fr->frame_time;
	p->time = vs->t0 + t;
	err[0] = 0;
	double t0 = clock_ms();
	/* live, after the first extraction: what an earlier frame's run asked,
	 * never waited for */
	bool wait = !fr->live || vs->extractions == 0;
	if (follow_grid(vs, p, err, errlen) < 0 || (!wait && follow_capacity(vs, p, false, err, errlen) < 0) ||
	    extract(vs, p, wait, err, errlen) < 0)
		return -1;
	/* the last picture is drawn without the densities and the pyramid
	 * (the no-flag run's peak) */
	if (fr->last)
		pipeline_release_field(vs->pl);
	if (fr->timing) {
		glFinish();
		fr->timing->update_ms = clock_ms() - t0;
		t0 = clock_ms();
	}
	struct pipeline_draw d;
	struct camera cam;
	pipeline_draw_info(vs->pl, &d);
	if (vs->inside) { /* in the chamber, turning slowly (cam_spin) */
		float a = p->cam_spin * t * (float)M_PI / 180.0f, c = cosf(a), sn = sinf(a);
		float at[3] = { vs->eye[0] + vs->look[0] * c - vs->look[2] * sn, vs->eye[1] + vs->look[1],
				vs->eye[2] + vs->look[0] * sn + vs->look[2] * c };
		float size = vs->g.cell * (float)vs->g.nx;
		camera_look(&cam, vs->eye, at, p->fov, scene_frame_aspect(fr), 0.002f * size, 2.0f * size);
	} else {
		camera_orbit(&cam, p, &vs->g, t, scene_frame_aspect(fr));
	}
	camera_window(&cam, fr->view);
	if (scene_roads(vs->ed, p, fr->r, err, errlen) < 0)
		return -1;
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
	*c = (struct scene_counts){ .triangles = st.triangles, .extractions = ((struct volume_scene *)s)->extractions };
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
	/* a software rasterizer's bins, freed after each part of the mesh
	 * (render_int.h) and after each frame, kept in the heap for the next
	 * (heap.c), not handed back and faulted in again */
	heap_policy();
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
	if (p->field == FIELD_TERRAIN && p->shape == SHAPE_CAVES && p->camera != CAMERA_MANUAL)
		vs->inside = cave_view(vs, p);
	return &vs->base;
}
