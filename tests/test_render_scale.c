/* isoterra — the governor's render scale (app/render/upscale.c): the
 * volume drawn at scale 0.5 and upscaled stays close to the full-size
 * frame (PSNR), is closer to it than a nearest-neighbour upscale of the
 * is not the full-size frame itself (the
 * scale took effect), and scale 1 gives back the full-size frame exactly. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_fixture.h"
#include "tcheck.h"

#define W 320
#define H 240

static double psnr(const uint8_t *a, const uint8_t *b)
{
	double se = 0;
	for (int i = 0; i < W * H * 4; i++)
		if (i % 4 != 3)
			se += (double)(a[i] - b[i]) * (a[i] - b[i]);
	double mse = se / (W * H * 3.0);
	return mse > 0 ? 10 * log10(255.0 * 255.0 / mse) : 99;
}

static int frame(struct renderer *r, const struct pipeline_draw *d, const struct params *p, const struct grid *g,
		 float scale, struct image *img)
{
	char err[256];
	if (renderer_set_scale(r, scale, err, sizeof(err)) < 0) {
		fprintf(stderr, "%s\n", err);
		return -1;
	}
	struct camera c;
	camera_orbit(&c, p, g, 0.0f, (float)W / H);
	if (renderer_draw(r, d, &c, p) < 0)
		return -1;
	return renderer_read(r, img);
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
	struct renderer *r = NULL;
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0 || !(r = renderer_create(W, H, ANTIALIAS_AUTO, err, sizeof(err))) ||
	    fixture_run(ft.pl, &p) < 0) {
		fprintf(stderr, "setup: %s\n", err);
		return 1;
	}
	struct pipeline *pl = ft.pl;
	struct pipeline_draw d;
	pipeline_draw_info(pl, &d);
	struct image full = { 0 }, half = { 0 }, again = { 0 };
	CHECK(frame(r, &d, &p, &g, 1.0f, &full) == 0, "full-size frame");
	CHECK(frame(r, &d, &p, &g, 0.5f, &half) == 0, "half-scale frame");
	CHECK(frame(r, &d, &p, &g, 1.0f, &again) == 0, "full-size frame again");
	if (full.rgba && half.rgba && again.rgba) {
		/* for scale: the full-size frame with its resolution halved by
		 * pixel doubling (each 2x2 block its top-left pixel) */
		uint8_t *nn = malloc((size_t)W * H * 4);
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				memcpy(nn + ((size_t)y * W + x) * 4, full.rgba + ((size_t)(y & ~1) * W + (x & ~1)) * 4, 4);
		double q_half = psnr(full.rgba, half.rgba), q_nn = psnr(full.rgba, nn);
		printf("PSNR vs the full-size frame: upscaled half-scale %.2f dB, nearest-neighbour of full %.2f dB\n",
		       q_half, q_nn);
		CHECK(q_half >= 22.0, "upscaled half-scale frame close to the full-size one (%.2f dB)", q_half);
		CHECK(q_half > q_nn, "upscaled %.2f dB beats pixel doubling %.2f dB", q_half, q_nn);
		CHECK(q_half < 60.0, "the scale took effect (%.2f dB: not the full-size frame)", q_half);
		CHECK(psnr(full.rgba, again.rgba) >= 99, "scale 1 again gives the full-size frame exactly");
		int lo = 255, hi = 0;
		for (int i = 0; i < W * H * 4; i += 4) {
			lo = half.rgba[i + 1] < lo ? half.rgba[i + 1] : lo;
			hi = half.rgba[i + 1] > hi ? half.rgba[i + 1] : hi;
		}
		CHECK(hi - lo > 64, "the upscaled frame has content (green %d..%d)", lo, hi);
		free(nn);
	}
	free(full.rgba);
	free(half.rgba);
	free(again.rgba);
	renderer_destroy(r);
	fixture_terrain_close(&ft);
	platform_close(plat);
	return tc_done("render_scale");
}
