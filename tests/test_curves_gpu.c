/* isoterra — test_curves (test_curves.c), on the GPU: closest point and
 * curve evaluation against the CPU, heightmap heights, the density pass
 * with edits against density_ref_volume, a road's centre line in the
 * extracted mesh, and the streaming world re-generating only the blocks an
 * edit reaches. */
#include "curves_test.h"
#include "gpu_fixture.h"
#include "world.h"
#include "terrain.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

/* ---- GPU ------------------------------------------------------------------------------------ */

void test_closest_gpu(struct edits *ed, const struct params *p, const float *items, int n)
{
	char err[512];
	float *out = malloc(sizeof(float) * 4 * (size_t)n);
	int rc = curves_gpu_test(ed, p, 0, items, n, out, err, sizeof(err));
	CHECK(rc == 0, "curve_test mode 0: %s", err);
	double worst = 0, worst_ref = 0;
	int bad = 0, bad_ref = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		const float *it = items + 16 * i;
		float c[3][4], ref[4];
		memcpy(c, it, sizeof(c));
		double b = brute_dist(c, it[12], it[13]);
		double scale = 1.0 + fabs(it[12]) + fabs(it[13]);
		double e = fabs(fabs((double)out[4 * i]) - b) / scale;
		worst = fmax(worst, e);
		bad += e > 2e-5;
		carve_ref_closest(c, it + 12, ref);
		/* |d| (two parts of a curve may be equally near, with either sign) */
		double er = fabs(fabs(out[4 * i]) - fabs(ref[0])) / scale;
		worst_ref = fmax(worst_ref, er);
		bad_ref += er > 1e-5;
	}
	printf("  closest point on the GPU: %d cases, worst error %.3g (relative to 1+|x|+|z|), vs CPU mirror %.3g\n", n,
	       worst, worst_ref);
	CHECK(bad == 0, "GPU closest point: %d of %d off the brute-force distance (worst %.3g)", bad, n, worst);
	CHECK(bad_ref == 0, "GPU vs CPU mirror: %d of %d differ (worst %.3g)", bad_ref, n, worst_ref);
	free(out);
}

