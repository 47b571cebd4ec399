/* isoterra tests — sun shadows (shaders/sun.glsl) against the CPU.
 *
 * The extraction bakes each vertex's sun visibility from one ray through
 * the density volume.  Here the CPU marches the same ray, from the GPU
 * vertex's position and normal, through the CPU reference of the field
 * (density_ref), in steps of a quarter cell, and classifies the vertex:
 *   - blocked: the ray crosses rock for longer than the GPU's step there
 *     (its steps grow geometrically; a thinner blade may fall between two
 *     of them) -> the GPU's visibility must be dark (<= 0.2);
 *   - open: the ray's clearance stays well outside the penumbra
 *     ((iso - d) >= 2 * shadow_soft * t + a quarter cell everywhere) ->
 *     the GPU's visibility must be full sun (>= 0.8);
 *   - between: the penumbra and the blades, not judged.
 * At most 2 % of either class may disagree (the GPU reads the stored
 * samples trilinearly, the CPU evaluates the field), and both classes must
 * hold enough vertices for the check to mean something.  Then: shadows off
 * (shadows = 0 or shadow_steps = 0) leaves every vertex in full sun. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "terrain.h"
#include "density_ref.h"

#include <math.h>
#include <string.h>

struct tally {
	unsigned blocked, blocked_bad, open, open_bad, between;
	double sum_blocked, sum_open; /* mean GPU visibility per class */
};

static void sun_dir(const struct params *p, float l[3])
{
	float el = p->light_el * (float)M_PI / 180.0f, az = p->light_az * (float)M_PI / 180.0f;
	l[0] = cosf(el) * cosf(az);
	l[1] = sinf(el);
	l[2] = cosf(el) * sinf(az);
}

/* The CPU's march of vertex v's ray: 1 blocked, 0 open, -1 between. */
static int classify(const struct params *p, const struct noise_set *ns, const struct grid *g, const float pos[3],
		    const float nrm[3])
{
	float l[3], start[3], lo[3], hi[3];
	sun_dir(p, l);
	int m = grid_margin(g);
	for (int a = 0; a < 3; a++) {
		start[a] = pos[a] + nrm[a] * 0.5f * g->cell;
		lo[a] = g->origin[a] + (float)(g->base[a] - m) * g->cell;
	}
	hi[0] = g->origin[0] + (float)(g->base[0] + g->nx + m) * g->cell;
	hi[1] = g->origin[1] + (float)(g->base[1] + g->ny + m) * g->cell;
	hi[2] = g->origin[2] + (float)(g->base[2] + g->nz + m) * g->cell;
	/* the GPU's steps: t_k = cell * q^k up to the reach */
	float q = powf(fmaxf(p->shadow_reach / g->cell, 1.0f), 1.0f / (float)p->shadow_steps);
	float dt = 0.25f * g->cell, run = 0.0f, run_from = 0.0f;
	bool blocked = false, open = true;
	for (float t = g->cell; t <= p->shadow_reach; t += dt) {
		float x[3];
		bool inside = true;
		for (int a = 0; a < 3; a++) {
			x[a] = start[a] + l[a] * t;
			inside = inside && x[a] >= lo[a] && x[a] <= hi[a];
		}
		if (!inside)
			break; /* a lone volume: open sky beyond its sides */
		float d = density_ref(p, ns, NULL, x[0], x[1], x[2]);
		if (d > p->iso) {
			if (run == 0.0f)
				run_from = t;
			run += dt;
			/* longer than the GPU's step where the run began (and a cell) */
			float step = run_from * (1.0f - 1.0f / q);
			if (run >= 1.5f * fmaxf(step, g->cell))
				blocked = true;
		} else {
			run = 0.0f;
		}
		if (p->iso - d < 2.0f * p->shadow_soft * t + 0.25f * g->cell)
			open = false;
	}
	return blocked ? 1 : open ? 0 : -1;
}

