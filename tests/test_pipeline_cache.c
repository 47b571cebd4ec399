/* isoterra — test_pipeline (test_pipeline.c): the program cache (a term
 * that is off leaves no code, switching it on compiles one variant,
 * moving its knob within "on" none) and every variant's densities against
 * the CPU's; the curves switched on and off. */
#include "pipeline_test.h"
#include "gpu_fixture.h"
#include "terrain.h"

#include <math.h>
#include <string.h>
#include <unistd.h>

/* ---- specialization and the program cache ------------------------------- */

static void set_kv(struct params *p, const char *kv)
{
	char buf[512], err[256];
	snprintf(buf, sizeof(buf), "%s", kv);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
		char *eq = strchr(tok, '=');
		CHECK(eq != NULL, "bad setting '%s'", tok);
		if (!eq)
			continue;
		*eq = 0;
		CHECK(params_set(p, tok, eq + 1, err, sizeof(err)) == 0, "params_set %s: %s", tok, err);
	}
}

/* The defaults with the settings kv, their grid and the terrain's
 * extraction on it.  0, or -1 (the failure checked, named by what). */
static int open_terrain(const char *kv, const char *what, struct params *p, struct grid *g, struct fixture_terrain *ft)
{
	params_defaults(p);
	set_kv(p, kv);
	grid_from_params(g, p);
	char err[512] = "";
	int rc = fixture_terrain_open(ft, g, p, err, sizeof(err));
	CHECK(rc == 0, "%s: pipeline_create: %s", what, err);
	return rc == 0 && ft->pl ? 0 : -1;
}

static bool reads(GLuint prog, const char *uniform)
{
	return prog && uniform && glGetUniformLocation(prog, uniform) >= 0;
}

/* The density pass with p: its program, the compiles it cost, and its
 * densities against the CPU reference. */
static GLuint density_with(struct pipeline *pl, struct edits *ed, const struct grid *g, const struct params *p,
			   const char *what, unsigned *compiled)
{
	unsigned c0 = pipeline_compiles(pl);
	CHECK(fixture_density(pl, p) == 0, "%s: density pass", what);
	*compiled = pipeline_compiles(pl) - c0;
	float *dg, *dc;
	double dmax, scale;
	density_vs_reference(pl, ed, g, p, what, &dg, &dc, &dmax, &scale);
	/* texture noise: the sampler's filter weights (see test_density.c) */
	double tol = p->noise == NOISE_TEXTURE ? 2e-2 * p->noise_amp : 1e-5 * fmax(scale, 1.0) + 1e-6;
	CHECK(dmax <= tol, "%s: GPU vs CPU density max error %g (scale %g)", what, dmax, scale);
	free(dg);
	free(dc);
	return pipeline_density_program(pl);
}

/* warp_amp 0 -> 0.5 -> 0.7 -> 0: one new variant for "on", shared by 0.5
 * and 0.7; back at 0 the first one again.  With AO the vertex pass is a
 * field program too: a flip costs the two, a knob move nothing. */