void test_eval_gpu(struct edits *ed, struct params *p)
{
	char err[512];
	struct curve_set s;
	random_set(&s, 5, 100.0f);
	CHECK(edits_set_curves(ed, &s, 16, err, sizeof(err)) == 0, "set: %s", err);
	set(p, "curve_incl_lo=0.3;curve_incl_hi=0.9;curve_incl_exp=2;curve_blend_lo=0.2;curve_blend_hi=0.8;curve_strength=0.9");
	int n = 4000;
	float *in = malloc(sizeof(float) * 4 * (size_t)n), *out = malloc(sizeof(float) * 4 * (size_t)n);
	for (int i = 0; i < n; i++) {
		in[4 * i] = frange(-140, 140);
		in[4 * i + 1] = frange(-140, 140);
		in[4 * i + 2] = frange(-10, 10);
		in[4 * i + 3] = frange(-20, 20);
	}
	int rc = curves_gpu_test(ed, p, 1, in, n, out, err, sizeof(err));
	CHECK(rc == 0, "curve_test mode 1: %s", err);
	int bad = 0, influenced = 0;
	double worst = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		float e[4];
		carve_ref_eval(ed, p, in[4 * i], in[4 * i + 1], false, e);
		float d = carve_ref_density(ed, p, in[4 * i], in[4 * i + 2], in[4 * i + 1], in[4 * i + 3]);
		if (e[1] > 0.0f) {
			influenced++;
			double err_h = fabs(out[4 * i] - e[0]), err_t = fabs(out[4 * i + 1] - e[1]);
			worst = fmax(worst, fmax(err_h, err_t));
			bad += err_h > 1e-3 || err_t > 1e-3;
		} else {
			bad += out[4 * i + 1] != 0.0f;
		}
		bad += fabsf(out[4 * i + 3] - d) > 1e-3f * (1.0f + fabsf(d));
	}
	printf("  curve evaluation through the GPU hash: %d points (%d influenced), worst |h|/Θ error %.3g\n", n,
	       influenced, worst);
	CHECK(bad == 0, "GPU curve_eval/carve vs CPU: %d of %d differ (worst %.3g)", bad, n, worst);
	/* (paths 3 and 4 are a tunnel and a bridge: no surface, their tube and
	 * deck checked by the carve above) */
	CHECK(influenced > 120, "points under the surface curves' influence: %d", influenced);
	/* displacement bake: GPU vs CPU, and the iterative baseline near it */
	struct bake_opts o = { { 96, 80 }, { -120, -110 }, { 240, 220 }, false, false };
	float *g = malloc(sizeof(float) * 96 * 80), *c = malloc(sizeof(float) * 96 * 80), *gi = malloc(sizeof(float) * 96 * 80);
	rc = curves_bake(ed, p, &o, g, err, sizeof(err));
	CHECK(rc == 0, "bake: %s", err);
	carve_ref_bake(ed, p, &o, c);
	o.dense = true; /* every texel: the same map as the tiles over non-empty cells */
	CHECK(curves_bake(ed, p, &o, gi, err, sizeof(err)) == 0, "dense bake: %s", err);
	int tdiff = 0;
	for (int i = 0; i < 96 * 80; i++)
		tdiff += gi[i] != g[i];
	CHECK(tdiff == 0, "tiled bake vs dense bake: %d texels differ", tdiff);
	o.iterative = true;
	CHECK(curves_bake(ed, p, &o, gi, err, sizeof(err)) == 0, "iterative bake: %s", err);
	double wb = 0, wi = 0, mean_i = 0;
	int nz = 0;
	for (int i = 0; i < 96 * 80; i++) {
		wb = fmax(wb, fabs(g[i] - c[i]));
		wi = fmax(wi, fabs(gi[i] - g[i]));
		mean_i += fabs(gi[i] - g[i]);
		nz += g[i] != 0.0f;
	}
	mean_i /= 96 * 80;
	printf("  bake 96x80: GPU vs CPU worst %.3g; iterative (32 segments) vs analytic worst %.3g, mean %.3g\n", wb, wi,
	       mean_i);
	CHECK(nz > 200 && wb < 2e-3, "bake GPU vs CPU: worst %g (%d non-zero texels)", wb, nz);
	CHECK(mean_i < 0.05 && wi < 2.0, "iterative baseline close to the analytic bake (worst %g, mean %g)", wi, mean_i);
	free(g);
	free(c);
	free(gi);
	free(in);
	free(out);
	curve_set_free(&s);
	params_defaults(p);
}

void test_heightmap_gpu(struct edits *ed, struct params *p, const struct noise_set *ns)
{
	char err[512];
	struct noise_gl ng;
	CHECK(noise_gl_init(&ng, ns, err, sizeof(err)) == 0, "noise gl: %s", err);
	noise_gl_bind(&ng);
	int n = 2000;
	float *in = malloc(sizeof(float) * 4 * (size_t)n), *out = malloc(sizeof(float) * 4 * (size_t)n);
	for (int i = 0; i < n; i++) {
		in[4 * i] = frange(-12, 12);
		in[4 * i + 1] = frange(-9, 9);
		in[4 * i + 2] = in[4 * i + 3] = 0;
	}
	int rc = curves_gpu_test(ed, p, 2, in, n, out, err, sizeof(err));
	CHECK(rc == 0, "curve_test mode 2: %s", err);
	double w = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		float hf = heightmap_ref_height(ed, p, ns, in[4 * i], in[4 * i + 1], true);
		float hb = heightmap_ref_height(ed, p, ns, in[4 * i], in[4 * i + 1], false);
		w = fmax(w, fmax(fabs(out[4 * i] - hf), fabs(out[4 * i + 1] - hb)));
	}
	CHECK(w < 1e-3, "GPU heightmap (fractal + bilinear) vs CPU: worst %g", w);
	noise_gl_destroy(&ng);
	free(in);
	free(out);
}

