/* isoterra — back faces culled where none can show (app/render/render.c,
 * renderer_begin).  A closed volume seen from outside is drawn the same
 * with its back faces culled as with every face drawn (the culling hides
 * nothing: the winding faces the air); an open volume, whose cut sides show
 * back faces (seen from below here), is drawn with none culled, and culling them there would
 * change the picture (the comparison can tell); culling the front faces
 * of the closed volume instead changes it too (the winding is not the
 * other way round). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "gpu_fixture.h"
#include "tcheck.h"

#define W 320
#define H 240

enum cull { AS_IS, NONE, BACK, FRONT };

/* the mesh alone, the renderer's culling as it set it or overridden */
static int mesh_frame(struct renderer *r, const struct pipeline_draw *d, const struct params *p, const struct grid *g,
		      enum cull cull, int *was_on, struct image *img)
{
	struct camera c;
	camera_orbit(&c, p, g, 0.0f, (float)W / H);
	if (renderer_begin(r, &c, p) < 0)
		return -1;
	*was_on = glIsEnabled(GL_CULL_FACE) == GL_TRUE;
	if (cull == NONE) {
		glDisable(GL_CULL_FACE);
	} else if (cull != AS_IS) {
		glEnable(GL_CULL_FACE);
		glCullFace(cull == BACK ? GL_BACK : GL_FRONT);
		glFrontFace(GL_CCW);
	}
	renderer_draw_mesh(r, d->vbo, d->indexed ? d->ibo : 0, d->indirect, d->indirect_offset, 0.0f, 0.0f);
	if (renderer_end(r) < 0)
		return -1;
	return renderer_read(r, img);
}

/* pixels whose colour differs by more than 24 in a channel */
static double differ(const struct image *a, const struct image *b)
{
	size_t n = 0;
	for (size_t i = 0; i < (size_t)W * H; i++)
		for (int k = 0; k < 3; k++)
			if (abs(a->rgba[i * 4 + k] - b->rgba[i * 4 + k]) > 24) {
				n++;
				break;
			}
	return (double)n / (double)(W * H);
}

static void volume(bool closed)
{
	struct params p;
	params_defaults(&p);
	p.grid = 48;
	p.closed = closed;
	/* from below: an open volume's cut bottom shows the surface's back
	 * faces, a closed one its floor */
	p.cam_pitch = -30.0f;
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "";
	struct fixture_terrain ft;
	struct renderer *r = NULL;
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0 ||
	    !(r = renderer_create(W, H, ANTIALIAS_OFF, err, sizeof(err))) || fixture_run(ft.pl, &p) < 0) {
		fprintf(stderr, "setup: %s\n", err);
		CHECK(0, "setup (closed %d)", closed);
		return;
	}
	struct pipeline_draw d;
	pipeline_draw_info(ft.pl, &d);
	struct image as_is = { 0 }, none = { 0 }, other = { 0 };
	int on = 0, ignored = 0;
	CHECK(mesh_frame(r, &d, &p, &g, AS_IS, &on, &as_is) == 0, "frame");
	CHECK(mesh_frame(r, &d, &p, &g, NONE, &ignored, &none) == 0, "frame, every face");
	CHECK(mesh_frame(r, &d, &p, &g, closed ? FRONT : BACK, &ignored, &other) == 0, "frame, culled");
	if (as_is.rgba && none.rgba && other.rgba) {
		double same = differ(&as_is, &none), changed = differ(&none, &other);
		printf("%s volume: culling %s; differs from every face drawn in %.5f of the pixels; %s culled: %.5f\n",
		       closed ? "closed" : "open", on ? "on" : "off", same, closed ? "front faces" : "back faces", changed);
		CHECK(on == closed, "culling %s for a%s volume", on ? "on" : "off", closed ? " closed" : "n open");
		CHECK(same <= 0.0005, "%s volume: %.5f of the pixels differ from every face drawn", closed ? "closed" : "open",
		      same);
		/* the other culling visibly changes it: the comparison can tell */
		CHECK(changed > 0.01, "%s culled: only %.5f of the pixels differ", closed ? "front faces" : "back faces",
		      changed);
	}
	free(as_is.rgba);
	free(none.rgba);
	free(other.rgba);
	renderer_destroy(r);
	fixture_terrain_close(&ft);
}

int main(void)
{
	struct platform *plat = fixture_open();
	volume(true);
	volume(false);
	platform_close(plat);
	return tc_done("cull");
}
