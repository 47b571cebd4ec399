/* isoterra — no floating debris of a few samples: the default terrain
 * (and more seeds) has, in the GPU's own densities, components of inside
 * samples (6-connected, labelled here on the CPU) that span at most
 * DEBRIS_SPAN (abi.h: six) samples along each axis: single samples, pairs,
 * clumps, each of which would float as a closed speck or rock.  The
 * extracted mesh, read back, has no vertex on the grid edges that leave
 * those components' samples, and no component of at most eight triangles
 * apart from pieces cut by the box's sides.  And the filter takes no
 * more: every component that spans one or two samples more (as small, and
 * not debris) still has its vertices, every one of them.  A vertex counts
 * for the components of its grid edge's two samples (the edge found even
 * where the vertex lies within a thousandth of a cell of one end), not for
 * a speck whose neighbour along the edge is a filled bubble: the speck
 * plugged a one-sample pit, and the vertex is the filled rock's.  One seed
 * has a clump with a run of six samples along x, the longest a candidate
 * may have: a filter whose runs were one shorter keeps it, and fails. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "terrain.h"
#include "abi.h"

#include <math.h>
#include <string.h>

static uint32_t root(uint32_t *par, uint32_t x)
{
	while (par[x] != x)
		x = par[x] = par[par[x]];
	return x;
}

static int on_border(const struct grid *g, const float *p)
{
	int n[3] = { g->nx, g->ny, g->nz };
	for (int a = 0; a < 3; a++) {
		float lo = g->origin[a], hi = g->origin[a] + (float)n[a] * g->cell, eps = 1e-4f * g->cell;
		if (fabsf(p[a] - lo) < eps || fabsf(p[a] - hi) < eps)
			return 1;
	}
	return 0;
}

/* Components of at most max_tris triangles none of whose vertices lies on
 * the box's sides (those are pieces of larger rock cut by the box). */
static int specks(const struct grid *g, const struct mesh *m, uint32_t max_tris)
{
	uint32_t *par = malloc(sizeof(uint32_t) * m->nverts), *tris = calloc(m->nverts, sizeof(uint32_t));
	unsigned char *cut = calloc(m->nverts, 1);
	if (!par || !tris || !cut) {
		free(par), free(tris), free(cut);
		return -1;
	}
	for (uint32_t v = 0; v < m->nverts; v++)
		par[v] = v;
	for (uint32_t t = 0; t < m->ntris; t++) {
		uint32_t a = root(par, m->idx[3 * t]);
		for (int k = 1; k < 3; k++) {
			uint32_t b = root(par, m->idx[3 * t + k]);
			if (a != b)
				par[b] = a;
		}
	}
	for (uint32_t t = 0; t < m->ntris; t++)
		tris[root(par, m->idx[3 * t])]++;
	for (uint32_t v = 0; v < m->nverts; v++)
		if (on_border(g, m->pos + 3 * v))
			cut[root(par, v)] = 1;
	int n = 0;
	for (uint32_t v = 0; v < m->nverts; v++)
		if (par[v] == v && tris[v] > 0 && tris[v] <= max_tris && !cut[v])
			n++;
	free(par), free(tris), free(cut);
	return n;
}

/* The components of inside samples (raw densities, 6-connected, over every
 * stored sample), by label: their span along each axis and whether one
 * lies on or beyond the box's sides (its mesh would be cut). */
struct comp {
	int lo[3], hi[3];
	int size;
	int run; /* its longest run of inside samples along x or y */
	bool edge;
};

static int span(const struct comp *c)
{
	int s = 0;
	for (int a = 0; a < 3; a++)
		s = c->hi[a] - c->lo[a] + 1 > s ? c->hi[a] - c->lo[a] + 1 : s;
	return s;
}

/* Labels each stored sample (-1: outside) into lab; the components into
 * *out.  Returns their count, or -1. */
