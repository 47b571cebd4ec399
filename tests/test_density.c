/* isoterra — density function tests.
 *
 * CPU part (always): half-float conversion, noise tables (determinism per
 * seed, rotations), improved Perlin noise against Perlin's formula on its
 * hashed lattice gradients, the hash's spread, texture noise, Worley, the
 * analytic test fields, the sign convention, hard floor, scrolling, flat
 * spot, terrace continuity.
 *
 * GPU part (needs an EGL surfaceless GLES 3.1 context, e.g. Mesa llvmpipe):
 * the density pass of the pipeline against density_ref_volume() for every
 * test field and every fractal family at grids 17 and 33.
 *   noise=alu:     max |gpu - cpu| <= 1e-4 * scale  (scale = field_scale for
 *                  the test fields, max |density| for the terrain); llvmpipe
 *                  measures 0 .. 2e-7 relative.
 *   noise=texture: the GPU filters the octaves above rotated_octaves with the
 *                  sampler's trilinear filter, the CPU with exact fp32
 *                  weights.  GPUs keep only ~8 fractional bits of the filter
 *                  weights, so up to ~1/256 of a texel step per octave may
 *                  differ: tolerance 2e-2 * noise_amp.  (llvmpipe filters
 *                  RGBA16F with fp32 weights: measured ~1e-5 * noise_amp.)
 *
 * One program in two files: this one (the fields and the terrain on the
 * CPU, the GPU part, the order of the checks) and test_density_noise.c
 * (half floats, the noise tables and functions). */
#include "density_test.h"
#include "cut_check.h"
#include "density_ref.h"
#include "terrain.h"
#include "gpu.h"
#include "image.h"
#include "noise.h"
#include "params.h"
#include "pipeline.h"
#include "platform.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* the program's counters (tcheck.h), shared by its files */
int tc_pass, tc_fail;

struct noise_set ns_a, ns_b;

static void set(struct params *p, const char *kv)
{
	char buf[512], err[256];
	snprintf(buf, sizeof(buf), "%s", kv);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
		char *eq = strchr(tok, '=');
		if (!eq) {
			CHECK(0, "bad setting '%s'", tok);
			continue;
		}
		*eq = 0;
		int rc = params_set(p, tok, eq + 1, err, sizeof(err));
		CHECK(rc == 0, "params_set %s: %s", tok, err);
	}
}

/* ---- density: fields and terms ------------------------------------------- */

static void test_fields(void)
{
	struct params p;
	params_defaults(&p);
	const float s = 2.5f;
	p.field_scale = s;
	const double tol = 1e-5 * s;

	set(&p, "field=torus");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0.6f * s, 0, 0), 0.16 * s, tol, "torus tube centre");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0.0f, -0.6f * s), 0.16 * s, tol, "torus tube centre (z)");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 1.0f * s, 0, 0), 0.0, tol, "torus outer surface");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0.6f * s, 0.4f * s, 0), 0.0, tol, "torus top surface");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0, 0), -0.2 * s, tol, "torus hole");

	set(&p, "field=bumps");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0.3f * s, 0), -0.3 * s, tol, "bumps at x=z=0");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, (float)M_PI / 10 * s, 0, 0), 0.2 * s, tol, "bumps crest");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, (float)M_PI / 10 * s, 0, (float)M_PI / 5 * s), -0.2 * s, tol,
		   "bumps trough");

	set(&p, "field=ripple");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, sqrtf((float)M_PI / 20) * s, 0, 0), 0.1 * s, tol, "ripple crest");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0, sqrtf((float)M_PI / 10) * s), 0.0, tol, "ripple node");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, -0.5f * s, 0), 0.5 * s, tol, "ripple below");

	set(&p, "field=sphere");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0, 0), s, tol, "sphere centre");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, -s, 0), 0.0, tol, "sphere surface");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0.6f * s, 0, 0.8f * s), 0.0, tol, "sphere surface (diagonal)");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 3 * s, 0, 0), -2 * s, tol, "sphere outside");

	set(&p, "field=checker");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0, 0), s, tol, "checker +");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, s, 0, 0), -s, tol, "checker -");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, s, s, 0), s, tol, "checker + (xy)");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, s, -s, s), -s, tol, "checker - (xyz)");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0.5f * s, 0, 0), 0.0, tol, "checker zero between");

	/* scrolling: time*scroll_speed shifts x, for test fields and terrain */
	set(&p, "field=bumps;time=2;scroll_speed=0.75");
	float a = density_ref(&p, &ns_a, NULL, 0.1f, 0.2f, 0.3f);
	set(&p, "time=0");
	CHECK_NEAR(a, density_ref(&p, &ns_a, NULL, 1.6f, 0.2f, 0.3f), 1e-6, "scroll (bumps)");
	params_defaults(&p);
	set(&p, "time=3;scroll_speed=-2");
	a = density_ref(&p, &ns_a, NULL, 4.0f, -1.0f, 2.0f);
	set(&p, "time=0");
	CHECK_NEAR(a, density_ref(&p, &ns_a, NULL, -2.0f, -1.0f, 2.0f), 1e-5, "scroll (terrain)");
}

