/* isoterra — the governor's render scale (app/render/upscale.c): the
 * volume drawn at scale 0.5 and upscaled stays close to the full-size
 * frame (PSNR), is closer to it than a nearest-neighbour upscale of the
 * full-size frame, is not the full-size frame itself (the scale took
 * effect), and scale 1 gives back the full-size frame exactly.  Against
 * the same view drawn by a renderer of half the size (the low-resolution
 * frame itself): every upscaled pixel lies within its four nearest texels
 * (nothing rings), and the upscale is crisper than a bilinear one of that
 * frame computed here (edge energy).
 *
 * Also the terrain's three variants (render.c): a mesh said to stay
 * beyond DETAIL_FINE_SHARE * DETAIL_RANGE is drawn without the finer
 * detail scale, one beyond DETAIL_RANGE without the detail normals.  Seen
 * from afar (all of the volume beyond that range) the three give the same
 * frame; from the middle distance, the one without the finer scale gives
 * the frame of both scales, and differs from the far one; from near, they
 * differ, and the governor's two steps draw a near mesh as the variant
 * without the finer scale and as the far variant do.
 * And the depth
 * pre-pass (render.h): the volume's frame with it is the frame without it,
 * pixel for pixel. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "abi.h"
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

/* edge energy: mean absolute difference between neighbouring pixels
 * (green), across and along rows */
static double edge_energy(const uint8_t *a)
{
	double sum = 0;
	for (int y = 0; y + 1 < H; y++)
		for (int x = 0; x + 1 < W; x++) {
			const uint8_t *p = a + ((size_t)y * W + x) * 4 + 1;
			sum += abs(p[0] - p[4]) + abs(p[0] - p[W * 4]);
		}
	return sum / ((W - 1.0) * (H - 1.0));
}

/* the half-size frame lo (W/2 x H/2) bilinearly upscaled to W x H, with
 * the same texel centres as the GPU's upscale */
static void bilinear(const uint8_t *lo, uint8_t *out)
{
	const int w = W / 2, h = H / 2;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			float sx = (x + 0.5f) * 0.5f - 0.5f, sy = (y + 0.5f) * 0.5f - 0.5f;
			sx = sx < 0 ? 0 : sx > w - 1 ? (float)(w - 1) : sx;
			sy = sy < 0 ? 0 : sy > h - 1 ? (float)(h - 1) : sy;
			int x0 = (int)sx, y0 = (int)sy, x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
			float fx = sx - x0, fy = sy - y0;
			for (int c = 0; c < 4; c++) {
				float a = lo[((size_t)y0 * w + x0) * 4 + c], b = lo[((size_t)y0 * w + x1) * 4 + c];
				float d = lo[((size_t)y1 * w + x0) * 4 + c], e = lo[((size_t)y1 * w + x1) * 4 + c];
				float v = (a + (b - a) * fx) * (1 - fy) + (d + (e - d) * fx) * fy;
				out[((size_t)y * W + x) * 4 + c] = (uint8_t)(v + 0.5f);
			}
		}
}

/* pixels of up (W x H) outside the range of their four nearest texels of
 * lo (W/2 x H/2), by more than 2 (rounding) */
static int ringing(const uint8_t *up, const uint8_t *lo)
{
	const int w = W / 2, h = H / 2;
	int n = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			int x0 = (x - 1) / 2, y0 = (y - 1) / 2;
			x0 = x0 < 0 ? 0 : x0;
			y0 = y0 < 0 ? 0 : y0;
			int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
			for (int c = 0; c < 3; c++) {
				int v[4] = { lo[((size_t)y0 * w + x0) * 4 + c], lo[((size_t)y0 * w + x1) * 4 + c],
					     lo[((size_t)y1 * w + x0) * 4 + c], lo[((size_t)y1 * w + x1) * 4 + c] };
				int mn = v[0], mx = v[0];
				for (int k = 1; k < 4; k++) {
					mn = v[k] < mn ? v[k] : mn;
					mx = v[k] > mx ? v[k] : mx;
				}
				int u = up[((size_t)y * W + x) * 4 + c];
				if (u < mn - 2 || u > mx + 2) {
					n++;
					break;
				}
			}
		}
	return n;
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