static int label(const struct grid *g, const float *dens, float iso, int32_t *lab, struct comp **out)
{
	int m = grid_margin(g), d[3] = { g->nx + 1 + 2 * m, g->ny + 1 + 2 * m, g->nz + 1 + 2 * m };
	long n = grid_dens_count(g);
	uint32_t *par = malloc(sizeof(uint32_t) * (size_t)n);
	if (!par)
		return -1;
	for (long i = 0; i < n; i++)
		par[i] = (uint32_t)i;
	for (int k = 0; k < d[2]; k++)
		for (int j = 0; j < d[1]; j++)
			for (int i = 0; i < d[0]; i++) {
				long c = i + (long)d[0] * (j + (long)d[1] * k);
				if (!(dens[c] > iso))
					continue;
				long nb[3] = { i + 1 < d[0] ? c + 1 : -1, j + 1 < d[1] ? c + d[0] : -1,
					       k + 1 < d[2] ? c + (long)d[0] * d[1] : -1 };
				for (int a = 0; a < 3; a++)
					if (nb[a] >= 0 && dens[nb[a]] > iso) {
						uint32_t ra = root(par, (uint32_t)c), rb = root(par, (uint32_t)nb[a]);
						if (ra != rb)
							par[rb] = ra;
					}
			}
	int nc = 0;
	for (long i = 0; i < n; i++)
		lab[i] = -1;
	for (long i = 0; i < n; i++)
		if (dens[i] > iso && par[i] == (uint32_t)i)
			lab[i] = nc++;
	struct comp *c = calloc(nc ? (size_t)nc : 1, sizeof(*c));
	if (!c) {
		free(par);
		return -1;
	}
	for (int q = 0; q < nc; q++)
		for (int a = 0; a < 3; a++)
			c[q].lo[a] = 1 << 30, c[q].hi[a] = -(1 << 30);
	int *ry = calloc((size_t)d[0], sizeof(int)); /* the y run ending at each x of the row */
	if (!ry) {
		free(par), free(c);
		return -1;
	}
	for (int k = 0; k < d[2]; k++)
		for (int j = 0; j < d[1]; j++)
			for (int i = 0, rx = 0; i < d[0]; i++) {
				long s = i + (long)d[0] * (j + (long)d[1] * k);
				if (!(dens[s] > iso)) {
					rx = ry[i] = 0;
					continue;
				}
				rx++;
				ry[i] = j ? ry[i] + 1 : 1;
				int q = lab[s] = lab[root(par, (uint32_t)s)];
				int at[3] = { i - m, j - m, k - m }, n3[3] = { g->nx, g->ny, g->nz };
				c[q].size++;
				c[q].run = rx > c[q].run ? rx : c[q].run;
				c[q].run = ry[i] > c[q].run ? ry[i] : c[q].run;
				for (int a = 0; a < 3; a++) {
					c[q].lo[a] = at[a] < c[q].lo[a] ? at[a] : c[q].lo[a];
					c[q].hi[a] = at[a] > c[q].hi[a] ? at[a] : c[q].hi[a];
					if (at[a] <= 0 || at[a] >= n3[a])
						c[q].edge = true;
				}
			}
	free(par), free(ry);
	*out = c;
	return nc;
}

/* The two samples of the grid edge vertex p lies on (their coordinates;
 * returns 0 when it lies on none, 1 when on a sample itself): marching
 * cubes puts each vertex on the grid edge whose two samples it separates,
 * at a fraction of the edge that may fall within a thousandth of either
 * end, so the edge is the axis farthest from a whole number of cells (the
 * other two lie on whole numbers up to the float's rounding). */
static int edge_ends(const struct grid *g, const float *p, int ends[2][3])
{
	int at[3], along = -1;
	float u[3], off = 1e-5f; /* under this, on a sample */
	for (int a = 0; a < 3; a++) {
		u[a] = (p[a] - g->origin[a]) / g->cell;
		float d = fabsf(u[a] - roundf(u[a]));
		if (d > off)
			off = d, along = a;
	}
	for (int a = 0; a < 3; a++) {
		if (a != along && fabsf(u[a] - roundf(u[a])) >= 1e-3f)
			return 0; /* on no grid edge */
		at[a] = a == along ? (int)floorf(u[a]) : (int)roundf(u[a]);
	}
	int m = grid_margin(g), n3[3] = { g->nx, g->ny, g->nz };
	for (int e = 0; e < (along < 0 ? 1 : 2); e++) {
		int q[3] = { at[0], at[1], at[2] };
		if (e)
			q[along]++;
		for (int a = 0; a < 3; a++) {
			if (q[a] < -m || q[a] > n3[a] + m)
				return 0;
			ends[e][a] = q[a];
		}
	}
	return along < 0 ? 1 : 2;
}

