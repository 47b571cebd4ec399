/* isoterra — a knob that turns --grid: the volume scene extracts at the new
 * grid, the same mesh a scene made at that grid extracts (not the old
 * grid's mesh under the new name).  And the scene extracts again only when
 * what the mesh is made of changes: a later frame of a static field keeps
 * the mesh (time passing, the camera orbiting), a knob turning a term of
 * the field or an edit file rewritten extracts the mesh a scene made with
 * it would, a scrolling field extracts every frame. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* One frame of scene s at p's grid, at time t; its mesh into *m. */
static int frame_mesh_at(struct scene *s, struct params *p, struct renderer *r, struct mesh *m, float t)
{
	char err[512] = "";
	struct scene_frame sf = { .index = 0, .r = r, .w = 64, .h = 64, .frame_time = t, .clock_time = t };
	if (s->ops->frame(s, p, &sf, err, sizeof(err)) < 0) {
		fprintf(stderr, "frame: %s\n", err);
		return -1;
	}
	return s->ops->read_mesh(s, m);
}

static int frame_mesh(struct scene *s, struct params *p, struct renderer *r, struct mesh *m)
{
	return frame_mesh_at(s, p, r, m, 0.0f);
}

static bool same_mesh(const struct mesh *a, const struct mesh *b)
{
	return a->ntris == b->ntris && a->nverts == b->nverts && !memcmp(a->pos, b->pos, sizeof(float) * 3 * a->nverts) &&
	       !memcmp(a->idx, b->idx, sizeof(uint32_t) * 3 * a->ntris);
}

/* A road across the default volume at height y0 + dy (the file a byte
 * longer when dy is not 0).  0 or -1. */
static int write_road(const char *path, float dy)
{
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	fprintf(f, "path,x,y,z,kind,width,falloff\n");
	for (int i = 0; i < 5; i++)
		fprintf(f, "road,%d,%.2f,%d,road,4,3\n", -20 + 10 * i, -2.0 + dy, -6 + 3 * i);
	if (dy != 0.0f)
		fputc('\n', f);
	return fclose(f) == 0 ? 0 : -1;
}

static unsigned long long extractions(struct scene *s)
{
	struct scene_counts c = { 0 };
	return s->ops->counts(s, &c) == 0 ? c.extractions : 0;
}

