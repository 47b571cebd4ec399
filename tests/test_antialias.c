/* isoterra — edge smoothing (--antialias, app/render): the volume drawn at
 * 320x240 with no smoothing, with the filter after the frame (fxaa.frag)
 * and with 4x multisampling, each against the same view drawn at 1280x960
 * without smoothing and averaged over 4x4 blocks (16 samples a pixel: the
 * independent reference).  On the pixels of the edges (a 4x4 block of the
 * reference whose samples disagree in luma by more than 64), both
 * smoothings come closer to the reference than no smoothing; the filter
 * leaves most pixels as they were; auto picks the filter on a software
 * rasterizer and multisampling on a GPU. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_fixture.h"
#include "tcheck.h"

#define W 320
#define H 240
#define SS 4

static int frame(int antialias, int w, int h, const struct pipeline_draw *d, const struct params *p,
		 const struct grid *g, struct image *img, int *used)
{
	char err[256];
	struct renderer *r = renderer_create(w, h, antialias, err, sizeof(err));
	if (!r) {
		fprintf(stderr, "renderer %dx%d: %s\n", w, h, err);
		return -1;
	}
	*used = renderer_antialias(r);
	struct camera c;
	camera_orbit(&c, p, g, 0.0f, (float)w / h);
	int rc = renderer_draw(r, d, &c, p) < 0 || renderer_read(r, img) < 0 ? -1 : 0;
	renderer_destroy(r);
	return rc;
}

static double luma(const uint8_t *px)
{
	return 0.299 * px[0] + 0.587 * px[1] + 0.114 * px[2];
}

int main(void)
{
	struct platform *plat = fixture_open();
	struct params p;
	params_defaults(&p);
	p.grid = 48;
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "";
	struct fixture_terrain ft;
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0 || fixture_run(ft.pl, &p) < 0) {
		fprintf(stderr, "setup: %s\n", err);
		return 1;
	}
	struct pipeline_draw d;
	pipeline_draw_info(ft.pl, &d);
	struct image off = { 0 }, fx = { 0 }, ms = { 0 }, au = { 0 }, big = { 0 };
	int u_off, u_fx, u_ms, u_au, u_big;
	CHECK(frame(ANTIALIAS_OFF, W, H, &d, &p, &g, &off, &u_off) == 0 && u_off == ANTIALIAS_OFF, "frame, no smoothing");
	CHECK(frame(ANTIALIAS_FXAA, W, H, &d, &p, &g, &fx, &u_fx) == 0 && u_fx == ANTIALIAS_FXAA, "frame, the filter");
	CHECK(frame(ANTIALIAS_MSAA, W, H, &d, &p, &g, &ms, &u_ms) == 0, "frame, multisampling (%s)",
	      u_ms == ANTIALIAS_MSAA ? "4 samples" : "not offered: the filter");
	CHECK(frame(ANTIALIAS_AUTO, W, H, &d, &p, &g, &au, &u_au) == 0, "frame, auto");
	int want = gpu_software_rasterizer() ? ANTIALIAS_FXAA : ANTIALIAS_MSAA;
	CHECK(u_au == want || (want == ANTIALIAS_MSAA && u_au == u_ms), "auto is %s on this %s rasterizer (got %d)",
	      want == ANTIALIAS_FXAA ? "the filter" : "multisampling", gpu_software_rasterizer() ? "software" : "GPU", u_au);
	CHECK(frame(ANTIALIAS_OFF, W * SS, H * SS, &d, &p, &g, &big, &u_big) == 0, "reference frame %dx%d", W * SS,
	      H * SS);
	if (off.rgba && fx.rgba && ms.rgba && big.rgba) {
		double e_off = 0, e_fx = 0, e_ms = 0;
		int edges = 0, fx_same = 0;
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				double ref[3] = { 0, 0, 0 }, lo = 1e9, hi = -1e9;
				for (int j = 0; j < SS; j++)
					for (int i = 0; i < SS; i++) {
						const uint8_t *s = big.rgba + (((size_t)(y * SS + j) * W * SS) + x * SS + i) * 4;
						for (int k = 0; k < 3; k++)
							ref[k] += s[k] / (double)(SS * SS);
						lo = fmin(lo, luma(s));
						hi = fmax(hi, luma(s));
					}
				size_t o = ((size_t)y * W + x) * 4;
				fx_same += !memcmp(off.rgba + o, fx.rgba + o, 3);
				if (hi - lo <= 64)
					continue;
				edges++;
				for (int k = 0; k < 3; k++) {
					e_off += (off.rgba[o + k] - ref[k]) * (off.rgba[o + k] - ref[k]);
					e_fx += (fx.rgba[o + k] - ref[k]) * (fx.rgba[o + k] - ref[k]);
					e_ms += (ms.rgba[o + k] - ref[k]) * (ms.rgba[o + k] - ref[k]);
				}
			}
		double n = 3.0 * (edges ? edges : 1);
		e_off = sqrt(e_off / n);
		e_fx = sqrt(e_fx / n);
		e_ms = sqrt(e_ms / n);
		printf("edge pixels %d of %d; RMS difference from the 16-sample reference: none %.2f, filter %.2f, "
		       "multisampling %.2f; the filter left %.1f %% of all pixels as they were\n",
		       edges, W * H, e_off, e_fx, e_ms, 100.0 * fx_same / (W * H));
		CHECK(edges > W * H / 200, "the view has edges (%d pixels)", edges);
		CHECK(e_fx < 0.9 * e_off, "the filter is closer to the reference on the edges: %.2f vs %.2f", e_fx, e_off);
		CHECK(e_ms < 0.9 * e_off, "multisampling is closer to the reference on the edges: %.2f vs %.2f", e_ms, e_off);
		CHECK(fx_same > W * H / 2, "the filter leaves flat regions alone (%d of %d pixels unchanged)", fx_same, W * H);
	}
	free(off.rgba);
	free(fx.rgba);
	free(ms.rgba);
	free(au.rgba);
	free(big.rgba);
	fixture_terrain_close(&ft);
	platform_close(plat);
	return tc_done("antialias");
}