/* density pass with curves (terrain) or heightmap vs density_ref_volume */
void check_density(struct edits *ed, const char *what, const struct params *p, int gridn)
{
	char err[512] = "";
	struct params q = *p;
	q.grid = gridn;
	struct grid g;
	grid_from_params(&g, &q);
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &q, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "%s: pipeline_create: %s", what, err);
	if (!pl) {
		terrain_destroy(tr);
		return;
	}
	CHECK(fixture_density(pl, &q) == 0, "%s: density pass", what);
	long nd = grid_dens_count(&g);
	float *dg = malloc(sizeof(float) * (size_t)nd), *dc = malloc(sizeof(float) * (size_t)nd);
	CHECK(pipeline_read_density(pl, dg) == 0, "%s: read", what);
	static struct noise_set ns;
	noise_set_init(&ns, q.seed);
	density_ref_volume(&q, &ns, ed, g.origin, g.cell, g.nx, g.ny, g.nz, dc);
	double dmax = 0, scale = 0;
	for (long i = 0; i < nd; i++) {
		dmax = fmax(dmax, fabs((double)dg[i] - dc[i]));
		scale = fmax(scale, fabs((double)dc[i]));
	}
	printf("  %s: GPU vs CPU density max error %.3g (scale %.3g)\n", what, dmax, scale);
	CHECK(dmax <= 2e-5 * fmax(scale, 1.0), "%s: GPU vs CPU density max error %g (scale %g)", what, dmax, scale);
	free(dg);
	free(dc);
	pipeline_destroy(pl);
	terrain_destroy(tr);
}

/* Heights where a vertical line at (x, z) crosses the mesh. */
static int ray_hits(const struct mesh *m, float x, float z, float *ys, int max)
{
	int n = 0;
	for (uint32_t t = 0; t < m->ntris; t++) {
		const float *a = m->pos + 3 * m->idx[3 * t], *b = m->pos + 3 * m->idx[3 * t + 1],
			    *c = m->pos + 3 * m->idx[3 * t + 2];
		float d = (b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0]);
		if (fabsf(d) < 1e-12f)
			continue;
		float u = ((x - a[0]) * (c[2] - a[2]) - (z - a[2]) * (c[0] - a[0])) / d;
		float v = ((b[0] - a[0]) * (z - a[2]) - (b[2] - a[2]) * (x - a[0])) / d;
		if (u < -1e-5f || v < -1e-5f || u + v > 1.0f + 1e-5f)
			continue;
		if (n < max)
			ys[n++] = a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]);
	}
	return n;
}

/* Top surface height of a density column at (i, k) of the grid (the GPU densities). */
static float column_top(const struct grid *g, const float *dens, int i, int k, float iso)
{
	int sx = g->nx + 3, sy = g->ny + 3;
	for (int j = g->ny - 1; j >= 1; j--) { /* from the top, skipping the closed border */
		float d0 = dens[((size_t)(k + 1) * sy + (size_t)(j + 1)) * sx + (size_t)(i + 1)];
		float d1 = dens[((size_t)(k + 1) * sy + (size_t)(j + 2)) * sx + (size_t)(i + 1)];
		if (d0 > iso && d1 <= iso)
			return g->origin[1] + g->cell * ((float)j + (d0 - iso) / (d0 - d1));
	}
	return NAN;
}

