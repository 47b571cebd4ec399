/* isoterra — test_pipeline (test_pipeline.c): the GPU mesh against the CPU
 * reference within the stated bound (pipeline_test.h), Marching Cubes'
 * bookkeeping redone on both meshes' densities. */
#include "pipeline_test.h"
#include "terrain.h"

#include <float.h>
#include <math.h>
#include <string.h>
#include <unistd.h>

/* Marching Cubes' bookkeeping of one density volume, as mc_ref.c does it:
 * every corner's inside bit, the owners' vertex masks (first vertex of
 * each), every cell's case (first triangle of each), and each vertex's
 * edge (owner * 3 + axis). */
struct mc_labels {
	int ox, oy, oz;
	uint8_t *in;      /* per corner, (nx+1)(ny+1)(nz+1) */
	uint8_t *mask;    /* per owner corner: bit s = a vertex on its edge along s */
	uint32_t *vbase;  /* per owner: its first vertex */
	uint8_t *cs;      /* per cell: the case */
	uint32_t *tbase;  /* per cell: its first triangle; [cells] = the count */
	uint32_t *vedge;  /* per vertex: owner * 3 + axis */
	uint32_t nv, nt;
};

static void labels_free(struct mc_labels *L)
{
	free(L->in);
	free(L->mask);
	free(L->vbase);
	free(L->cs);
	free(L->tbase);
	free(L->vedge);
	memset(L, 0, sizeof(*L));
}

static int labels_make(struct mc_labels *L, const struct mc_tables *t, const struct grid *g, const float *d,
		       float iso)
{
	memset(L, 0, sizeof(*L));
	L->ox = g->nx + 1;
	L->oy = g->ny + 1;
	L->oz = g->nz + 1;
	size_t owners = (size_t)L->ox * L->oy * L->oz, cells = (size_t)g->nx * g->ny * g->nz;
	L->in = malloc(owners);
	L->mask = malloc(owners);
	L->vbase = malloc(sizeof(uint32_t) * owners);
	L->cs = malloc(cells ? cells : 1);
	L->tbase = malloc(sizeof(uint32_t) * (cells + 1));
	if (!L->in || !L->mask || !L->vbase || !L->cs || !L->tbase) {
		labels_free(L);
		return -1;
	}
	for (int z = 0; z < L->oz; z++)
		for (int y = 0; y < L->oy; y++)
			for (int x = 0; x < L->ox; x++)
				L->in[x + (size_t)L->ox * (y + (size_t)L->oy * z)] = (uint8_t)mc_ref_inside(g, d, iso, x, y, z);
	uint64_t nv = 0;
	for (int z = 0; z < L->oz; z++)
		for (int y = 0; y < L->oy; y++)
			for (int x = 0; x < L->ox; x++) {
				size_t c = x + (size_t)L->ox * (y + (size_t)L->oy * z);
				int m = 0;
				if (x < g->nx && L->in[c] != L->in[c + 1])
					m |= 1;
				if (y < g->ny && L->in[c] != L->in[c + L->ox])
					m |= 2;
				if (z < g->nz && L->in[c] != L->in[c + (size_t)L->ox * L->oy])
					m |= 4;
				L->mask[c] = (uint8_t)m;
				L->vbase[c] = (uint32_t)nv;
				nv += (uint64_t)((m & 1) + ((m >> 1) & 1) + ((m >> 2) & 1));
			}
	uint64_t nt = 0;
	for (int z = 0, c = 0; z < g->nz; z++)
		for (int y = 0; y < g->ny; y++)
			for (int x = 0; x < g->nx; x++, c++) {
				int cs = 0;
				for (int n = 0; n < 8; n++)
					cs |= L->in[(x + t->corner[n][0]) +
						    (size_t)L->ox * ((y + t->corner[n][1]) + (size_t)L->oy * (z + t->corner[n][2]))]
					      << n;
				L->cs[c] = (uint8_t)cs;
				L->tbase[c] = (uint32_t)nt;
				nt += t->tri_count[cs];
			}
	L->tbase[cells] = (uint32_t)nt;
	L->nv = (uint32_t)nv;
	L->nt = (uint32_t)nt;
	L->vedge = malloc(sizeof(uint32_t) * (nv ? nv : 1));
	if (!L->vedge) {
		labels_free(L);
		return -1;
	}
	for (size_t c = 0, v = 0; c < owners; c++)
		for (int s = 0; s < 3; s++)
			if (L->mask[c] & (1 << s))
				L->vedge[v++] = (uint32_t)(c * 3 + (size_t)s);
	return 0;
}