/* the mesh alone (no water), drawn by the variant for meshes dist away */
static int mesh_frame(struct renderer *r, const struct pipeline_draw *d, const struct params *p, const struct grid *g,
		      float dist, struct image *img)
{
	struct camera c;
	camera_orbit(&c, p, g, 0.0f, (float)W / H);
	if (renderer_begin(r, &c, p) < 0)
		return -1;
	renderer_draw_mesh(r, d->vbo, d->indexed ? d->ibo : 0, d->indirect, d->indirect_offset, 0.0f, dist);
	if (renderer_end(r) < 0)
		return -1;
	return renderer_read(r, img);
}

/* the eye's distance to the volume's box */
static float eye_box_distance(const struct camera *c, const struct grid *g)
{
	float lo[3], hi[3];
	grid_box(g, lo, hi);
	return camera_box_distance(c, lo, hi);
}

/* pixels whose colour differs between two frames */
static int pixels_moved(const unsigned char *a, const unsigned char *b)
{
	int moved = 0;
	for (int i = 0; i < W * H * 4; i += 4)
		moved += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2];
	return moved;
}

/* the same frame from two programs that should draw it alike: within a
 * rounding of the driver's (pixel for pixel on llvmpipe) */
static bool frames_alike(const struct image *a, const struct image *b)
{
	return psnr(a->rgba, b->rgba) >= 60.0 && pixels_moved(a->rgba, b->rgba) <= W * H / 1000;
}

/* the three variants compared, from near, from the middle distance (the
 * finer scale faded out) and from afar (all the detail faded out) */