void test_road_centreline(struct edits *ed)
{
	char err[512] = "";
	struct params p;
	params_defaults(&p);
	set(&p, "grid=48;octaves=5;noise_amp=16;closed=true;vol_size=32;vol_height=0.75;vol_y=-1"); /* the diorama box */
	struct grid g;
	grid_from_params(&g, &p);
	/* the road: an S across the volume; first the uncarved surface along it */
	const int NP = 5;
	float pts[5 * 3] = { -14, 0, -9, -5, 0, -3, 0, 0, 1, 6, 0, 2, 14, 0, 9 };
	edits_clear(ed);
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "pipeline: %s", err);
	if (!pl) {
		terrain_destroy(tr);
		return;
	}
	long nd = grid_dens_count(&g);
	float *dens = malloc(sizeof(float) * (size_t)nd);
	CHECK(fixture_density(pl, &p) == 0 && pipeline_read_density(pl, dens) == 0, "uncarved density");
	/* heights of the uncarved terrain at the road's vertices; road at their median */
	float tops[5], sorted[5];
	for (int v = 0; v < NP; v++) {
		int i = (int)lroundf((pts[3 * v] - g.origin[0]) / g.cell), k = (int)lroundf((pts[3 * v + 2] - g.origin[2]) / g.cell);
		tops[v] = column_top(&g, dens, i, k, p.iso);
		sorted[v] = isnan(tops[v]) ? 0.0f : tops[v];
	}
	for (int a = 0; a < NP; a++)
		for (int b = a + 1; b < NP; b++)
			if (sorted[b] < sorted[a]) {
				float t = sorted[a];
				sorted[a] = sorted[b];
				sorted[b] = t;
			}
	for (int v = 0; v < NP; v++) /* a gentle grade around the median */
		pts[3 * v + 1] = sorted[NP / 2] + 0.15f * pts[3 * v];
	struct curve_path rp = make_path(NP, pts, 4.0f, 3.0f, 0.0f, 0.5f);
	struct curve_set rs = { .paths = &rp, .npaths = 1 };
	CHECK(edits_set_curves(ed, &rs, 16, err, sizeof(err)) == 0, "road: %s", err);
	CHECK(fixture_run(pl, &p) == 0, "carved pipeline run");
	struct mesh m;
	CHECK(pipeline_read_mesh(pl, &m) == 0, "read mesh");
	CHECK(pipeline_read_density(pl, dens) == 0, "carved density");
	/* along the centre line, away from the closed volume's walls */
	const struct edits *e = ed;
	int n = 0, bad_mesh = 0, bad_col = 0, cut = 0, fill = 0;
	double worst = 0;
	for (int qi = 0; qi < e->quads.nquads; qi++) {
		float c[3][4];
		curve_quads_get(&e->quads, qi, c);
		for (int s = 0; s < 8; s++) {
			double t = (s + 0.5) / 8.0, x, z;
			qeval(c, t, &x, &z);
			if (fabs(x) > 16 - 3 * g.cell || fabs(z) > 16 - 3 * g.cell)
				continue;
			float ev[4];
			carve_ref_eval(e, &p, (float)x, (float)z, false, ev);
			float h = ev[0];
			float ys[16];
			int nh = ray_hits(&m, (float)x, (float)z, ys, 16), nk = 0;
			for (int k = 0; k < nh; k++) /* not the closed volume's floor and ceiling */
				if (ys[k] > g.origin[1] + 1.5f * g.cell && ys[k] < g.origin[1] + ((float)g.ny - 1.5f) * g.cell)
					ys[nk++] = ys[k];
			nh = nk;
			int ok = nh > 0;
			for (int k = 0; k < nh; k++) {
				ok &= fabsf(ys[k] - h) <= g.cell;
				worst = fmax(worst, fabs(ys[k] - h));
			}
			bad_mesh += !ok;
			/* the density column at the nearest grid column */
			int ci = (int)lroundf(((float)x - g.origin[0]) / g.cell), ck = (int)lroundf(((float)z - g.origin[2]) / g.cell);
			float cx = g.origin[0] + (float)ci * g.cell, cz = g.origin[2] + (float)ck * g.cell;
			carve_ref_eval(e, &p, cx, cz, false, ev);
			float top = column_top(&g, dens, ci, ck, p.iso);
			bad_col += !(fabsf(top - ev[0]) <= g.cell);
			n++;
		}
	}
	for (int v = 0; v < NP; v++) {
		if (isnan(tops[v]))
			continue;
		cut += tops[v] > pts[3 * v + 1] + 2 * g.cell;
		fill += tops[v] < pts[3 * v + 1] - 2 * g.cell;
	}
	printf("  road centre line: %d points, worst |mesh y - curve height| %.3f (voxel %.3f); uncarved terrain above "
	       "the road at %d vertices, below at %d\n",
	       n, worst, g.cell, cut, fill);
	CHECK(n >= 40, "centre-line points checked: %d", n);
	CHECK(bad_mesh == 0, "%d of %d centre-line points: the mesh is not at the curve height +- one voxel (worst %g)",
	      bad_mesh, n, worst);
	CHECK(bad_col == 0, "%d of %d density columns: surface not at the curve height +- one voxel", bad_col, n);
	CHECK(cut > 0 && fill > 0, "the road both cuts (%d) and fills (%d) the terrain", cut, fill);
	mesh_free(&m);
	free(dens);
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_clear(ed);
}