/* Whether every stated bound holds. */
bool cmp_ok(const struct mesh_cmp *r)
{
	return r->layout && r->certain_differ == 0 && r->certain_vert_missing == 0 && r->vert_far == 0 &&
	       r->vert_off_edge == 0 && r->bad_index == 0 && r->zero_area == 0 &&
	       r->count_differ <= (uint64_t)MC_MAX_TRIS * r->ambiguous_differ;
}

void cmp_print(const char *what, const struct mesh_cmp *r)
{
	printf("%-28s bound %.2g: %llu samples near iso; %llu of %llu surface cells ambiguous, %llu differ (%llu "
	       "triangles, %llu zero-area); worst vertex %.2g cell, %.2f of its tolerance%s\n",
	       what, r->bound, (unsigned long long)r->near_samples, (unsigned long long)r->ambiguous_cells,
	       (unsigned long long)r->surface_cells, (unsigned long long)r->ambiguous_differ,
	       (unsigned long long)r->tris_differ, (unsigned long long)r->zero_area_ambiguous, r->worst_diff,
	       r->worst_ratio, cmp_ok(r) ? "" : "  ** FAILS **");
	if (!cmp_ok(r))
		printf("  layout %d, certain cells differing %llu, certain vertices missing %llu, far %llu, off their "
		       "edge %llu, bad indices %llu, zero-area %llu (%llu in ambiguous cells), alone %llu\n",
		       r->layout, (unsigned long long)r->certain_differ, (unsigned long long)r->certain_vert_missing,
		       (unsigned long long)r->vert_far, (unsigned long long)r->vert_off_edge,
		       (unsigned long long)r->bad_index, (unsigned long long)r->zero_area,
		       (unsigned long long)r->zero_area_ambiguous, (unsigned long long)r->uncertain_vert_alone);
}

/* Whether sample q (corner indices) is one of the stored densities, the
 * margin included. */
static bool stored(const struct grid *g, const int q[3])
{
	int m = grid_margin(g);
	return q[0] >= -m && q[1] >= -m && q[2] >= -m && q[0] <= g->nx + m && q[1] <= g->ny + m && q[2] <= g->nz + m;
}

/* The GPU mesh gm (made from the GPU's densities dg) against the reference
 * cm (made from dc), within bound: fills r.  -1 when out of memory. */
