/* isoterra — no floating one-sample debris: the default terrain (and two
 * more seeds) has samples inside the rock none of whose six neighbours is
 * (counted on the GPU's own densities: each would have been a speck of
 * eight triangles, a closed component of its own), and the extracted mesh,
 * read back, has no component of at most eight triangles apart from pieces
 * cut by the box's sides. */
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

int main(void)
{
	struct platform *plat = fixture_open();
	static const int seeds[] = { 10, 1, 77 };
	int before_total = 0;
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
		int before = dens ? islands(&g, dens, p.iso) : -1, after = specks(&g, &m, 8);
		printf("seed %5d: %d one-sample islands in the field (specks of 8 triangles unfiltered), "
		       "%d components of <= 8 triangles in the mesh (%u triangles)\n",
		       p.seed, before, after, m.ntris);
		before_total += before;
		CHECK(after == 0, "seed %d: %d floating specks left", p.seed, after);
		mesh_free(&m);
		free(dens);
		fixture_terrain_close(&ft);
	}
	/* the seeds do make debris, so the check above means something */
	CHECK(before_total >= 3, "only %d one-sample islands in the fields: the seeds test nothing", before_total);
	platform_close(plat);
	return tc_done("debris");
}
