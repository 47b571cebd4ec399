/* isoterra — a knob that turns --grid: the volume scene extracts at the new
 * grid, the same mesh a scene made at that grid extracts (not the old
 * grid's mesh under the new name). */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <string.h>

/* One frame of scene s at p's grid; its mesh into *m. */
static int frame_mesh(struct scene *s, struct params *p, struct renderer *r, struct mesh *m)
{
	char err[512] = "";
	struct scene_frame sf = { .index = 0, .r = r, .w = 64, .h = 64 };
	if (s->ops->frame(s, p, &sf, err, sizeof(err)) < 0) {
		fprintf(stderr, "frame: %s\n", err);
		return -1;
	}
	return s->ops->read_mesh(s, m);
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
	CHECK(m37.ntris == ref.ntris && m37.nverts == ref.nverts &&
		      !memcmp(m37.pos, ref.pos, sizeof(float) * 3 * ref.nverts) &&
		      !memcmp(m37.idx, ref.idx, sizeof(uint32_t) * 3 * ref.ntris),
	      "turned to 37 extracts what a grid-37 scene does");
	mesh_free(&m32);
	mesh_free(&m37);
	mesh_free(&ref);
	scene_destroy(fresh);
	scene_destroy(s);
	renderer_destroy(r);
	platform_close(plat);
	return tc_done("test_scene_grid");
}