static bool raw_in(const struct grid *g, const float *dens, float iso, int i, int j, int k)
{
	return dens[grid_dens_index(g, i, j, k)] > iso;
}

/* An outside sample whose six neighbours are inside: the filter fills it
 * (docs/PIPELINE.md, "No floating debris of a few samples"). */
static bool bubble(const struct grid *g, const float *dens, float iso, int i, int j, int k)
{
	static const int nb[6][3] = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 } };
	int m = grid_margin(g), lo = -m + 1, at[3] = { i, j, k }, n3[3] = { g->nx, g->ny, g->nz };
	for (int a = 0; a < 3; a++)
		if (at[a] < lo || at[a] > n3[a] + m - 1)
			return false; /* a neighbour beyond the stored samples: outside */
	if (raw_in(g, dens, iso, i, j, k))
		return false;
	for (int f = 0; f < 6; f++)
		if (!raw_in(g, dens, iso, i + nb[f][0], j + nb[f][1], k + nb[f][2]))
			return false;
	return true;
}

/* The vertices a kept component must have: one on each grid edge from one
 * of its samples to an outside neighbour, less the neighbours that are
 * one-sample bubbles (the filter fills those). */
static int expected_verts(const struct grid *g, const float *dens, float iso, const int32_t *lab, int32_t q,
			  const struct comp *c)
{
	static const int nb[6][3] = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 } };
	int n = 0;
	for (int k = c->lo[2]; k <= c->hi[2]; k++)
		for (int j = c->lo[1]; j <= c->hi[1]; j++)
			for (int i = c->lo[0]; i <= c->hi[0]; i++) {
				if (lab[grid_dens_index(g, i, j, k)] != q)
					continue;
				for (int d = 0; d < 6; d++) {
					int a = i + nb[d][0], b = j + nb[d][1], e = k + nb[d][2];
					n += !raw_in(g, dens, iso, a, b, e) && !bubble(g, dens, iso, a, b, e);
				}
			}
	return n;
}

