/* isoterra — no floating one- or two-sample debris: the default terrain
 * (and two more seeds) has samples inside the rock none of whose six
 * neighbours is, and pairs of inside samples with no other inside
 * neighbour (counted on the GPU's own densities: each would have been a
 * speck of eight or sixteen triangles, a closed component of its own), and
 * the extracted mesh, read back, has no component of at most eight
 * triangles apart from pieces cut by the box's sides, and no vertex around
 * a pair's two samples. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "terrain.h"

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

/* Samples of the cells' corners strictly inside the box that are inside
 * the rock with all six neighbours outside (raw densities). */
static int islands(const struct grid *g, const float *dens, float iso)
{
	int n = 0;
	for (int k = 1; k < g->nz; k++)
		for (int j = 1; j < g->ny; j++)
			for (int i = 1; i < g->nx; i++) {
				if (!(dens[grid_dens_index(g, i, j, k)] > iso))
					continue;
				int any = dens[grid_dens_index(g, i - 1, j, k)] > iso ||
					  dens[grid_dens_index(g, i + 1, j, k)] > iso ||
					  dens[grid_dens_index(g, i, j - 1, k)] > iso ||
					  dens[grid_dens_index(g, i, j + 1, k)] > iso ||
					  dens[grid_dens_index(g, i, j, k - 1)] > iso ||
					  dens[grid_dens_index(g, i, j, k + 1)] > iso;
				n += !any;
			}
	return n;
}

/* Pairs of adjacent samples strictly inside the box, both inside the rock,
 * neither with another inside neighbour (raw densities); the world
 * positions of the first 16 pairs' two samples into at[] (x, y, z of the
 * lower, then of the upper). */
static int pairs(const struct grid *g, const float *dens, float iso, float at[16][6])
{
	static const int nb[6][3] = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 } };
	int n = 0;
	for (int k = 2; k < g->nz - 1; k++)
		for (int j = 2; j < g->ny - 1; j++)
			for (int i = 2; i < g->nx - 1; i++) {
				if (!(dens[grid_dens_index(g, i, j, k)] > iso))
					continue;
				int count = 0, only = -1;
				for (int d = 0; d < 6; d++)
					if (dens[grid_dens_index(g, i + nb[d][0], j + nb[d][1], k + nb[d][2])] > iso)
						count++, only = d;
				if (count != 1 || (only & 1) == 0)
					continue; /* each pair once: from its lower sample */
				int q[3] = { i + nb[only][0], j + nb[only][1], k + nb[only][2] }, other = 0;
				for (int d = 0; d < 6; d++)
					if (d != (only ^ 1))
						other += dens[grid_dens_index(g, q[0] + nb[d][0], q[1] + nb[d][1], q[2] + nb[d][2])] > iso;
				if (other == 0 && n < 16) {
					int c[3] = { i, j, k };
					for (int a = 0; a < 3; a++) {
						at[n][a] = g->origin[a] + (float)c[a] * g->cell;
						at[n][3 + a] = g->origin[a] + (float)q[a] * g->cell;
					}
				}
				n += other == 0;
			}
	return n;
}

/* Mesh vertices on the grid edges that leave the pairs' samples: a pair's
 * speck has its vertices there (marching cubes puts each vertex on the
 * edge whose ends it separates), and no other surface has, so rock on a
 * diagonal next to a pair (no six-neighbour: the pair stays an island)
 * does not count. */
static int near_pairs(const struct grid *g, const struct mesh *m, float at[16][6], int n)
{
	int near = 0;
	float eps = 1e-3f * g->cell;
	for (int q = 0; q < n && q < 16; q++)
		for (uint32_t v = 0; v < m->nverts; v++) {
			const float *p = m->pos + 3 * v;
			int on = 0;
			for (int e = 0; e < 2 && !on; e++) {
				const float *c = at[q] + 3 * e;
				for (int a = 0; a < 3 && !on; a++) { /* along axis a, the other two on the sample's lines */
					int b = (a + 1) % 3, d = (a + 2) % 3;
					on = fabsf(p[b] - c[b]) < eps && fabsf(p[d] - c[d]) < eps &&
					     fabsf(p[a] - c[a]) < g->cell - eps;
				}
			}
			near += on;
		}
	return near;
}

int main(void)
{
	struct platform *plat = fixture_open();
	static const int seeds[] = { 10, 1, 77 };
	int before_total = 0, pairs_total = 0;
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
		float *dens = malloc(sizeof(float) * (size_t)grid_dens_count(&g));
		struct mesh m = { 0 };
		CHECK(dens && pipeline_read_density(ft.pl, dens) == 0, "seed %d: read density", p.seed);
		CHECK(pipeline_read_mesh(ft.pl, &m) == 0, "seed %d: read mesh", p.seed);
		float at[16][6];
		int before = dens ? islands(&g, dens, p.iso) : -1, two = dens ? pairs(&g, dens, p.iso, at) : -1;
		int after = specks(&g, &m, 8), left = near_pairs(&g, &m, at, two);
		printf("seed %5d: %d one-sample islands and %d two-sample ones in the field; in the mesh (%u triangles) "
		       "%d components of <= 8 triangles, %d vertices around the pairs\n",
		       p.seed, before, two, m.ntris, after, left);
		CHECK(left == 0, "seed %d: the two-sample islands left %d vertices", p.seed, left);
		before_total += before;
		pairs_total += two;
		CHECK(after == 0, "seed %d: %d floating specks left", p.seed, after);
		mesh_free(&m);
		free(dens);
		fixture_terrain_close(&ft);
	}
	/* the seeds do make debris, so the check above means something */
	CHECK(before_total >= 3, "only %d one-sample islands in the fields: the seeds test nothing", before_total);
	CHECK(pairs_total >= 1, "no two-sample island in the fields: the seeds test nothing of the pairs");
	platform_close(plat);
	return tc_done("debris");
}