static void judge(const char *what, const struct params *p, const struct noise_set *ns, const struct grid *g,
		  const struct mesh *m, struct tally *t)
{
	memset(t, 0, sizeof(*t));
	for (uint32_t i = 0; i < m->nverts; i += 3) {
		float sun = m->vis[2 * i + 1];
		int c = classify(p, ns, g, m->pos + 3 * i, m->nrm + 3 * i);
		if (c == 1) {
			t->blocked++;
			t->blocked_bad += sun > 0.2f;
			t->sum_blocked += sun;
		} else if (c == 0) {
			t->open++;
			t->open_bad += sun < 0.8f;
			t->sum_open += sun;
		} else {
			t->between++;
		}
	}
	unsigned n = t->blocked + t->open + t->between;
	printf("%s: %u vertices judged: %u blocked (%u lit by the GPU, mean %.3f), %u open (%u shadowed by the GPU, "
	       "mean %.3f), %u between\n",
	       what, n, t->blocked, t->blocked_bad, t->blocked ? t->sum_blocked / t->blocked : 0.0, t->open,
	       t->open_bad, t->open ? t->sum_open / t->open : 0.0, t->between);
	CHECK(t->blocked >= n / 20, "%s: only %u of %u vertices in shadow: the case tests little", what, t->blocked, n);
	CHECK(t->open >= n / 5, "%s: only %u of %u vertices in open sun", what, t->open, n);
	CHECK(t->blocked_bad <= t->blocked / 50, "%s: %u of %u vertices the CPU finds in shadow are lit", what,
	      t->blocked_bad, t->blocked);
	CHECK(t->open_bad <= t->open / 50, "%s: %u of %u vertices the CPU finds in the sun are shadowed", what,
	      t->open_bad, t->open);
}

/* Every vertex in full sun (the rays not cast). */
static void all_lit(const char *what, struct fixture_terrain *ft, const struct params *p)
{
	struct mesh m = { 0 };
	CHECK(fixture_run(ft->pl, p) == 0 && pipeline_read_mesh(ft->pl, &m) == 0, "%s: pipeline", what);
	uint32_t dark = 0;
	for (uint32_t i = 0; m.vis && i < m.nverts; i++)
		dark += m.vis[2 * i + 1] < 1.0f;
	CHECK(m.nverts > 1000 && dark == 0, "%s: %u of %u vertices shadowed", what, dark, m.nverts);
	mesh_free(&m);
}

int main(void)
{
	struct platform *plat = fixture_open();
	/* a low sun from two sides, two seeds; AO off (independent of the sun) */
	static const struct {
		int seed;
		float el, az;
	} cases[] = { { 1, 22.0f, 70.0f }, { 5, 30.0f, -120.0f } };
	for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
		struct params p;
		params_defaults(&p);
		p.grid = 64;
		p.seed = cases[c].seed;
		p.light_el = cases[c].el;
		p.light_az = cases[c].az;
		p.ao_rays = 0;
		p.closed = false;
		struct grid g;
		grid_from_params(&g, &p);
		char err[512] = "", what[64];
		snprintf(what, sizeof(what), "seed %d, sun at %.0f/%.0f deg", p.seed, (double)p.light_el,
			 (double)p.light_az);
		struct fixture_terrain ft;
		CHECK(fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) == 0, "pipeline: %s", err);
		if (!ft.pl)
			continue;
		struct mesh m = { 0 };
		CHECK(fixture_run(ft.pl, &p) == 0 && pipeline_read_mesh(ft.pl, &m) == 0, "%s: pipeline", what);
		struct noise_set ns;
		noise_set_init(&ns, p.seed);
		struct tally t;
		if (m.vis)
			judge(what, &p, &ns, &g, &m, &t);
		mesh_free(&m);
		if (c == 0) {
			struct params q = p;
			q.shadows = 0.0f;
			all_lit("shadows 0", &ft, &q);
			q = p;
			q.shadow_steps = 0;
			all_lit("shadow_steps 0", &ft, &q);
		}
		fixture_terrain_close(&ft);
	}
	platform_close(plat);
	return tc_done("shadows");
}