int main(void)
{
	struct platform *plat = fixture_open();
	char err[512] = "";
	struct params p;
	params_defaults(&p);
	p.grid = 32;
	struct renderer *r = renderer_create(64, 64, ANTIALIAS_AUTO, err, sizeof(err));
	struct scene *s = scene_create(&p, err, sizeof(err));
	CHECK(r && s, "scene: %s", err);
	struct mesh m32, m37, ref;
	CHECK(frame_mesh(s, &p, r, &m32) == 0, "grid 32");
	p.grid = 37; /* what a knob does */
	CHECK(frame_mesh(s, &p, r, &m37) == 0, "grid 37 after 32");
	struct scene *fresh = scene_create(&p, err, sizeof(err));
	CHECK(fresh && frame_mesh(fresh, &p, r, &ref) == 0, "a scene made at grid 37: %s", err);
	printf("  grid 32: %u triangles; turned to 37: %u; made at 37: %u\n", m32.ntris, m37.ntris, ref.ntris);
	CHECK(m37.ntris != m32.ntris, "the mesh changed with the grid");
	CHECK(same_mesh(&m37, &ref), "turned to 37 extracts what a grid-37 scene does");

	/* later frames of the same field: time passes (the camera orbits), the
	 * field does not scroll: no extraction, the same mesh */
	unsigned long long n0 = extractions(s);
	struct mesh later, amp, amp_ref;
	CHECK(frame_mesh_at(s, &p, r, &later, 2.5f) == 0, "a later frame");
	CHECK(extractions(s) == n0, "a later frame of a static field extracts nothing (%llu -> %llu extractions)", n0,
	      extractions(s));
	CHECK(same_mesh(&later, &m37), "a later frame keeps the mesh");
	/* a knob turns a term of the field: extracted again, as a scene made
	 * with it extracts */
	p.noise_amp *= 1.5f;
	CHECK(frame_mesh_at(s, &p, r, &amp, 3.0f) == 0, "noise_amp turned");
	CHECK(extractions(s) == n0 + 1, "a turned term extracts again (%llu -> %llu extractions)", n0, extractions(s));
	struct scene *fresh_amp = scene_create(&p, err, sizeof(err));
	CHECK(fresh_amp && frame_mesh_at(fresh_amp, &p, r, &amp_ref, 3.0f) == 0, "a scene made with it: %s", err);
	printf("  noise_amp x1.5: %u triangles (was %u), a scene made with it %u\n", amp.ntris, m37.ntris, amp_ref.ntris);
	CHECK(!same_mesh(&amp, &m37), "the mesh changed with the term");
	CHECK(same_mesh(&amp, &amp_ref), "turned, it extracts what a scene made with it does");
	/* a scrolling field moves with time: every frame extracts */
	p.scroll_speed = 1.0f;
	CHECK(frame_mesh_at(s, &p, r, &later, 3.0f) == 0 && frame_mesh_at(s, &p, r, &later, 4.0f) == 0, "scrolling");
	CHECK(extractions(s) == n0 + 3, "a scrolling field extracts every frame (%llu extractions, want %llu)",
	      extractions(s), n0 + 3);
	/* an edit file rewritten between frames (a road moved, the file a
	 * byte longer: its key changes within the same second): reloaded and
	 * extracted again, the mesh a scene made with the new file extracts */
	p.scroll_speed = 0.0f;
	char dir[] = "/tmp/isoterra-scene-grid-XXXXXX", csv[96];
	CHECK(mkdtemp(dir) != NULL, "temporary directory");
	snprintf(csv, sizeof(csv), "%s/road.csv", dir);
	struct mesh road1, road2, road_ref;
	memset(&road2, 0, sizeof(road2));
	memset(&road_ref, 0, sizeof(road_ref));
	CHECK(write_road(csv, 0.0f) == 0, "write %s", csv);
	snprintf(p.curves, sizeof(p.curves), "%s", csv);
	CHECK(frame_mesh_at(s, &p, r, &road1, 5.0f) == 0, "with the road");
	unsigned long long n1 = extractions(s);
	CHECK(write_road(csv, 1.25f) == 0, "rewrite %s", csv);
	CHECK(frame_mesh_at(s, &p, r, &road2, 5.5f) == 0, "the road moved");
	CHECK(extractions(s) == n1 + 1, "a rewritten edit file extracts again (%llu -> %llu extractions)", n1,
	      extractions(s));
	struct scene *fresh_road = scene_create(&p, err, sizeof(err));
	CHECK(fresh_road && frame_mesh_at(fresh_road, &p, r, &road_ref, 5.5f) == 0, "a scene made with it: %s", err);
	printf("  the road moved: %u triangles (was %u), a scene made with the new file %u\n", road2.ntris, road1.ntris,
	       road_ref.ntris);
	CHECK(!same_mesh(&road2, &road1), "the mesh changed with the file");
	CHECK(same_mesh(&road2, &road_ref), "reloaded, it extracts what a scene made with the new file does");
	scene_destroy(fresh_road);
	mesh_free(&road1);
	mesh_free(&road2);
	mesh_free(&road_ref);
	unlink(csv);
	rmdir(dir);
	mesh_free(&later);
	mesh_free(&amp);
	mesh_free(&amp_ref);
	scene_destroy(fresh_amp);
	mesh_free(&m32);
	mesh_free(&m37);
	mesh_free(&ref);
	scene_destroy(fresh);
	scene_destroy(s);
	renderer_destroy(r);
	platform_close(plat);
	return tc_done("test_scene_grid");
}