/* ---- edits re-generate only the affected world blocks ------------------------ */

#define WB_LODS 2
#define WB_R 12 /* block indices -WB_R..WB_R-1 in x and z, -4..3 in y */
struct wb_snap {
	int gens[WB_LODS][8][2 * WB_R][2 * WB_R];
	int state[WB_LODS][8][2 * WB_R][2 * WB_R];
};

static void wb_snapshot(const struct world *w, struct wb_snap *s)
{
	for (int l = 0; l < WB_LODS; l++)
		for (int y = 0; y < 8; y++)
			for (int z = 0; z < 2 * WB_R; z++)
				for (int x = 0; x < 2 * WB_R; x++) {
					int idx[3] = { x - WB_R, y - 4, z - WB_R };
					s->gens[l][y][z][x] = world_block_generations(w, l, idx, &s->state[l][y][z][x]);
				}
}

/* Blocks of the world (known before the edit) whose density samples see a
 * curve (Θ > 0 somewhere in the block's XZ footprint padded by its sample
 * margin), by sampling the CPU mirror of the carve on a fine XZ grid: the
 * blocks an edit of these curves must re-generate. */
static void wb_touched(const struct edits *ed, const struct params *p, const struct wb_snap *before, bool touched[WB_LODS][2 * WB_R][2 * WB_R])
{
	const struct edits *e = ed;
	memset(touched, 0, sizeof(bool) * WB_LODS * 4 * WB_R * WB_R);
	const float step = 0.25f;
	for (float z = -WB_R * p->block_size * 2; z < WB_R * p->block_size * 2; z += step)
		for (float x = -WB_R * p->block_size * 2; x < WB_R * p->block_size * 2; x += step) {
			float ev[4];
			carve_ref_eval(e, p, x, z, false, ev);
			if (ev[1] <= 0.0f)
				continue;
			for (int l = 0; l < WB_LODS; l++) {
				float bs = p->block_size * (float)(1 << l);
				/* world.c: 1 + AO_MARGIN (6) density samples around a block */
				float pad = 7.0f * bs / (float)p->block_cells;
				for (int bz = 0; bz < 2 * WB_R; bz++)
					for (int bx = 0; bx < 2 * WB_R; bx++) {
						float lx = (float)(bx - WB_R) * bs, lz = (float)(bz - WB_R) * bs;
						if (x >= lx - pad && x <= lx + bs + pad && z >= lz - pad && z <= lz + bs + pad)
							touched[l][bz][bx] = true;
					}
			}
		}
	(void)before;
}

/* One edit: the blocks re-generated must include every known block whose
 * samples the changed curves reach, and lie within the path's padded
 * bounding box (computed here from the input points). */