/* The f-th fractal family's name, from the parameter table (so a family
 * added there is tested here without an edit). */
static const char *family(int f)
{
	static char names[FRACTAL_COUNT][32];
	const char *c = params_find("fractal")->choices;
	for (int i = 0; i < f && c; i++) {
		c = strchr(c, '|');
		c = c ? c + 1 : NULL;
	}
	const char *bar = c ? strchr(c, '|') : NULL;
	snprintf(names[f], sizeof(names[f]), "%.*s", c ? (int)(bar ? (size_t)(bar - c) : strlen(c)) : 0, c ? c : "");
	return names[f];
}

static void test_terrain(void)
{
	struct params p;
	for (int f = 0; f < FRACTAL_COUNT; f++)
		for (int n = 0; n < 2; n++) {
			params_defaults(&p);
			char kv[128];
			snprintf(kv, sizeof(kv), "fractal=%s;noise=%s", family(f), n ? "texture" : "alu");
			set(&p, kv);
			struct noise_set *ns = &ns_a;
			int rock_deep = 0, air_high = 0, floor_rock = 0, pos = 0, neg = 0, bad = 0;
			for (int i = 0; i < 64; i++) {
				float x = -16.0f + (float)(i % 8) * 4.1f, z = -16.0f + (float)(i / 8) * 4.3f;
				rock_deep += density_ref(&p, ns, NULL, x, -200.0f, z) > 0;
				air_high += density_ref(&p, ns, NULL, x, 200.0f, z) < 0;
				floor_rock += density_ref(&p, ns, NULL, x, p.floor_y - 1.0f, z) > 0;
				for (int j = 0; j < 16; j++) {
					float d = density_ref(&p, ns, NULL, x, -18.0f + 2.0f * (float)j, z);
					pos += d > 0;
					neg += d < 0;
					bad += !isfinite(d);
				}
			}
			CHECK(rock_deep == 64 && air_high == 64, "%s: rock far below (%d/64), air far above (%d/64)", kv,
			      rock_deep, air_high);
			CHECK(floor_rock == 64, "%s: rock below the hard floor (%d/64)", kv, floor_rock);
			CHECK(bad == 0, "%s: %d non-finite densities", kv, bad);
			CHECK(pos > 64 && neg > 64, "%s: the default volume holds a surface (%d rock, %d air)", kv, pos, neg);
		}

	/* the newer families against their definitions: hybrid and
	 * slope_damped start from the plain basis (one octave = fbm's one
	 * octave); slope_damped with mf_slope 0 keeps only octave 0 (a slope of
	 * 0 damps every later octave); abs_multifractal's cascade is centred on
	 * E|n| and reacts only to |n| */
	{
		params_defaults(&p);
		set(&p, "fractal=fbm;octaves=1");
		float one = density_ref(&p, &ns_a, NULL, 2.3f, 0.7f, -4.1f);
		set(&p, "fractal=hybrid");
		CHECK_NEAR(density_ref(&p, &ns_a, NULL, 2.3f, 0.7f, -4.1f), one, 1e-4, "hybrid, one octave = fbm");
		set(&p, "fractal=slope_damped");
		CHECK_NEAR(density_ref(&p, &ns_a, NULL, 2.3f, 0.7f, -4.1f), one, 1e-4, "slope_damped, one octave = fbm");
		set(&p, "octaves=9;mf_slope=0");
		CHECK_NEAR(density_ref(&p, &ns_a, NULL, 2.3f, 0.7f, -4.1f), one, 1e-4, "slope_damped, mf_slope 0 = octave 0");
		set(&p, "mf_slope=3");
		CHECK(fabsf(density_ref(&p, &ns_a, NULL, 2.3f, 0.7f, -4.1f) - one) > 1e-3, "slope_damped adds octaves");
		set(&p, "fractal=abs_multifractal;octaves=1;mf_offset=1;mf_contrast=2;hurst=1");
		float nabs = fabsf(noise_perlin(&ns_a, 0.0f, 0.0f, 0.0f)); /* a lattice point: 0 */
		CHECK(nabs == 0.0f, "lattice point");
		/* one octave: h = (1 + 2|n|) - (1 + 2 E|n|) = 2 (|n| - E|n|) >= -2 E|n| */
		int below = 0;
		for (int i = 0; i < 200; i++) {
			float x = -20.0f + 0.37f * (float)i, y = 0.0f, z = 3.0f;
			float d = density_ref(&p, &ns_a, NULL, x, y, z) - (-y * p.ground_slope);
			set(&p, "noise_amp=0");
			d -= density_ref(&p, &ns_a, NULL, x, y, z) - (-y * p.ground_slope);
			set(&p, "noise_amp=24");
			below += d / 24.0f < -2.0f * 0.2205f - 1e-4f;
		}
		CHECK(below == 0, "abs_multifractal: %d values below its floor -2 E|n|", below);
	}

	/* marble: without turbulence, plain sine bands along y */
	params_defaults(&p);
	set(&p, "warp_amp=0");
	{
		float base = density_ref(&p, &ns_a, NULL, 1.3f, 2.1f, -0.4f);
		set(&p, "marble_amp=2.5;marble_freq=0.2;marble_turb=0");
		CHECK_NEAR(density_ref(&p, &ns_a, NULL, 1.3f, 2.1f, -0.4f) - base, 2.5 * sin(2.0 * M_PI * 0.2 * 2.1), 1e-4,
			   "marble bands without turbulence");
		set(&p, "marble_turb=4");
		CHECK(fabsf(density_ref(&p, &ns_a, NULL, 1.3f, 2.1f, -0.4f) - base - 2.5f * sinf(2.0f * (float)M_PI * 0.2f * 2.1f)) >
			      1e-3f,
		      "marble turbulence moves the bands");
	}

	/* hard floor alone: no ground, no noise */
	params_defaults(&p);
	set(&p, "shape=caves;cave_bias=-5;noise_amp=0;warp_amp=0");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 1, 0, 1), -5.0, 1e-6, "caves bias");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 1, p.floor_y - 1.0f, 1), -5.0 + p.floor_strength, 1e-4, "hard floor");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 1, p.floor_y + 0.1f, 1), -5.0, 1e-6, "above the hard floor");
	/* planet */
	set(&p, "shape=planet;planet_radius=10;floor_strength=0");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, 0, 0), 0.0, 1e-5, "planet surface at the origin");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 0, -10, 0), 10.0, 1e-5, "planet centre");
	/* flat spot: lerp(d, flat_y - y, 0.9) inside inner, untouched beyond outer */
	params_defaults(&p);
	float d0 = density_ref(&p, &ns_a, NULL, 1.0f, 2.5f, -1.0f);
	float d_far = density_ref(&p, &ns_a, NULL, 30.0f, 2.5f, 0.0f);
	set(&p, "flat_spot=true;flat_x=0;flat_z=0;flat_y=2;flat_inner=4;flat_outer=8");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 1.0f, 2.5f, -1.0f), d0 + 0.9f * ((2.0f - 2.5f) - d0), 1e-4, "flat spot inside");
	CHECK_NEAR(density_ref(&p, &ns_a, NULL, 30.0f, 2.5f, 0.0f), d_far, 1e-6, "flat spot beyond outer radius");
	/* terraces and shelf are continuous in y */
	static const char *terr[] = { "terrace=pre", "terrace=post", "shelf=pre", "shelf=post" };
	for (int t = 0; t < 4; t++) {
		params_defaults(&p);
		set(&p, terr[t]);
		/* above the hard floor (its ramp is floor_strength*floor_sharpness steep) */
		float prev = density_ref(&p, &ns_a, NULL, 3.3f, -12.0f, 1.7f), jump = 0;
		for (int j = 1; j <= 2600; j++) {
			float d = density_ref(&p, &ns_a, NULL, 3.3f, -12.0f + (float)j * 0.01f, 1.7f);
			jump = fmaxf(jump, fabsf(d - prev));
			prev = d;
		}
		CHECK(jump < 0.5f, "%s: density continuous along y (max step %g over dy = 0.01)", terr[t], jump);
	}
	params_defaults(&p);
	float plain = density_ref(&p, &ns_a, NULL, 3.3f, 0.3f, 1.7f);
	set(&p, "terrace=pre");
	CHECK(density_ref(&p, &ns_a, NULL, 3.3f, 0.3f, 1.7f) != plain, "terraces change the density");

	/* volume layout: (nx+3)(ny+3)(nz+3), one-sample margin, x fastest */
	params_defaults(&p);
	p.closed = false; /* raw samples (the closed volume is checked below) */
	const float org[3] = { -1.0f, 2.0f, 3.0f };
	float vol[6 * 5 * 4];
	density_ref_volume(&p, &ns_a, NULL, org, 0.5f, 3, 2, 1, vol);
	CHECK(vol[0] == density_ref(&p, &ns_a, NULL, -1.5f, 1.5f, 2.5f), "volume corner (-1,-1,-1)");
	CHECK(vol[(2 * 5 + 3) * 6 + 4] == density_ref(&p, &ns_a, NULL, -1.0f + 3 * 0.5f, 2.0f + 2 * 0.5f, 3.0f + 1 * 0.5f),
	      "volume sample (4,3,2)");
	/* closed volume: air on the border corners, more air in the margin,
	 * the inside untouched */
	{
		float raw[8 * 8 * 8], cl[8 * 8 * 8];
		params_defaults(&p);
		p.closed = false;
		density_ref_volume(&p, &ns_a, NULL, org, 0.5f, 5, 5, 5, raw);
		p.closed = true;
		density_ref_volume(&p, &ns_a, NULL, org, 0.5f, 5, 5, 5, cl);
		int bad = 0;
		for (int k = 0; k < 8; k++)
			for (int j = 0; j < 8; j++)
				for (int i = 0; i < 8; i++) {
					int n = (k * 8 + j) * 8 + i;
					int margin = i == 0 || j == 0 || k == 0 || i == 7 || j == 7 || k == 7;
					int border = !margin && (i == 1 || j == 1 || k == 1 || i == 6 || j == 6 || k == 6);
					if (margin)
						bad += !(cl[n] <= p.iso - 0.5f);
					else if (border)
						bad += !(cl[n] < p.iso);
					else
						bad += cl[n] != raw[n];
				}
		CHECK(bad == 0, "closed volume: %d samples wrong", bad);
	}
}

