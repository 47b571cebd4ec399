/* isoterra — Marching Cubes tables and CPU extractor: table properties,
 * watertightness on random and analytic fields, orientation, accuracy.
 * The fields here are computed by the test itself (not by density_ref). */
#include "app.h"
#include "tcheck.h"
#include "mesh_check.h"

#include <math.h>
#include <stdint.h>

static void check_tables(void)
{
	struct mc_tables tables;
	mc_tables_build(&tables);
	const struct mc_tables *t = &tables;
	CHECK(t->tri_count[0] == 0 && t->tri_count[255] == 0, "cases 0 and 255 emit nothing");
	int max = 0, bad_edges = 0, missing = 0;
	for (int cs = 1; cs < 255; cs++) {
		int used[12] = { 0 };
		CHECK(t->tri_count[cs] >= 1 && t->tri_count[cs] <= 5, "case %d: %d triangles", cs, t->tri_count[cs]);
		if (t->tri_count[cs] > max)
			max = t->tri_count[cs];
		for (int k = 0; k < t->tri_count[cs] * 3; k++)
			used[t->tri[cs][k]] = 1;
		for (int e = 0; e < 12; e++) {
			int a = (cs >> t->edge_corner[e][0]) & 1, b = (cs >> t->edge_corner[e][1]) & 1;
			if (used[e] && a == b)
				bad_edges++;
			if (!used[e] && a != b)
				missing++;
		}
	}
	CHECK(max == 5, "max triangles per cell %d", max);
	CHECK(bad_edges == 0, "%d triangles use an edge the surface does not cross", bad_edges);
	CHECK(missing == 0, "%d crossed edges have no vertex", missing);
	/* the chapter's example: case 193 = corners 0, 6, 7 -> triangle (8,3,0)
	 * around corner 0 and the quad {5,7,10,11} */
	CHECK(t->tri_count[193] == 3, "case 193 has 3 triangles");
	int corner0 = 0, quad = 0;
	for (int i = 0; i < 3; i++) {
		int s = 0;
		for (int k = 0; k < 3; k++)
			s |= 1 << t->tri[193][3 * i + k];
		if (s == ((1 << 0) | (1 << 3) | (1 << 8))) {
			corner0++;
			/* winding: (8,3,0) up to rotation */
			const int8_t *v = &t->tri[193][3 * i];
			int rot = (v[0] == 8 && v[1] == 3) || (v[0] == 3 && v[1] == 0) || (v[0] == 0 && v[1] == 8);
			CHECK(rot, "case 193 corner-0 triangle winds like the chapter's (8,3,0)");
		} else if ((s & ~((1 << 5) | (1 << 7) | (1 << 10) | (1 << 11))) == 0) {
			quad++;
		}
	}
	CHECK(corner0 == 1 && quad == 2, "case 193 geometry (corner0 %d, quad %d)", corner0, quad);
	/* ownership: edges 3, 0, 8 belong to the cell itself, slots x, y, z */
	CHECK(t->edge_owner[3][3] == 0 && t->edge_owner[0][3] == 1 && t->edge_owner[8][3] == 2, "slots of 3/0/8");
	for (int e = 0; e < 12; e++) {
		const int8_t *o = t->edge_owner[e];
		int a = t->edge_corner[e][0], b = t->edge_corner[e][1];
		int lo = t->corner[a][o[3]] < t->corner[b][o[3]] ? a : b;
		CHECK(o[0] == t->corner[lo][0] && o[1] == t->corner[lo][1] && o[2] == t->corner[lo][2], "owner of edge %d", e);
	}
}

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static float frand(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (float)((rng >> 11) & 0xffffff) / (float)0x1000000;
}

typedef float (*field_fn)(float x, float y, float z);
static float f_sphere(float x, float y, float z) { return 0.8f - sqrtf(x * x + y * y + z * z); }
static float f_torus(float x, float y, float z)
{
	float q = 0.6f - sqrtf(x * x + z * z);
	return 0.16f - q * q - y * y;
}

static float *sample(const struct grid *g, field_fn f)
{
	float *d = malloc(sizeof(float) * (size_t)grid_dens_count(g));
	for (int k = -1; k <= g->nz + 1; k++)
		for (int j = -1; j <= g->ny + 1; j++)
			for (int i = -1; i <= g->nx + 1; i++)
				d[grid_dens_index(g, i, j, k)] = f(g->origin[0] + (float)i * g->cell,
								   g->origin[1] + (float)j * g->cell,
								   g->origin[2] + (float)k * g->cell);
	return d;
}

static void check_closed(const char *what, const struct mesh *m)
{
	struct topo t;
	mesh_topology(m, NULL, NULL, &t);
	CHECK(t.bad_index == 0, "%s: %llu bad indices", what, (unsigned long long)t.bad_index);
	CHECK(t.duplicated == 0, "%s: %llu duplicated directed edges", what, (unsigned long long)t.duplicated);
	CHECK(t.unmatched == 0, "%s: %llu unmatched edges of %llu", what, (unsigned long long)t.unmatched,
	      (unsigned long long)t.edges);
}