static void wb_check_edit(struct edits *ed, const char *what, struct world *w, const struct params *p, const struct camera *c,
			  const struct curve_set *next, const float *pts, int npts, float reach)
{
	static struct wb_snap before, after;
	static bool touched_old[WB_LODS][2 * WB_R][2 * WB_R], touched_new[WB_LODS][2 * WB_R][2 * WB_R];
	char err[256];
	wb_snapshot(w, &before);
	wb_touched(ed, p, &before, touched_old);
	struct world_stats s0, s1;
	world_get_stats(w, &s0);
	CHECK(edits_set_curves(ed, next, 16, err, sizeof(err)) == 0, "%s: %s", what, err);
	wb_touched(ed, p, &before, touched_new);
	CHECK(world_fill(w, p, c, 1.0) == 0, "%s: world_fill", what);
	world_get_stats(w, &s1);
	wb_snapshot(w, &after);
	float bx0 = FLT_MAX, bz0 = FLT_MAX, bx1 = -FLT_MAX, bz1 = -FLT_MAX;
	for (int i = 0; i < npts; i++) {
		bx0 = fminf(bx0, pts[3 * i] - reach);
		bx1 = fmaxf(bx1, pts[3 * i] + reach);
		bz0 = fminf(bz0, pts[3 * i + 2] - reach);
		bz1 = fmaxf(bz1, pts[3 * i + 2] + reach);
	}
	int known = 0, regen = 0, must = 0, missed = 0, outside = 0;
	for (int l = 0; l < WB_LODS; l++) {
		float bs = p->block_size * (float)(1 << l);
		float pad = 8.0f * bs / (float)p->block_cells; /* the margin + one cell of rounding */
		for (int y = 0; y < 8; y++)
			for (int z = 0; z < 2 * WB_R; z++)
				for (int x = 0; x < 2 * WB_R; x++) {
					int st = before.state[l][y][z][x];
					if (st == 0) /* unknown or evicted */
						continue;
					known++;
					bool again = after.gens[l][y][z][x] > before.gens[l][y][z][x];
					regen += again;
					if (touched_old[l][z][x] || touched_new[l][z][x]) {
						must++;
						missed += !again;
					}
					float lx = (float)(x - WB_R) * bs, lz = (float)(z - WB_R) * bs;
					bool in_box = lx + bs + pad >= bx0 && lx - pad <= bx1 && lz + bs + pad >= bz0 && lz - pad <= bz1;
					outside += again && !in_box;
				}
	}
	printf("  world edit (%s): %d known blocks, %d must re-generate, %d re-generated (%llu generations in all)\n",
	       what, known, must, regen, (unsigned long long)(s1.generated - s0.generated));
	CHECK(must > 0, "%s: the edit touches blocks of the view", what);
	CHECK(missed == 0, "%s: %d blocks under the edit were not re-generated", what, missed);
	CHECK(outside == 0, "%s: %d blocks away from the edited path were re-generated", what, outside);
	CHECK(regen < known / 2, "%s: %d of %d blocks re-generated: not local", what, regen, known);
	CHECK(s1.generated - s0.generated == (uint64_t)regen, "%s: generations %llu == blocks re-generated %d", what,
	      (unsigned long long)(s1.generated - s0.generated), regen);
}

void test_world_edits(struct edits *ed)
{
	struct params p;
	params_defaults(&p);
	set(&p, "scene=world;block_pool=200;view_distance=40;lod_levels=2;ao_rays=0;fade_time=0;gen_per_frame=64");
	edits_clear(ed);
	char err[512] = "";
	struct world *w = world_create(&p, ed, err, sizeof(err));
	CHECK(w != NULL, "world_create: %s", err);
	if (!w)
		return;
	struct camera c;
	float eye[3] = { 0, 14, 30 }, at[3] = { 0, 0, 0 };
	camera_look(&c, eye, at, p.fov, 1.5f, 0.1f, 100.0f);
	CHECK(world_fill(w, &p, &c, 0.0) == 0, "world_fill");
	struct world_stats st;
	world_get_stats(w, &st);
	uint64_t g0 = st.generated;
	CHECK(world_fill(w, &p, &c, 0.5) == 0, "world_fill again");
	world_get_stats(w, &st);
	CHECK(st.generated == g0, "no edit, nothing re-generated (%llu -> %llu)", (unsigned long long)g0,
	      (unsigned long long)st.generated);
	/* a road across part of the view, then moved, then removed */
	float a[3 * 3] = { -10, 0.5f, -2, -2, 1.0f, 2, 6, 1.5f, 0 };
	struct curve_path rp = make_path(3, a, 3.0f, 2.0f, 0.0f, 0.5f);
	struct curve_set rs = { .paths = &rp, .npaths = 1 };
	float reach = 3.0f / 2 + 2.0f;
	wb_check_edit(ed, "road added", w, &p, &c, &rs, a, 3, reach);
	float b[3 * 3] = { -10, 0.5f, -2, -2, 3.0f, 2, 6, 1.5f, 0 }, ab[6 * 3];
	memcpy(ab, a, sizeof(a));
	memcpy(ab + 9, b, sizeof(b));
	rp.pts = b;
	wb_check_edit(ed, "road raised", w, &p, &c, &rs, ab, 6, reach);
	struct curve_set none = { .paths = NULL, .npaths = 0 };
	wb_check_edit(ed, "road removed", w, &p, &c, &none, b, 3, reach);
	world_destroy(w);
	edits_clear(ed);
}