/* ---- GPU vs CPU -------------------------------------------------------- */

struct gcase {
	const char *settings;
	bool texture;
};

/* GPU against CPU over a cube of m^3 samples (tests/cut_check.h: where the
 * field may cut far samples, their contract).  expect_cut: 1 = some
 * samples must be cut (the test sees the cut at work), 0 = none may be,
 * -1 = either. */
static void compare_volume(const char *what, const struct params *p, int m, const float *gv, const float *cv,
			   double tol, bool texture, int expect_cut)
{
	struct cut_stats st;
	cut_compare(p, m, m, m, gv, cv, tol, &st);
	size_t cnt = (size_t)m * m * m, at = st.at_far, fb = st.first_bad;
	printf("  %-44s grid %2d  max|gpu-cpu| %.3g near the surface, %.3g elsewhere (tol %.3g%s); %zu of %zu samples "
	       "cut (bound %.3g)\n",
	       what, m - 3, st.err_near, st.err_far, tol, texture ? ", texture" : "", st.cut, cnt,
	       cut_may(p) ? cut_bound(p) : 0.0);
	CHECK(st.err_far <= tol, "%s grid %d: max |gpu - cpu| = %g at %zu (gpu %g, cpu %g), tol %g%s", what, m - 3,
	      st.err_far, at, (double)gv[at], (double)cv[at], tol, cut_may(p) ? " (nor within the cut's bound)" : "");
	CHECK(st.bad_sign == 0 && st.bad_rock == 0 && st.bad_near == 0,
	      "%s grid %d: cut samples with the wrong sign %zu, too shallow in rock %zu, near the surface %zu (first at "
	      "%zu: gpu %g, cpu %g)",
	      what, m - 3, st.bad_sign, st.bad_rock, st.bad_near, fb, fb < cnt ? (double)gv[fb] : 0.0,
	      fb < cnt ? (double)cv[fb] : 0.0);
	if (expect_cut == 1)
		CHECK(st.cut > 0, "%s grid %d: no sample cut (the far samples' cut is not at work)", what, m - 3);
	else if (expect_cut == 0)
		CHECK(st.cut == 0, "%s grid %d: %zu samples cut with the cut off", what, m - 3, st.cut);
}