int main(void)
{
	struct platform *plat = fixture_open();
	/* seed 3 has a clump with a run of six samples along x (the longest a
	 * candidate may have); the other three none */
	static const int seeds[] = { 10, 1, 77, 7, 3 };
	int by_size[3] = { 0, 0, 0 }, kept_total = 0, full_total = 0;
	for (size_t s = 0; s < sizeof(seeds) / sizeof(seeds[0]); s++) {
		struct params p;
		params_defaults(&p);
		p.seed = seeds[s];
		p.ao_rays = 0; /* shading, not geometry */
		struct grid g;
		grid_from_params(&g, &p);
		char err[512] = "";
		struct fixture_terrain ft;
		CHECK(fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) == 0, "pipeline: %s", err);
		if (!ft.pl)
			continue;
		CHECK(fixture_run(ft.pl, &p) == 0, "seed %d: pipeline_run", p.seed);
		long nd = grid_dens_count(&g);
		float *dens = malloc(sizeof(float) * (size_t)nd);
		int32_t *lab = malloc(sizeof(int32_t) * (size_t)nd);
		struct mesh m = { 0 };
		struct comp *c = NULL;
		CHECK(dens && lab && pipeline_read_density(ft.pl, dens) == 0, "seed %d: read density", p.seed);
		CHECK(pipeline_read_mesh(ft.pl, &m) == 0, "seed %d: read mesh", p.seed);
		int nc = dens && lab ? label(&g, dens, p.iso, lab, &c) : -1;
		CHECK(nc >= 0, "seed %d: labelling: out of memory", p.seed);
		int *verts = calloc(nc > 0 ? (size_t)nc : 1, sizeof(int));
		if (nc < 0 || !verts) {
			free(verts), free(c), free(lab), free(dens), mesh_free(&m);
			fixture_terrain_close(&ft);
			continue;
		}
		/* each vertex counts for the components of its edge's samples, but
		 * not for debris whose neighbour along the edge is a bubble: the
		 * filter filled that one and dropped the debris, and the vertex
		 * between them is the filled rock's (a speck plugging a one-sample
		 * pit) */
		for (uint32_t v = 0; v < m.nverts; v++) {
			int at[2][3], ne = edge_ends(&g, m.pos + 3 * v, at);
			for (int e = 0; e < ne; e++) {
				int32_t q = lab[grid_dens_index(&g, at[e][0], at[e][1], at[e][2])];
				if (q < 0)
					continue;
				if (ne == 2 && !c[q].edge && span(&c[q]) <= DEBRIS_SPAN &&
				    bubble(&g, dens, p.iso, at[1 - e][0], at[1 - e][1], at[1 - e][2]))
					continue;
				verts[q]++;
			}
		}
		int debris[3] = { 0, 0, 0 }, left = 0, kept = 0, kept_bad = 0, full = 0;
		for (int q = 0; q < nc; q++) {
			if (c[q].edge)
				continue; /* cut by the box: not all of it is in view of the grid */
			int sp = span(&c[q]);
			if (sp <= DEBRIS_SPAN) {
				debris[c[q].size == 1 ? 0 : c[q].size == 2 ? 1 : 2]++;
				full += c[q].run == DEBRIS_SPAN;
				left += verts[q];
			} else if (sp <= DEBRIS_SPAN + 2) {
				int want = expected_verts(&g, dens, p.iso, lab, q, &c[q]);
				kept++;
				if (verts[q] != want && kept_bad++ < 3)
					printf("  seed %d: a component of %d samples spanning %d has %d vertices, not %d\n", p.seed,
					       c[q].size, sp, verts[q], want);
			}
		}
		int after = specks(&g, &m, 8);
		printf("seed %5d: debris in the field: %d single samples, %d pairs, %d clumps of 3+ (span <= %d; %d with a "
		       "run of %d along x or y); %d vertices on their edges in the mesh (%u triangles); %d components of "
		       "<= 8 triangles; %d components spanning %d-%d samples, %d missing vertices\n",
		       p.seed, debris[0], debris[1], debris[2], DEBRIS_SPAN, full, DEBRIS_SPAN, left, m.ntris, after, kept,
		       DEBRIS_SPAN + 1, DEBRIS_SPAN + 2, kept_bad);
		CHECK(left == 0, "seed %d: the debris left %d vertices", p.seed, left);
		CHECK(after == 0, "seed %d: %d floating specks left", p.seed, after);
		CHECK(kept_bad == 0, "seed %d: %d components spanning %d-%d samples lost vertices", p.seed, kept_bad,
		      DEBRIS_SPAN + 1, DEBRIS_SPAN + 2);
		for (int k = 0; k < 3; k++)
			by_size[k] += debris[k];
		kept_total += kept;
		full_total += full;
		free(verts), free(c), free(lab), free(dens);
		mesh_free(&m);
		fixture_terrain_close(&ft);
	}
	/* the seeds do make debris of each kind, and components just too
	 * large to be debris, so the checks above mean something */
	CHECK(by_size[0] >= 3, "only %d one-sample islands in the fields: the seeds test nothing", by_size[0]);
	CHECK(by_size[1] >= 1, "no two-sample island in the fields: the seeds test nothing of the pairs");
	CHECK(by_size[2] >= 3, "only %d clumps of 3+ samples in the fields: the seeds test little of them", by_size[2]);
	CHECK(kept_total >= 1, "no component spanning %d-%d samples in the fields: nothing shows the filter keeps them",
	      DEBRIS_SPAN + 1, DEBRIS_SPAN + 2);
	CHECK(full_total >= 1, "no debris with a run of %d samples in the fields: nothing shows the filter's longest run",
	      DEBRIS_SPAN);
	platform_close(plat);
	return tc_done("debris");
}