static void check_random_fields(void)
{
	/* random corner signs exercise all 256 cases and every ambiguous face;
	 * the outermost corners are air so the surface is closed; every grid
	 * more than DEBRIS_SPAN (abi.h) samples inside along x, so its
	 * components are not all debris (half the samples inside: one of them
	 * spans the grid) */
	int sizes[] = { 8, 11, 13 };
	int seen[256] = { 0 };
	struct mc_tables tables;
	mc_tables_build(&tables);
	for (int s = 0; s < 3; s++) {
		for (int rep = 0; rep < 6; rep++) {
			struct grid g = { sizes[s], sizes[s] + 1, sizes[s] + 2, { 0, 0, 0 }, 1.0f, 0, { 0, 0, 0 } };
			float *d = malloc(sizeof(float) * (size_t)grid_dens_count(&g));
			for (int k = -1; k <= g.nz + 1; k++)
				for (int j = -1; j <= g.ny + 1; j++)
					for (int i = -1; i <= g.nx + 1; i++) {
						int border = i <= 0 || j <= 0 || k <= 0 || i >= g.nx || j >= g.ny || k >= g.nz;
						float v = frand() * 2.0f - 1.0f;
						if (fabsf(v) < 1e-3f)
							v = 0.5f;
						d[grid_dens_index(&g, i, j, k)] = border ? -1.0f : v;
					}
			for (int k = 0; k < g.nz; k++)
				for (int j = 0; j < g.ny; j++)
					for (int i = 0; i < g.nx; i++) {
						int cs = 0;
						const struct mc_tables *t = &tables;
						for (int n = 0; n < 8; n++)
							cs |= (d[grid_dens_index(&g, i + t->corner[n][0], j + t->corner[n][1],
										 k + t->corner[n][2])] > 0) << n;
						seen[cs] = 1;
					}
			struct mesh m;
			CHECK(mc_ref_extract(&g, d, 0.0f, &m) == 0, "extract random field");
			check_closed("random field", &m);
			CHECK(m.ntris > 0, "random field has triangles");
			mesh_free(&m);
			free(d);
		}
	}
	int nseen = 0;
	for (int i = 0; i < 256; i++)
		nseen += seen[i];
	CHECK(nseen >= 250, "random fields covered %d of 256 cases", nseen);
}

static void check_analytic(void)
{
	int sizes[] = { 16, 33, 50 };
	for (int s = 0; s < 3; s++) {
		int n = sizes[s];
		struct grid g = { n, n, n, { -1.2f, -1.2f, -1.2f }, 2.4f / (float)n, 0, { 0, 0, 0 } };
		float *d = sample(&g, f_sphere);
		struct mesh m;
		CHECK(mc_ref_extract(&g, d, 0.0f, &m) == 0, "extract sphere");
		check_closed("sphere", &m);
		/* vertices on the sphere, normals outward, faces wound outward */
		double max_r = 0, min_dot = 1, min_face = 1;
		for (uint32_t i = 0; i < m.nverts; i++) {
			const float *p = m.pos + 3 * i, *nn = m.nrm + 3 * i;
			double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
			if (fabs(r - 0.8) > max_r)
				max_r = fabs(r - 0.8);
			double dot = (p[0] * nn[0] + p[1] * nn[1] + p[2] * nn[2]) / r;
			if (dot < min_dot)
				min_dot = dot;
		}
		for (uint32_t i = 0; i < m.ntris; i++) {
			const float *a = m.pos + 3 * m.idx[3 * i], *b = m.pos + 3 * m.idx[3 * i + 1],
				    *c = m.pos + 3 * m.idx[3 * i + 2];
			double u[3], v[3], cx[3], ce[3];
			for (int k = 0; k < 3; k++) {
				u[k] = b[k] - a[k];
				v[k] = c[k] - a[k];
				ce[k] = (a[k] + b[k] + c[k]) / 3;
			}
			cx[0] = u[1] * v[2] - u[2] * v[1];
			cx[1] = u[2] * v[0] - u[0] * v[2];
			cx[2] = u[0] * v[1] - u[1] * v[0];
			double l = sqrt(cx[0] * cx[0] + cx[1] * cx[1] + cx[2] * cx[2]);
			double cl = sqrt(ce[0] * ce[0] + ce[1] * ce[1] + ce[2] * ce[2]);
			if (l > 1e-12) {
				double dot = (cx[0] * ce[0] + cx[1] * ce[1] + cx[2] * ce[2]) / (l * cl);
				if (dot < min_face)
					min_face = dot;
			}
		}
		CHECK(max_r < 0.25 * g.cell, "sphere n=%d: vertex radius error %g (cell %g)", n, max_r, (double)g.cell);
		CHECK(min_dot > 0.95, "sphere n=%d: normals outward (min cos %g)", n, min_dot);
		CHECK(min_face > 0.0, "sphere n=%d: triangles wound counter-clockwise from air (min cos %g)", n, min_face);
		/* Euler characteristic of a sphere: V - E + F = 2 */
		long long E = (long long)m.ntris * 3 / 2;
		CHECK((long long)m.nverts - E + (long long)m.ntris == 2, "sphere n=%d: Euler characteristic %lld", n,
		      (long long)m.nverts - E + (long long)m.ntris);
		mesh_free(&m);
		free(d);

		d = sample(&g, f_torus);
		CHECK(mc_ref_extract(&g, d, 0.0f, &m) == 0, "extract torus");
		check_closed("torus", &m);
		E = (long long)m.ntris * 3 / 2;
		CHECK((long long)m.nverts - E + (long long)m.ntris == 0, "torus n=%d: Euler characteristic %lld (genus 1)", n,
		      (long long)m.nverts - E + (long long)m.ntris);
		mesh_free(&m);
		free(d);
	}
}

int main(void)
{
	check_tables();
	check_random_fields();
	check_analytic();
	return tc_done("mc_tables");
}