static void gpu_compare_cut(const char *what, int n, const char *settings, bool texture, int expect_cut)
{
	struct params p;
	params_defaults(&p);
	set(&p, settings);
	struct grid g;
	memset(&g, 0, sizeof(g));
	g.nx = g.ny = g.nz = n;
	g.cell = p.vol_size / (float)n;
	g.origin[0] = p.vol_x - 0.5f * p.vol_size;
	g.origin[1] = p.vol_y - 0.5f * p.vol_size;
	g.origin[2] = p.vol_z - 0.5f * p.vol_size;
	size_t cnt = (size_t)(n + 3) * (size_t)(n + 3) * (size_t)(n + 3);
	float *gv = calloc(cnt, sizeof(float)), *cv = calloc(cnt, sizeof(float));
	char err[512] = "";
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "%s: pipeline_create: %s", what, err);
	if (pl) {
		int rc = pipeline_density(pl, &p, err, sizeof(err));
		CHECK(rc == 0, "%s: pipeline_density: %s", what, err);
		rc = pipeline_read_density(pl, gv);
		CHECK(rc == 0, "%s: pipeline_read_density", what);
		pipeline_destroy(pl);
		static struct noise_set ns;
		noise_set_init(&ns, p.seed);
		density_ref_volume(&p, &ns, ed, g.origin, g.cell, n, n, n, cv);
		double dmax = 0;
		for (size_t i = 0; i < cnt; i++)
			dmax = fmax(dmax, fabs((double)cv[i]));
		double scale = p.field != 0 ? p.field_scale : fmax(1.0, dmax);
		double tol = texture ? 2e-2 * p.noise_amp : 1e-4 * scale;
		compare_volume(what, &p, n + 3, gv, cv, tol, texture, expect_cut);
	}
	terrain_destroy(tr);
	edits_destroy(ed);
	free(gv);
	free(cv);
}

