/* isoterra — the volume scene's mesh capacity follows the field.  Endless
 * caves at grid 64 ask about 98 000 triangles, over the automatic capacity
 * (16 a cell of the largest face: 67 600).  Against a scene given room to
 * spare (explicit capacities, never clamped): offline, the first frame's
 * mesh is that scene's, whole; live, the first extraction too (no frame
 * has shown a mesh yet); live later, a knob that asks for more than the
 * grown room is drawn clamped for a frame and whole from the next on,
 * without a stall (the counts read behind a fence); an explicit capacity
 * stays clamped, and the report says so. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int frame_mesh(struct scene *s, struct params *p, struct renderer *r, bool live, float t, struct mesh *m)
{
	char err[512] = "";
	struct scene_frame sf = { .index = 0, .r = r, .w = 64, .h = 64, .live = live, .frame_time = t, .clock_time = t };
	if (s->ops->frame(s, p, &sf, err, sizeof(err)) < 0) {
		fprintf(stderr, "frame: %s\n", err);
		return -1;
	}
	return s->ops->read_mesh(s, m);
}

static bool same_mesh(const struct mesh *a, const struct mesh *b)
{
	return a->ntris == b->ntris && a->nverts == b->nverts && !memcmp(a->pos, b->pos, sizeof(float) * 3 * a->nverts) &&
	       !memcmp(a->idx, b->idx, sizeof(uint32_t) * 3 * a->ntris);
}

/* The report's warning ("" when the mesh is whole). */
static void warning(struct scene *s, const struct params *p, char *warn, size_t len)
{
	char line[512];
	warn[0] = 0;
	if (s->ops->report(s, p, line, sizeof(line), warn, len) < 0)
		snprintf(warn, len, "(no report)");
}

/* A scene of p with room to spare: its mesh, never clamped. */
static int roomy_mesh(const struct params *p, struct renderer *r, struct mesh *m)
{
	char err[512] = "", warn[512];
	struct params q = *p;
	q.max_triangles = q.max_vertices = 1000000;
	struct scene *s = scene_create(&q, err, sizeof(err));
	if (!s || frame_mesh(s, &q, r, false, 0.0f, m) < 0) {
		fprintf(stderr, "a roomy scene: %s\n", err);
		scene_destroy(s);
		return -1;
	}
	warning(s, &q, warn, sizeof(warn));
	scene_destroy(s);
	if (warn[0]) {
		fprintf(stderr, "a roomy scene is clamped: %s\n", warn);
		return -1;
	}
	return 0;
}

int main(void)
{
	struct platform *plat = fixture_open();
	char err[512] = "", warn[512];
	struct params p;
	params_defaults(&p);
	CHECK(params_apply_preset(&p, "caves", err, sizeof(err)) == 0, "caves: %s", err);
	p.grid = 64;
	CHECK(p.max_triangles == 0 && p.max_vertices == 0, "the caves preset leaves the capacity automatic");
	struct renderer *r = renderer_create(64, 64, ANTIALIAS_AUTO, err, sizeof(err));
	CHECK(r, "renderer: %s", err);
	struct mesh ref, m;
	memset(&ref, 0, sizeof(ref));
	memset(&m, 0, sizeof(m));
	CHECK(roomy_mesh(&p, r, &ref) == 0, "the reference");
	printf("  caves at grid 64: %u triangles, %u vertices (automatic capacity 67600)\n", ref.ntris, ref.nverts);
	CHECK(ref.ntris > 67600, "the field asks more than the automatic capacity (%u triangles)", ref.ntris);

	/* offline: whole at once */
	struct scene *s = scene_create(&p, err, sizeof(err));
	CHECK(s && frame_mesh(s, &p, r, false, 0.0f, &m) == 0, "offline: %s", err);
	CHECK(same_mesh(&m, &ref), "offline: the whole mesh (%u triangles, want %u)", m.ntris, ref.ntris);
	warning(s, &p, warn, sizeof(warn));
	CHECK(!warn[0], "offline: no warning (%s)", warn);
	scene_destroy(s);
	mesh_free(&m);

	/* live: the first extraction whole; a knob that asks more than the
	 * grown room: clamped for a frame, whole from the next */
	s = scene_create(&p, err, sizeof(err));
	CHECK(s && frame_mesh(s, &p, r, true, 0.0f, &m) == 0, "live: %s", err);
	CHECK(same_mesh(&m, &ref), "live: the first frame's mesh whole (%u triangles, want %u)", m.ntris, ref.ntris);
	mesh_free(&m);
	struct params more = p;
	more.noise_freq *= 1.6f;
	struct mesh ref_more;
	memset(&ref_more, 0, sizeof(ref_more));
	CHECK(roomy_mesh(&more, r, &ref_more) == 0, "the reference with the knob turned");
	printf("  noise_freq x1.6: %u triangles\n", ref_more.ntris);
	CHECK(ref_more.ntris > ref.ntris + ref.ntris / 8 + 1024, "the knob asks more than the grown room (%u triangles)",
	      ref_more.ntris);
	CHECK(frame_mesh(s, &more, r, true, 0.5f, &m) == 0, "live, the knob turned");
	warning(s, &more, warn, sizeof(warn));
	printf("  the frame the knob turned: %u triangles (%s)\n", m.ntris, warn[0] ? "clamped" : "whole");
	CHECK(m.ntris < ref_more.ntris && warn[0], "live: that frame is clamped, not stalled for (%u triangles)", m.ntris);
	mesh_free(&m);
	bool whole = false;
	for (int f = 1; f <= 3 && !whole; f++) {
		CHECK(frame_mesh(s, &more, r, true, 0.5f + 0.1f * (float)f, &m) == 0, "live, a frame later");
		whole = same_mesh(&m, &ref_more);
		printf("  %d frame(s) later: %u triangles\n", f, m.ntris);
		mesh_free(&m);
	}
	CHECK(whole, "live: whole again within three frames");
	warning(s, &more, warn, sizeof(warn));
	CHECK(!warn[0], "live: no warning once grown (%s)", warn);
	scene_destroy(s);

	/* an explicit capacity stays: clamped, said */
	struct params fixed = p;
	fixed.max_triangles = 50000;
	s = scene_create(&fixed, err, sizeof(err));
	CHECK(s && frame_mesh(s, &fixed, r, false, 0.0f, &m) == 0, "explicit: %s", err);
	warning(s, &fixed, warn, sizeof(warn));
	CHECK(m.ntris == 50000, "explicit: clamped to --max-triangles 50000 (%u triangles)", m.ntris);
	CHECK(strstr(warn, "capacity exceeded") != NULL, "explicit: the report warns (%s)", warn);
	scene_destroy(s);
	mesh_free(&m);
	mesh_free(&ref);
	mesh_free(&ref_more);
	renderer_destroy(r);
	platform_close(plat);
	return tc_done("test_scene_capacity");
}