static void detail_variants(struct renderer *r, const struct pipeline_draw *d, const struct params *p_in,
			    const struct grid *g)
{
	struct params p = *p_in;
	const float fine = (float)(DETAIL_FINE_SHARE * DETAIL_RANGE);
	/* near: the eye just over the terrain (the finer scale, within
	 * DETAIL_FINE_SHARE * DETAIL_RANGE, changes a fifth of the pixels
	 * from here; from 0.6, where the coarser changes a third, none); the
	 * middle distance: the first orbit distance from 0.6 on that puts the
	 * whole volume between the two ranges, where the coarser scale changes
	 * 1 % of the pixels */
	float dists[3] = { 0.08f, -1.0f, 1.5f };
	for (float cd = 0.6f; cd < 1.5f && dists[1] < 0; cd += 0.02f) {
		struct camera c;
		p.cam_dist = cd;
		p.cam_yaw = 35.0f;
		p.cam_pitch = 17.0f;
		camera_orbit(&c, &p, g, 0.0f, (float)W / H);
		float dd = eye_box_distance(&c, g);
		if (dd >= fine + 0.5f && dd < DETAIL_RANGE - 8.0f)
			dists[1] = cd;
	}
	CHECK(dists[1] > 0, "an orbit distance puts the volume between %.2f and %.2f units", fine, DETAIL_RANGE);
	for (int view = 0; view < 3; view++) {
		if (dists[view] < 0)
			continue;
		p.cam_dist = dists[view];
		p.cam_yaw = 35.0f;
		p.cam_pitch = 17.0f;
		struct camera c;
		camera_orbit(&c, &p, g, 0.0f, (float)W / H);
		float dd = eye_box_distance(&c, g);
		/* the mesh said to come to 0 (both scales), dd (what the world
		 * says of it) and never (the far variant) */
		struct image a = { 0 }, m = { 0 }, b = { 0 };
		CHECK(mesh_frame(r, d, &p, g, 0.0f, &a) == 0, "near variant frame");
		CHECK(mesh_frame(r, d, &p, g, dd, &m) == 0, "frame of a mesh %.1f units away", dd);
		CHECK(mesh_frame(r, d, &p, g, 1e9f, &b) == 0, "far variant frame");
		if (a.rgba && m.rgba && b.rgba) {
			int am = pixels_moved(a.rgba, m.rgba), ab = pixels_moved(a.rgba, b.rgba),
			    mb = pixels_moved(m.rgba, b.rgba);
			printf("detail variants, eye %.1f units from the volume: pixels that differ: both scales vs its "
			       "own variant %d, vs none %d; its own vs none %d (%.2f dB)\n",
			       dd, am, ab, mb, psnr(a.rgba, b.rgba));
			if (view == 2) {
				CHECK(dd > DETAIL_RANGE, "the far view is beyond the detail range (%.1f)", dd);
				CHECK(frames_alike(&a, &b) && frames_alike(&m, &b),
				      "from afar the variant without detail draws the same frame (%d, %d pixels)", ab, mb);
			} else if (view == 1) {
				CHECK(dd >= fine && dd < DETAIL_RANGE, "the middle view is between the ranges (%.1f)", dd);
				CHECK(frames_alike(&a, &m),
				      "from the middle distance the variant without the finer scale draws the frame of "
				      "both (%d pixels)", am);
				CHECK(mb >= W * H / 200, "from the middle distance the coarser scale shows (%d pixels)", mb);
			} else {
				CHECK(dd < fine, "the near view is within the finer scale's range (%.1f)", dd);
				CHECK(ab >= W * H / 20, "from near the detail shows (%d pixels)", ab);
				/* the governor's two detail steps: a near mesh drawn
				 * without the finer scale (as by a mesh beyond its
				 * range: the same program), then with the far
				 * variant, then the detail back */
				struct image one = { 0 }, mid = { 0 }, off = { 0 }, on = { 0 };
				CHECK(mesh_frame(r, d, &p, g, fine, &mid) == 0, "mesh at the finer scale's range");
				renderer_set_detail(r, 1);
				CHECK(mesh_frame(r, d, &p, g, 0.0f, &one) == 0, "near mesh, the coarser scale only");
				renderer_set_detail(r, 0);
				CHECK(mesh_frame(r, d, &p, g, 0.0f, &off) == 0, "near mesh, detail off");
				renderer_set_detail(r, 2);
				CHECK(mesh_frame(r, d, &p, g, 0.0f, &on) == 0, "near mesh, detail on again");
				if (one.rgba && mid.rgba && off.rgba && on.rgba) {
					int fine_px = pixels_moved(a.rgba, one.rgba);
					printf("  the finer scale: %d pixels\n", fine_px);
					CHECK(fine_px >= W * H / 50, "from near the finer scale shows (%d pixels)", fine_px);
					CHECK(!memcmp(one.rgba, mid.rgba, (size_t)W * H * 4),
					      "the coarser scale only: a near mesh is drawn as one beyond the finer "
					      "scale's range, pixel for pixel");
					CHECK(!memcmp(off.rgba, b.rgba, (size_t)W * H * 4),
					      "detail off: a near mesh is drawn as a far one, pixel for pixel");
					CHECK(!memcmp(on.rgba, a.rgba, (size_t)W * H * 4), "detail on again: the near frame back");
				}
				free(one.rgba);
				free(mid.rgba);
				free(off.rgba);
				free(on.rgba);
			}
		}
		free(a.rgba);
		free(m.rgba);
		free(b.rgba);
	}
}