void check_cache(void)
{
	struct params p;
	struct grid g;
	struct fixture_terrain ft;
	/* one program per density pass: the far samples' cut off (its own
	 * variants: check_cut_cache) */
	if (open_terrain("grid=16;ao_rays=0;warp_amp=0;density_cut=false", "cache", &p, &g, &ft) < 0)
		return;
	struct edits *ed = ft.ed;
	struct pipeline *pl = ft.pl;
	unsigned c;
	GLuint off = density_with(pl, ed, &g, &p, "warp_amp=0", &c);
	CHECK(c == 0, "warp_amp 0: pipeline_create's variant is used (%u compiles)", c);
	CHECK(!reads(off, "u_warp_amp") && !reads(off, "u_warp_freq"), "warp_amp 0: no warp uniform in the program");
	p.warp_amp = 0.5f;
	GLuint on = density_with(pl, ed, &g, &p, "warp_amp=0.5", &c);
	CHECK(c == 1 && on != off, "warp_amp 0 -> 0.5: one new density variant (%u compiles)", c);
	CHECK(reads(on, "u_warp_amp") && reads(on, "u_warp_freq"), "warp_amp 0.5: the warp reads its uniforms");
	p.warp_amp = 0.7f;
	GLuint on2 = density_with(pl, ed, &g, &p, "warp_amp=0.7", &c);
	CHECK(c == 0 && on2 == on, "warp_amp 0.5 -> 0.7: the same variant (%u compiles)", c);
	p.warp_amp = 0.0f;
	GLuint back = density_with(pl, ed, &g, &p, "warp_amp=0 again", &c);
	CHECK(c == 0 && back == off, "warp_amp 0.7 -> 0: the first variant again (%u compiles)", c);

	/* the whole pipeline with AO: density + vertex variants */
	p.ao_rays = 8;
	unsigned c0 = pipeline_compiles(pl);
	CHECK(fixture_run(pl, &p) == 0, "cache: run with AO");
	CHECK(pipeline_compiles(pl) - c0 == 1, "AO on: one vertex variant (%u compiles)", pipeline_compiles(pl) - c0);
	p.warp_amp = 2.0f;
	c0 = pipeline_compiles(pl);
	CHECK(fixture_run(pl, &p) == 0, "cache: run with AO, warp on");
	CHECK(pipeline_compiles(pl) - c0 == 1, "warp on with AO: the AO variant (density's is cached) (%u compiles)",
	      pipeline_compiles(pl) - c0);
	c0 = pipeline_compiles(pl);
	for (int i = 0; i < 5; i++) {
		p.warp_amp = 1.0f + (float)i;
		p.noise_amp = 20.0f + (float)i;
		p.floor_y = -13.0f + (float)i;
		p.time += 1.0f / 30.0f;
		CHECK(fixture_run(pl, &p) == 0, "cache: knob frame %d", i);
	}
	CHECK(pipeline_compiles(pl) == c0, "live knobs within 'on', time advancing: no compile (%u)",
	      pipeline_compiles(pl) - c0);
	/* more states than the cache holds: the least recently used goes, the
	 * one in use every frame stays */
	p.warp_amp = 0.0f;
	p.ao_rays = 0;
	CHECK(fixture_density(pl, &p) == 0, "cache: warp off");
	GLuint keep = pipeline_density_program(pl);
	static const char *states[] = { "terrace=pre", "terrace=post", "shelf=pre", "shelf=post", "flat_spot=true",
					"shape=planet", "shape=caves", "fractal=fbm", "fractal=ridged", "fractal=hetero",
					"noise=texture", "rotated_octaves=0", "floor_strength=0", "scroll_speed=1",
					"noise_amp=0", "closed=false", "fractal=turbulence", "fractal=multifractal" };
	for (size_t i = 0; i < sizeof(states) / sizeof(states[0]); i++) {
		struct params q = p;
		set_kv(&q, states[i]);
		CHECK(fixture_density(pl, &q) == 0, "cache: %s", states[i]);
		c0 = pipeline_compiles(pl);
		CHECK(fixture_density(pl, &p) == 0 && pipeline_density_program(pl) == keep && pipeline_compiles(pl) == c0,
		      "cache: after %s the frame's own variant is still there", states[i]);
	}
	fixture_terrain_close(&ft);
}

/* Every term off and on: off leaves none of its uniforms in the density
 * program (no code), on reads them; the flip compiles one variant; both
 * match the CPU reference. */
struct term_case {
	const char *ctx, *off, *on; /* settings: common, the term off, on */
	const char *uniform;        /* a uniform only the term reads */
	bool curves;                /* with a curve in the edit state */
};

static void check_term(const struct term_case *t, const char *hm_file)
{
	struct params p;
	params_defaults(&p);
	char kv[512];
	snprintf(kv, sizeof(kv), "grid=16;ao_rays=0;density_cut=false;heightmap=%s;heightmap_scale=4%s%s;%s", hm_file,
		 t->ctx[0] ? ";" : "",
		 t->ctx, t->off);
	set_kv(&p, kv);
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "", what[160];
	struct edits *ed = edits_create();
	if (t->curves) {
		static const float pts[4 * 3] = { -14, -2, -9, -4, 0, -2, 3, 1, 4, 14, 2, 9 };
		struct curve_path cp;
		memset(&cp, 0, sizeof(cp));
		curve_path_defaults(&cp, CURVE_ROAD);
		cp.width = 4.0f;
		cp.falloff = 3.0f;
		cp.npts = 4;
		cp.pts = (float *)pts;
		snprintf(cp.label, sizeof(cp.label), "test road");
		struct curve_set cs = { .paths = &cp, .npaths = 1 };
		CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "curves: %s", err);
	}
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "%s: pipeline_create: %s", t->off, err);
	if (pl) {
		unsigned c;
		snprintf(what, sizeof(what), "%s %s", t->ctx, t->off);
		GLuint off = density_with(pl, ed, &g, &p, what, &c);
		const char *u = t->uniform ? t->uniform : "(no own uniform)";
		CHECK(c == 0 && !reads(off, t->uniform), "%s: no %s in the program (%u compiles)", what, u, c);
		set_kv(&p, t->on);
		snprintf(what, sizeof(what), "%s %s", t->ctx, t->on);
		GLuint on = density_with(pl, ed, &g, &p, what, &c);
		CHECK(c == 1 && on != off && (!t->uniform || reads(on, t->uniform)),
		      "%s: one new variant that reads %s (%u compiles)", what, u, c);
		set_kv(&p, t->off);
		CHECK(density_with(pl, ed, &g, &p, t->off, &c) == off && c == 0, "%s again: the first variant (%u compiles)",
		      t->off, c);
		printf("term %-34s off/on: %-18s %s\n", t->on, u, "compiled out / in");
	}
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
}