int mesh_vs_reference(const struct grid *g, float iso, const float *dg, const struct mesh *gm, const float *dc,
		      const struct mesh *cm, double bound, struct mesh_cmp *r)
{
	memset(r, 0, sizeof(*r));
	r->bound = bound;
	struct mc_tables t;
	mc_tables_build(&t);
	struct mc_labels lg, lc;
	if (labels_make(&lg, &t, g, dg, iso) < 0)
		return -1;
	if (labels_make(&lc, &t, g, dc, iso) < 0) {
		labels_free(&lg);
		return -1;
	}
	size_t owners = (size_t)lg.ox * lg.oy * lg.oz, nd = (size_t)grid_dens_count(g);
	uint8_t *near = calloc(nd, 1), *unsure = calloc(owners, 1);
	int rc = -1;
	if (!near || !unsure)
		goto out;
	/* samples near the iso level; corners whose inside bit is not certain */
	for (size_t i = 0; i < nd; i++)
		if (!(fabs((double)dc[i] - iso) > bound)) { /* NaN counts as near */
			near[i] = 1;
			r->near_samples++;
		}
	static const int nb[7][3] = { { 0, 0, 0 },  { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 },
				      { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 } };
	int m = grid_margin(g);
	/* ... and samples on the iso level to the mesh's precision: a vertex on
	 * an edge from such a sample, t = (iso - d0) / (d1 - d0) of a cell from
	 * it, rounds onto its corner when t is under the float rounding of the
	 * coordinates (in cells), and where two of its edges' vertices do, they
	 * meet there and a triangle between them has no area (diorama seed 203
	 * at grid 64: a sample of -2.4e-7 among densities of 1-3 put three
	 * vertices on one point).  One such edge is no meeting (a closed box's
	 * wall: every vertex towards it on its inner corner).  Four times that
	 * rounding, from the GPU's densities (its mesh's) */
	int n3[3] = { g->nx, g->ny, g->nz };
	double cells = 0.0;
	for (int a = 0; a < 3; a++) {
		double lo = fabs((double)g->origin[a] / g->cell + g->base[a] - m),
		       hi = fabs((double)g->origin[a] / g->cell + g->base[a] + n3[a] + m);
		cells = fmax(cells, fmax(fmax(lo, hi), (double)(n3[a] + m)));
	}
	double tround = 4.0 * FLT_EPSILON * cells;
	for (int z = -m; z <= g->nz + m; z++)
		for (int y = -m; y <= g->ny + m; y++)
			for (int x = -m; x <= g->nx + m; x++) {
				long i = grid_dens_index(g, x, y, z);
				double d = (double)dg[i];
				int onto = 0;
				for (int k = 1; k < 7 && !near[i]; k++) {
					int q[3] = { x + nb[k][0], y + nb[k][1], z + nb[k][2] };
					if (!stored(g, q))
						continue;
					double e = (double)dg[grid_dens_index(g, q[0], q[1], q[2])];
					onto += (d > iso) != (e > iso) && fabs(d - iso) <= tround * fabs(e - d);
				}
				if (onto >= 2) {
					near[i] = 1;
					r->near_samples++;
				}
			}
	for (int z = 0; z < lg.oz; z++)
		for (int y = 0; y < lg.oy; y++)
			for (int x = 0; x < lg.ox; x++)
				for (int k = 0; k < 7; k++) {
					int q[3] = { x + nb[k][0], y + nb[k][1], z + nb[k][2] };
					if (!stored(g, q))
						continue;
					if (near[grid_dens_index(g, q[0], q[1], q[2])])
						unsure[x + (size_t)lg.ox * (y + (size_t)lg.oy * z)] = 1;
				}
	/* the GPU mesh has the layout of its own densities (its triangles are
	 * then read cell by cell through lg) */
	r->layout = gm->ntris == lg.nt && gm->nverts == lg.nv && cm->ntris == lc.nt && cm->nverts == lc.nv;
	r->count_differ = gm->ntris > cm->ntris ? gm->ntris - cm->ntris : cm->ntris - gm->ntris;
	for (uint32_t i = 0; i < gm->ntris * 3; i++)
		r->bad_index += gm->idx[i] >= gm->nverts;
	if (!r->layout || r->bad_index)
		goto done;
	/* cells */
	for (int z = 0, c = 0; z < g->nz; z++)
		for (int y = 0; y < g->ny; y++)
			for (int x = 0; x < g->nx; x++, c++) {
				bool amb = false;
				for (int n = 0; n < 8; n++)
					amb |= unsure[(x + t.corner[n][0]) +
						      (size_t)lg.ox * ((y + t.corner[n][1]) + (size_t)lg.oy * (z + t.corner[n][2]))];
				uint32_t g0 = lg.tbase[c], gn = lg.tbase[c + 1] - g0, c0 = lc.tbase[c], cn = lc.tbase[c + 1] - c0;
				if (gn || cn)
					r->surface_cells++;
				bool same = gn == cn;
				for (uint32_t k = 0; same && k < 3 * gn; k++)
					same = lg.vedge[gm->idx[3 * g0 + k]] == lc.vedge[cm->idx[3 * c0 + k]];
				for (uint32_t k = 0; k < gn; k++) {
					const uint32_t *v = gm->idx + 3 * (size_t)(g0 + k);
					double e1[3], e2[3];
					for (int a = 0; a < 3; a++) {
						e1[a] = (double)gm->pos[3 * v[1] + a] - gm->pos[3 * v[0] + a];
						e2[a] = (double)gm->pos[3 * v[2] + a] - gm->pos[3 * v[0] + a];
					}
					double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
					       cz = e1[0] * e2[1] - e1[1] * e2[0];
					if (!(cx * cx + cy * cy + cz * cz > 0.0)) {
						if (amb)
							r->zero_area_ambiguous++;
						else
							r->zero_area++;
					}
				}
				if (amb) {
					r->ambiguous_cells += gn || cn;
					if (!same) {
						r->ambiguous_differ++;
						r->tris_differ += gn > cn ? gn : cn;
					}
				} else if (!same) {
					r->certain_differ++;
				}
			}
	/* vertices: the reference's by edge, then every GPU vertex against it */
	uint32_t *ref = malloc(sizeof(uint32_t) * owners * 3);
	if (!ref)
		goto out;
	for (size_t e = 0; e < owners * 3; e++)
		ref[e] = UINT32_MAX;
	for (uint32_t v = 0; v < lc.nv; v++)
		ref[lc.vedge[v]] = v;
	uint8_t *seen = calloc(owners * 3, 1);
	if (!seen) {
		free(ref);
		goto out;
	}
	for (uint32_t v = 0; v < lg.nv; v++) {
		uint32_t e = lg.vedge[v], o = e / 3;
		int s = (int)(e % 3), x = (int)(o % (uint32_t)lg.ox), y = (int)(o / (uint32_t)lg.ox % (uint32_t)lg.oy),
		    z = (int)(o / ((uint32_t)lg.ox * (uint32_t)lg.oy));
		size_t o1 = o + (s == 0 ? 1 : s == 1 ? (size_t)lg.ox : (size_t)lg.ox * lg.oy);
		bool certain = !unsure[o] && !unsure[o1];
		seen[e] = 1;
		if (ref[e] == UINT32_MAX) {
			if (certain)
				r->certain_vert_missing++;
			else
				r->uncertain_vert_alone++;
			continue;
		}
		double d0 = dc[grid_dens_index(g, x, y, z)],
		       d1 = dc[grid_dens_index(g, x + (s == 0), y + (s == 1), z + (s == 2))];
		double diff = 0;
		for (int a = 0; a < 3; a++)
			diff = fmax(diff, fabs((double)gm->pos[3 * v + a] - cm->pos[3 * ref[e] + a]) / g->cell);
		if (certain) {
			double tol = 1e-4 + bound / fabs(d0 - d1);
			r->worst_ratio = fmax(r->worst_ratio, diff / tol);
			r->worst_diff = fmax(r->worst_diff, diff);
			r->vert_far += !(diff <= tol);
		} else {
			r->vert_off_edge += !(diff <= 1.0 + 1e-4);
		}
	}
	for (uint32_t v = 0; v < lc.nv; v++)
		if (!seen[lc.vedge[v]]) {
			uint32_t o = lc.vedge[v] / 3;
			int s = (int)(lc.vedge[v] % 3);
			size_t o1 = o + (s == 0 ? 1 : s == 1 ? (size_t)lg.ox : (size_t)lg.ox * lg.oy);
			if (!unsure[o] && !unsure[o1])
				r->certain_vert_missing++;
			else
				r->uncertain_vert_alone++;
		}
	free(seen);
	free(ref);
done:
	rc = 0;
out:
	free(near);
	free(unsure);
	labels_free(&lg);
	labels_free(&lc);
	return rc;
}
