/* isoterra — rendered output: the default scene matches the golden image
 * within a stated tolerance, rendering is deterministic, and the three
 * compaction methods draw the same picture.
 *
 * Tolerance: mean absolute RGB difference <= 2.0 (of 255) and at most 1% of
 * pixels differing by more than 48 in any channel.  That absorbs driver
 * rasterisation/precision differences (llvmpipe versions, a real GPU) but
 * not a changed terrain, camera or shading.
 * ISOTERRA_UPDATE_GOLDEN=1 rewrites the golden image. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <string.h>

static void golden_params(struct params *p)
{
	params_defaults(p);
	snprintf(p->size, sizeof(p->size), "160x120");
	p->grid = 48;
	p->count = 1;
	/* the golden image's smoothing, whatever the driver's auto picks */
	p->antialias = ANTIALIAS_MSAA;
}

/* Pixels that differ by more than 8 in any channel. */
static int changed(const struct image *a, const struct image *b)
{
	int n = 0;
	for (int i = 0; a->rgba && b->rgba && i < a->width * a->height; i++)
		for (int c = 0; c < 3; c++)
			if (abs(a->rgba[4 * i + c] - b->rgba[4 * i + c]) > 8) {
				n++;
				break;
			}
	return n;
}

/* Water waves: layered fBm normals move with time; without octaves the
 * water is a still mirror (nothing else in the frame depends on time). */
static void test_water_waves(void)
{
	struct params p;
	golden_params(&p);
	p.water_level = 1.0f; /* much of the box under water */
	p.cam_spin = 0.0f;
	char err[512] = "";
	struct image w0 = { 0 }, w1 = { 0 }, f0 = { 0 }, f1 = { 0 };
	CHECK(render_to_image(&p, &w0, err, sizeof(err)) == 0, "water t=0: %s", err);
	p.time = 1.0f;
	CHECK(render_to_image(&p, &w1, err, sizeof(err)) == 0, "water t=1: %s", err);
	p.water_octaves = 0;
	CHECK(render_to_image(&p, &f1, err, sizeof(err)) == 0, "mirror t=1: %s", err);
	p.time = 0.0f;
	CHECK(render_to_image(&p, &f0, err, sizeof(err)) == 0, "mirror t=0: %s", err);
	int moving = changed(&w0, &w1), still = changed(&f0, &f1), waves = changed(&w1, &f1);
	printf("water: %d pixels move in one second, %d without waves; waves change %d pixels\n", moving, still, waves);
	CHECK(moving > 200, "the waves move (%d pixels changed in one second)", moving);
	CHECK(still == 0, "without wave octaves nothing moves (%d pixels)", still);
	CHECK(waves > 400, "the waves change the water (%d pixels)", waves);
	image_free(&w0);
	image_free(&w1);
	image_free(&f0);
	image_free(&f1);
}

/* The OSD's font scale on small screens: the largest that keeps the box
 * (cols * 6 + 8 font pixels, 2 of margin each side) inside the width,
 * from the height's (1 below 300 rows, 2, 3 from 600, 4 from 1080). */
static void test_osd_fit(void)
{
	static const struct { int w, h, cols, want; } cases[] = {
		{ 320, 240, 40, 1 },  /* a 320x240 handheld: 248 px of box */
		{ 480, 320, 40, 1 },  /* 2x would be 496 px, wider than the panel */
		{ 480, 320, 20, 2 },  /* a short name: 256 px at 2x */
		{ 1280, 720, 40, 3 }, /* as before: 744 px */
		{ 1920, 1080, 40, 4 },
		{ 800, 1280, 40, 3 }, /* a portrait panel: 4x (992 px) is too wide */
		{ 100, 2000, 40, 1 }, /* never below 1 */
	};
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		int s = osd_fit_scale(cases[i].w, cases[i].h, cases[i].cols);
		CHECK(s == cases[i].want, "OSD scale at %dx%d, %d columns: %d, want %d", cases[i].w, cases[i].h,
		      cases[i].cols, s, cases[i].want);
		if (s > 1)
			CHECK((cases[i].cols * 6 + 8) * s <= cases[i].w - 4 * s, "the box fits at %dx%d", cases[i].w,
			      cases[i].h);
	}
}