void check_terms(void)
{
	/* a heightmap for field=heightmap (any file name is harmless elsewhere) */
	char dir[] = "/tmp/isoterra-pipeline-XXXXXX", hm[64], err[256];
	CHECK(mkdtemp(dir) != NULL, "mkdtemp");
	snprintf(hm, sizeof(hm), "%s/hm.png", dir);
	uint16_t v[9 * 7];
	for (int i = 0; i < 9 * 7; i++)
		v[i] = (uint16_t)((i * 7919u + 1237u) % 65536u);
	CHECK(image_write_png_gray16(hm, v, 9, 7, err, sizeof(err)) == 0, "heightmap: %s", err);
	static const struct term_case cases[] = {
		{ "", "warp_amp=0", "warp_amp=3", "u_warp_amp", false },
		{ "", "noise_amp=0", "noise_amp=12", "u_noise_amp", false },
		{ "", "noise_amp=0", "noise_amp=12", "u_lacunarity", false },
		{ "", "floor_strength=0", "floor_strength=40", "u_floor_sharpness", false },
		{ "", "rotated_octaves=0", "rotated_octaves=2", "u_rotated_octaves", false },
		{ "noise=texture", "rotated_octaves=0", "rotated_octaves=3", "u_rotated_octaves", false },
		{ "time=1.5", "scroll_speed=0", "scroll_speed=2", "u_scroll_speed", false },
		{ "field=bumps;field_scale=8;time=1.5", "scroll_speed=0", "scroll_speed=-1", "u_time", false },
		{ "", "terrace=off", "terrace=pre", "u_terrace_step", false },
		{ "", "terrace=off", "terrace=post", "u_terrace_strength", false },
		{ "", "shelf=off", "shelf=pre", "u_shelf_y", false },
		{ "", "shelf=off", "shelf=post", "u_shelf_width", false },
		{ "", "flat_spot=false", "flat_spot=true", "u_flat_inner", false },
		{ "", "shape=ground", "shape=planet", "u_planet_radius", false },
		{ "", "shape=ground", "shape=caves", "u_cave_bias", false },
		{ "", "noise=alu", "noise=texture", "u_noise0", false },
		{ "", "fractal=geiss", "fractal=ridged", "u_ridge_gain", false },
		{ "", "fractal=geiss", "fractal=worley", "u_worley_c1", false },
		{ "", "fractal=geiss", "fractal=slope_damped", "u_mf_slope", false },
		{ "", "marble_amp=0", "marble_amp=2", "u_marble_turb", false },
		{ "", "control_strength=0", "control_strength=0.6", "u_control_freq", false },
		/* the walls read no uniform of their own (every variant reads
		 * u_iso for the sign bits): only the new variant is checked */
		{ "", "closed=false", "closed=true", NULL, false },
		{ "field=heightmap", "heightmap_detail=0", "heightmap_detail=2", "u_heightmap_octaves", false },
		{ "field=heightmap;octaves=4", "heightmap_noise=0", "heightmap_noise=0.3", "u_heightmap_noise", false },
		{ "field=heightmap", "field=terrain", "field=heightmap", "u_heightmap_base", false },
		{ "", "curve_strength=0", "curve_strength=0.8", "u_curve_count", true },
		{ "field=heightmap;heightmap_detail=1", "curve_strength=0", "curve_strength=1", "u_curve_blend_lo", true },
	};
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++)
		check_term(&cases[i], hm);
	unlink(hm);
	rmdir(dir);
}