/* the volume's frame with the depth pre-pass and without */
static void prepass_same(struct renderer *r, const struct pipeline_draw *d, const struct params *p,
			 const struct grid *g)
{
	struct image with = { 0 }, without = { 0 };
	bool was = renderer_prepass(r);
	renderer_set_prepass(r, true);
	CHECK(frame(r, d, p, g, 1.0f, &with) == 0, "frame with the depth pre-pass");
	renderer_set_prepass(r, false);
	CHECK(frame(r, d, p, g, 1.0f, &without) == 0, "frame without the depth pre-pass");
	renderer_set_prepass(r, was);
	if (with.rgba && without.rgba) {
		int moved = 0;
		for (int i = 0; i < W * H * 4; i += 4)
			moved += memcmp(with.rgba + i, without.rgba + i, 3) != 0;
		printf("depth pre-pass: %d pixels differ from the frame without it\n", moved);
		CHECK(moved <= W * H / 2000, "the depth pre-pass changes no picture (%d pixels differ)", moved);
	}
	free(with.rgba);
	free(without.rgba);
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
	struct renderer *r = NULL, *rl = NULL;
	/* edge smoothing off: the subject is the upscale, and the half-size
	 * renderer must draw what the scaled one draws */
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0 ||
	    !(r = renderer_create(W, H, ANTIALIAS_OFF, err, sizeof(err))) ||
	    !(rl = renderer_create(W / 2, H / 2, ANTIALIAS_OFF, err, sizeof(err))) || fixture_run(ft.pl, &p) < 0) {
		fprintf(stderr, "setup: %s\n", err);
		return 1;
	}
	struct pipeline *pl = ft.pl;
	struct pipeline_draw d;
	pipeline_draw_info(pl, &d);
	struct image full = { 0 }, half = { 0 }, again = { 0 }, lo = { 0 };
	CHECK(frame(r, &d, &p, &g, 1.0f, &full) == 0, "full-size frame");
	CHECK(frame(rl, &d, &p, &g, 1.0f, &lo) == 0, "half-size frame");
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
		double e_full = edge_energy(full.rgba), e_half = edge_energy(half.rgba);
		printf("edge energy: full-size %.3f, upscaled half-scale %.3f (%.3f of it)\n", e_full, e_half,
		       e_half / e_full);
		if (lo.rgba) {
			uint8_t *bl = malloc((size_t)W * H * 4);
			bilinear(lo.rgba, bl);
			double e_bl = edge_energy(bl);
			int ring = ringing(half.rgba, lo.rgba);
			printf("half-size frame upscaled here: bilinear edge energy %.3f; upscaled pixels outside their "
			       "four texels: %d\n",
			       e_bl, ring);
			CHECK(ring <= W * H / 1000, "nothing rings: %d pixels outside their four nearest texels", ring);
			CHECK(e_half > e_bl * 1.02, "crisper than bilinear: edge energy %.3f vs %.3f", e_half, e_bl);
			CHECK(psnr(half.rgba, bl) >= 25.0, "close to the bilinear upscale of the half-size frame (%.2f dB)",
			      psnr(half.rgba, bl));
			free(bl);
		}
		CHECK(q_half >= 22.0, "upscaled half-scale frame close to the full-size one (%.2f dB)", q_half);
		CHECK(q_half > q_nn, "upscaled %.2f dB beats pixel doubling %.2f dB", q_half, q_nn);
		CHECK(q_half < 60.0, "the scale took effect (%.2f dB: not the full-size frame)", q_half);
		CHECK(psnr(full.rgba, again.rgba) >= 99, "scale 1 again gives the full-size frame exactly");
		int g_lo = 255, g_hi = 0;
		for (int i = 0; i < W * H * 4; i += 4) {
			g_lo = half.rgba[i + 1] < g_lo ? half.rgba[i + 1] : g_lo;
			g_hi = half.rgba[i + 1] > g_hi ? half.rgba[i + 1] : g_hi;
		}
		CHECK(g_hi - g_lo > 64, "the upscaled frame has content (green %d..%d)", g_lo, g_hi);
		free(nn);
	}
	CHECK(renderer_set_scale(r, 1.0f, err, sizeof(err)) == 0, "scale 1: %s", err);
	detail_variants(r, &d, &p, &g);
	prepass_same(r, &d, &p, &g);
	free(full.rgba);
	free(half.rgba);
	free(again.rgba);
	free(lo.rgba);
	renderer_destroy(r);
	renderer_destroy(rl);
	fixture_terrain_close(&ft);
	platform_close(plat);
	return tc_done("render_scale");
}