static void gpu_compare(const char *what, int n, const char *settings, bool texture)
{
	gpu_compare_cut(what, n, settings, texture, -1);
}

static void test_gpu(void)
{
	struct platform_options opt = { .name = "surfaceless", .width = 64, .height = 64, .debug = false };
	char err[512] = "";
	struct platform *pf = platform_open(&opt, err, sizeof(err));
	if (!pf) {
		printf("GPU part skipped: platform_open(surfaceless): %s\n", err);
		return;
	}
	struct gpu_caps caps;
	if (gpu_init(&caps, false, err, sizeof(err)) < 0) {
		printf("GPU part skipped: gpu_init: %s\n", err);
		platform_close(pf);
		return;
	}
	printf("GPU: %s / %s\n", caps.renderer, caps.version);

	static const char *fields[] = { "torus", "bumps", "ripple", "sphere", "checker" };
	char kv[256], what[128];
	for (int gi = 0; gi < 2; gi++) {
		int n = gi ? 33 : 17;
		for (int f = 0; f < 5; f++) {
			snprintf(kv, sizeof(kv), "field=%s;field_scale=8", fields[f]);
			snprintf(what, sizeof(what), "field=%s", fields[f]);
			gpu_compare(what, n, kv, false);
		}
		/* checker at one cell per sign change: the worst case */
		snprintf(kv, sizeof(kv), "field=checker;field_scale=%g", 32.0 / n);
		gpu_compare("field=checker (one cell per check)", n, kv, false);
		for (int f = 0; f < FRACTAL_COUNT; f++) {
			snprintf(kv, sizeof(kv), "fractal=%s;noise=alu", family(f));
			snprintf(what, sizeof(what), "fractal=%s noise=alu", family(f));
			gpu_compare(what, n, kv, false);
		}
	}
	for (int f = 0; f < FRACTAL_COUNT; f++) {
		snprintf(kv, sizeof(kv), "fractal=%s;noise=texture", family(f));
		snprintf(what, sizeof(what), "fractal=%s noise=texture", family(f));
		gpu_compare(what, 17, kv, true);
	}
	gpu_compare("noise=texture rotated_octaves=0 far away", 17, "noise=texture;rotated_octaves=0;vol_x=1000;vol_z=-3000",
		    true);
	gpu_compare("all terms (terrace, shelf, flat spot, scroll)", 33,
		    "terrace=pre;shelf=post;flat_spot=true;flat_y=-2;time=1.5;scroll_speed=2", false);
	gpu_compare("terrace=post shelf=pre", 17, "terrace=post;shelf=pre", false);
	gpu_compare("noise_y_scale=0.25 fractal=ridged", 17, "noise_y_scale=0.25;fractal=ridged", false);
	gpu_compare("noise_y_scale=0", 17, "noise_y_scale=0", false);
	gpu_compare("control_strength=0.9 (noise)", 17, "control_strength=0.9;control_freq=0.06", false);
	gpu_compare("control_strength=0.9 (noise) noise=texture", 17, "control_strength=0.9;control_freq=0.06;noise=texture",
		    true);
	gpu_compare("marble_amp=3", 17, "marble_amp=3;marble_freq=0.2;marble_turb=5", false);
	gpu_compare("marble_amp=3 noise=texture", 17, "marble_amp=3;noise=texture", true);
	gpu_compare("shape=planet seed=3", 17, "shape=planet;planet_radius=12;seed=3", false);
	gpu_compare("shape=caves seed=0", 17, "shape=caves;cave_bias=2;seed=0", false);
	/* the terms a zero turns off (P_TERM: compiled out), off beside the
	 * defaults' on above */
	gpu_compare("warp_amp=0", 17, "warp_amp=0", false);
	gpu_compare("floor_strength=0", 17, "floor_strength=0", false);
	gpu_compare("noise_amp=0", 17, "noise_amp=0", false);
	gpu_compare("rotated_octaves=0 noise=alu", 17, "rotated_octaves=0", false);
	gpu_compare("rotated_octaves=4 noise=alu", 17, "rotated_octaves=4", false);
	gpu_compare("time=1.5 scroll_speed=0", 17, "time=1.5;scroll_speed=0", false);
	gpu_compare("time=1.5 scroll_speed=-1", 17, "time=1.5;scroll_speed=-1", false);
	gpu_compare("field=bumps time=2 scroll_speed=0", 17, "field=bumps;field_scale=8;time=2;scroll_speed=0", false);
	gpu_compare("every term off (warp, floor, rotation, scroll)", 17,
		    "warp_amp=0;floor_strength=0;rotated_octaves=0;time=2;scroll_speed=0", false);
	gpu_compare("noise=texture warp_amp=0 floor_strength=0", 17, "noise=texture;warp_amp=0;floor_strength=0", true);
#define BENCH_FIELD                                                                                          \
	"fractal=fbm;octaves=7;warp_amp=0;floor_strength=0;rotated_octaves=0;closed=false;vol_height=1;vol_y=0;" \
	"noise_freq=0.125;lacunarity=2.03;hurst=0.9785;noise_amp=3.9"
	/* the far samples' cut at work, and off */
	gpu_compare_cut("plain fBm, 7 octaves (benchmark field)", 33, BENCH_FIELD, false, 1);
	gpu_compare_cut("the benchmark field, density_cut=false", 33, BENCH_FIELD ";density_cut=false", false, 0);
	gpu_compare_cut("the default field (geiss, warp, floor)", 33, "", false, 1);
	gpu_compare_cut("turbulence, terraces, flat spot, control", 33,
			"fractal=turbulence;terrace=pre;flat_spot=true;flat_y=-2;control_strength=0.5", false, 1);
	gpu_compare_cut("geiss, closed, iso 1.5", 33, "closed=true;iso=1.5", false, 1);
	/* the control map from a file: plains on the left, mountains on the right */
	{
		char dir[] = "/tmp/isoterra-control-XXXXXX", cm[64], e[256];
		CHECK(mkdtemp(dir) != NULL, "mkdtemp");
		snprintf(cm, sizeof(cm), "%s/control.png", dir);
		uint16_t v[7 * 5];
		for (int i = 0; i < 7 * 5; i++)
			v[i] = (uint16_t)((i % 7) * 65535 / 6 + (i / 7) * 1000);
		CHECK(image_write_png_gray16(cm, v, 7, 5, e, sizeof(e)) == 0, "control map: %s", e);
		snprintf(kv, sizeof(kv), "control_strength=0.85;control_map=%s;control_map_scale=5", cm);
		gpu_compare("control_strength=0.85 (file)", 17, kv, false);
		/* all black at strength 1: no noise term at all; all white: the full term */
		struct params p, q;
		params_defaults(&p);
		params_defaults(&q);
		for (int i = 0; i < 7 * 5; i++)
			v[i] = 0;
		CHECK(image_write_png_gray16(cm, v, 7, 5, e, sizeof(e)) == 0, "control map: %s", e);
		snprintf(kv, sizeof(kv), "control_strength=1;control_map=%s", cm);
		set(&p, kv);
		set(&q, "noise_amp=0");
		struct edits *ed = edits_create();
		CHECK(edits_load(ed, &p, e, sizeof(e)) == 0, "edits_load: %s", e);
		int bad = 0;
		for (int i = 0; i < 50; i++) {
			float x = -20.0f + 0.83f * (float)i, y = -3.0f + 0.1f * (float)i, z = 7.0f - 0.5f * (float)i;
			bad += fabsf(density_ref(&p, &ns_a, ed, x, y, z) - density_ref(&q, &ns_a, NULL, x, y, z)) > 1e-5f;
		}
		CHECK(bad == 0, "a black control map at strength 1 removes the noise term (%d of 50 differ)", bad);
		for (int i = 0; i < 7 * 5; i++)
			v[i] = 65535;
		CHECK(image_write_png_gray16(cm, v, 7, 5, e, sizeof(e)) == 0, "control map: %s", e);
		edits_clear(ed); /* the same size and second: reload */
		CHECK(edits_load(ed, &p, e, sizeof(e)) == 0, "edits_load: %s", e);
		params_defaults(&q);
		bad = 0;
		for (int i = 0; i < 50; i++) {
			float x = -20.0f + 0.83f * (float)i, y = -3.0f + 0.1f * (float)i, z = 7.0f - 0.5f * (float)i;
			bad += fabsf(density_ref(&p, &ns_a, ed, x, y, z) - density_ref(&q, &ns_a, NULL, x, y, z)) > 1e-5f;
		}
		CHECK(bad == 0, "a white control map leaves the full noise term (%d of 50 differ)", bad);
		edits_destroy(ed);
		unlink(cm);
		rmdir(dir);
	}
	/* the heightmap's detail and 3D noise terms, off and on */
	{
		char dir[] = "/tmp/isoterra-density-XXXXXX", hm[64], e[256];
		CHECK(mkdtemp(dir) != NULL, "mkdtemp");
		snprintf(hm, sizeof(hm), "%s/hm.png", dir);
		uint16_t v[9 * 7];
		for (int i = 0; i < 9 * 7; i++)
			v[i] = (uint16_t)((i * 7919u + 1237u) % 65536u);
		CHECK(image_write_png_gray16(hm, v, 9, 7, e, sizeof(e)) == 0, "heightmap: %s", e);
		static const char *hm_terms[] = { "heightmap_detail=0;heightmap_noise=0", "heightmap_detail=2;heightmap_noise=0",
						  "heightmap_detail=0;heightmap_noise=0.3", "heightmap_detail=2;heightmap_noise=0.3",
						  "heightmap_detail=2;heightmap_noise=0.3;noise_amp=0" };
		for (int i = 0; i < 5; i++) {
			snprintf(kv, sizeof(kv), "field=heightmap;heightmap=%s;heightmap_scale=4;octaves=4;%s", hm, hm_terms[i]);
			snprintf(what, sizeof(what), "field=heightmap %s", hm_terms[i]);
			gpu_compare(what, 17, kv, false);
		}
		unlink(hm);
		rmdir(dir);
	}
	platform_close(pf);
}

int main(void)
{
	test_half();
	test_tables();
	test_perlin();
	test_tex_noise();
	test_worley();
	test_fields();
	test_terrain();
	test_gpu();
	return tc_done("test_density");
}