/* No curves in the edit state: the carve is compiled out; a curve added
 * through the API (an editor) brings it in at the next pass, once. */
void check_curves_switch(void)
{
	struct params p;
	struct grid g;
	struct fixture_terrain ft;
	if (open_terrain("grid=16;ao_rays=0;density_cut=false", "curves switch", &p, &g, &ft) < 0)
		return;
	char err[512] = "";
	struct edits *ed = ft.ed;
	struct pipeline *pl = ft.pl;
	if (pl) {
		unsigned c;
		GLuint none = density_with(pl, ed, &g, &p, "no curves", &c);
		CHECK(c == 0 && !reads(none, "u_curve_count") && !reads(none, "u_curve_strength"),
		      "no curves: the carve is not in the program (%u compiles)", c);
		static const float pts[3 * 3] = { -12, 0, -6, 0, 1, 2, 12, 0, 6 };
		struct curve_path cp;
		memset(&cp, 0, sizeof(cp));
		curve_path_defaults(&cp, CURVE_RIVER);
		cp.npts = 3;
		cp.pts = (float *)pts;
		snprintf(cp.label, sizeof(cp.label), "test river");
		struct curve_set cs = { .paths = &cp, .npaths = 1 };
		CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "curves: %s", err);
		GLuint with = density_with(pl, ed, &g, &p, "one curve", &c);
		CHECK(c == 1 && with != none && reads(with, "u_curve_count"), "a curve: the carve compiled in (%u)", c);
		cp.pts = (float *)(const float[9]){ -12, 1, -6, 0, 2, 2, 12, 1, 6 };
		CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "curves: %s", err);
		CHECK(density_with(pl, ed, &g, &p, "the curve moved", &c) == with && c == 0,
		      "a curve moved: the same variant (%u compiles)", c);
		edits_clear(ed);
		CHECK(density_with(pl, ed, &g, &p, "curves cleared", &c) == none && c == 0,
		      "curves cleared: the first variant again (%u compiles)", c);
	}
	if (pl)
		fixture_terrain_close(&ft);
}

/* The far samples' cut (app/extract/field.h `cuts`): its first pass makes
 * the refine passes' programs, knobs within it compile nothing, and off
 * and on again find their variants in the cache; the densities keep the
 * cut's contract against the CPU reference (tests/cut_check.h). */
void check_cut_cache(void)
{
	struct params p;
	struct grid g;
	struct fixture_terrain ft;
	/* a cube: the default volume is too flat for the cut to pay
	 * (app/terrain/terrain.c terrain_cuts) */
	if (open_terrain("grid=16;ao_rays=0;vol_height=1", "cut cache", &p, &g, &ft) < 0)
		return;
	unsigned c;
	GLuint cut = density_with(ft.pl, ft.ed, &g, &p, "density_cut=true", &c);
	CHECK(c == 3, "the first cut: the refine variant, the debris filter's near variant and the refine list (%u "
		      "compiles)", c);
	p.noise_amp *= 1.5f;
	p.iso = 0.5f;
	CHECK(density_with(ft.pl, ft.ed, &g, &p, "noise_amp, iso moved", &c) == cut && c == 0,
	      "knobs within the cut: no compile (%u)", c);
	p.density_cut = false;
	GLuint whole = density_with(ft.pl, ft.ed, &g, &p, "density_cut=false", &c);
	CHECK(c == 1 && whole != cut, "the cut off: its own variant (%u compiles)", c);
	p.density_cut = true;
	CHECK(density_with(ft.pl, ft.ed, &g, &p, "density_cut=true again", &c) == cut && c == 0,
	      "the cut on again: from the cache (%u compiles)", c);
	/* a volume lower than four of the cut's margins: the field leaves the
	 * cut off there (the same cells, smaller) */
	struct params low = p;
	low.vol_size = 32.0f;
	struct grid lg;
	grid_from_params(&lg, &low);
	pipeline_set_grid(ft.pl, &lg, 0.0f);
	CHECK(density_with(ft.pl, ft.ed, &lg, &low, "vol_size=32", &c) == whole && c == 0,
	      "a low volume: the program without the cut (%u compiles)", c);
	fixture_terrain_close(&ft);
}