int main(void)
{
	struct platform *plat = fixture_open();
	const char *src = getenv("ISOTERRA_SRC");
	char golden[1024];
	snprintf(golden, sizeof(golden), "%s/tests/golden/default_160x120.png", src ? src : ".");
	struct params p;
	golden_params(&p);
	char err[512] = "";
	struct image a = { 0 }, b = { 0 }, ref = { 0 };
	CHECK(render_to_image(&p, &a, err, sizeof(err)) == 0, "render: %s", err);
	CHECK(render_to_image(&p, &b, err, sizeof(err)) == 0, "render again: %s", err);
	if (a.rgba && b.rgba)
		CHECK(!memcmp(a.rgba, b.rgba, (size_t)a.width * a.height * 4), "same parameters, same image");

	if (getenv("ISOTERRA_UPDATE_GOLDEN") && a.rgba) {
		CHECK(image_write_png(&a, golden, err, sizeof(err)) == 0, "write golden: %s", err);
		printf("golden image updated: %s\n", golden);
	}
	CHECK(image_read_png(&ref, golden, err, sizeof(err)) == 0, "golden image: %s", err);
	if (a.rgba && ref.rgba) {
		struct image_diff d;
		CHECK(image_compare(&a, &ref, 48, &d) == 0, "compare sizes %dx%d vs %dx%d", a.width, a.height, ref.width,
		      ref.height);
		printf("golden: mean abs %.3f, rmse %.3f, %.3f%% pixels over 48, max %d, PSNR %.1f dB\n", d.mean_abs, d.rmse,
		       100.0 * d.frac_over, d.max_abs, d.psnr);
		CHECK(d.mean_abs <= 2.0, "mean abs difference %.3f > 2.0", d.mean_abs);
		CHECK(d.frac_over <= 0.01, "%.3f%% of pixels differ by more than 48", 100.0 * d.frac_over);
		/* the image is a terrain, not a blank sky: many distinct colours */
		int sky = 0;
		for (int i = 0; i < a.width * a.height; i++)
			sky += abs(a.rgba[4 * i] - 158) < 3 && abs(a.rgba[4 * i + 1] - 189) < 3;
		CHECK(sky < a.width * a.height * 85 / 100, "image is almost all sky (%d of %d pixels)", sky, a.width * a.height);
	}
	/* the other compaction methods draw the same terrain (they compute no
	 * ambient occlusion and no sun shadows, so compare without them) */
	struct params p0 = p;
	p0.ao_rays = 0;
	p0.shadows = 0.0f;
	image_free(&a);
	CHECK(render_to_image(&p0, &a, err, sizeof(err)) == 0, "render without AO: %s", err);
	for (int m = 1; m <= 2; m++) {
		struct params q = p0;
		q.compaction = m;
		struct image c = { 0 };
		CHECK(render_to_image(&q, &c, err, sizeof(err)) == 0, "render method %d: %s", m, err);
		if (c.rgba && a.rgba) {
			struct image_diff d;
			image_compare(&a, &c, 48, &d);
			printf("method %d vs histopyramid: mean abs %.3f, %.3f%% over 48\n", m, d.mean_abs, 100.0 * d.frac_over);
			CHECK(d.mean_abs <= 0.5 && d.frac_over <= 0.002, "method %d draws another picture (mean %.3f)", m,
			      d.mean_abs);
		}
		image_free(&c);
	}
	image_free(&a);
	image_free(&b);
	image_free(&ref);
	test_water_waves();
	test_osd_fit();
	platform_close(plat);
	return tc_done("render");
}
