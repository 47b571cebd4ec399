/* isoterra — the GPU pipeline against the CPU reference: density values;
 * the mesh identical to the CPU's Marching Cubes on the GPU's densities,
 * and to the full CPU reference (libm's sin, cos: not the GPU's) exactly
 * away from the iso level and within a bound derived from the measured
 * density error near it, on any correct driver (mesh_vs_reference, with a
 * self-check that a simulated driver difference passes and real errors
 * fail); watertightness and no degenerate triangles; non-power-of-two
 * and non-cubic grids, the worst-case field (3D checkerboard) clamped
 * without writing out of bounds, and the atomic / no-compaction methods
 * agreeing with the HistoPyramid; the program cache: a term that is off
 * leaves no code (no uniform of it in the program), switching it on
 * compiles one variant, moving its knob within "on" none, and every
 * variant's densities match the CPU's. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "mesh_check.h"
#include "terrain.h"

#include <math.h>
#include <string.h>
#include <unistd.h>

static struct noise_set ns;

struct border_ctx {
	const struct grid *g;
};

static int on_plane(const struct grid *g, const float *p, int axis, int side)
{
	int n = axis == 0 ? g->nx : axis == 1 ? g->ny : g->nz;
	float plane = g->origin[axis] + (side ? (float)n * g->cell : 0.0f);
	return fabsf(p[axis] - plane) < 1e-4f * g->cell + 1e-6f;
}

static int border_edge(const struct mesh *m, uint32_t a, uint32_t b, void *ctx)
{
	const struct grid *g = ((struct border_ctx *)ctx)->g;
	for (int axis = 0; axis < 3; axis++)
		for (int side = 0; side < 2; side++)
			if (on_plane(g, m->pos + 3 * a, axis, side) && on_plane(g, m->pos + 3 * b, axis, side))
				return 1;
	return 0;
}

static double max_pos_diff(const struct mesh *a, const struct mesh *b)
{
	double d = 0;
	for (uint32_t i = 0; i < a->nverts * 3; i++)
		d = fmax(d, fabs((double)a->pos[i] - b->pos[i]));
	return d;
}

static double max_nrm_diff(const struct mesh *a, const struct mesh *b)
{
	double d = 0;
	for (uint32_t i = 0; i < a->nverts * 3; i++)
		d = fmax(d, fabs((double)a->nrm[i] - b->nrm[i]));
	return d;
}

/* ---- the GPU mesh against the CPU reference, on any driver ----------------
 *
 * The GPU's sin, cos, exp... are not libm's: its densities differ from the
 * CPU reference's in the last bits (measured below: max |gpu - cpu|, the
 * "density err").  A sample that close to the iso level may land on the
 * other side of it, and the cells around it then have another Marching
 * Cubes case: on NVIDIA bumps at grid 100 gave 94356 triangles against the
 * reference's 94352.  So the mesh is compared with a stated bound instead of
 * by counts:
 *  - bound = BOUND_K (2) x the measured max |gpu - cpu| density error: a
 *    sample whose reference density is farther than that from the iso
 *    level is on the same side of it on both (|gpu - cpu| <= max error <
 *    bound; 1 x would do, 2 x is the margin); the max error itself is held
 *    to 1e-5 x the field's scale + 1e-6 by the density check;
 *  - a corner's inside bit depends on its sign and its six neighbours' (the
 *    debris filter, mc_ref.c): it is certain when none of the seven is
 *    within the bound;
 *  - a cell with its eight corners certain ("certain cell") has exactly the
 *    reference's triangles: the same edges, in the same order; a vertex on
 *    an edge with both ends certain is on both meshes, within
 *    cell x (1e-4 + bound / |d0 - d1|) of the reference's (t = d0 / (d0 -
 *    d1) moves by at most err / |d0 - d1|; 1e-4 for float rounding);
 *  - a cell with a corner not certain ("ambiguous") may differ, by at most
 *    MC_MAX_TRIS (5) triangles (Marching Cubes' most): the triangle counts
 *    differ by at most 5 x the ambiguous cells that differ.  How many
 *    cells are ambiguous is the field's affair (bumps has planes of
 *    samples on the iso level: sin(k pi)), not bounded: the bound is;
 *  - the GPU mesh itself: no index past its vertices, no repeated index, no
 *    triangle of zero area in a certain cell (two vertices can meet only at
 *    a corner on the iso level: an ambiguous one), and watertight
 *    (mesh_topology, below). */
#define BOUND_K 2.0

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

struct mesh_cmp {
	double bound;                /* per sample: |reference - iso| <= bound may flip */
	uint64_t near_samples;       /* samples within the bound */
	uint64_t surface_cells;      /* cells the surface crosses (either mesh) */
	uint64_t ambiguous_cells;    /* of those, cells with a corner not certain */
	uint64_t ambiguous_differ;   /* of those, cells whose triangles differ */
	uint64_t tris_differ;        /* triangles of those cells (the larger side) */
	uint64_t count_differ;       /* |GPU - reference| triangle counts */
	uint64_t certain_differ;     /* certain cells that differ: must be 0 */
	uint64_t certain_vert_missing; /* a certain edge's vertex in one mesh only: must be 0 */
	uint64_t uncertain_vert_alone; /* an ambiguous edge's vertex in one mesh only */
	uint64_t vert_far;           /* certain vertices beyond their tolerance: must be 0 */
	uint64_t vert_off_edge;      /* ambiguous vertices off their edge: must be 0 */
	uint64_t bad_index;          /* GPU indices past its vertices: must be 0 */
	uint64_t zero_area;          /* GPU triangles of zero area in certain cells: must be 0 */
	uint64_t zero_area_ambiguous;
	double worst_ratio;          /* the largest vertex difference / its tolerance */
	double worst_diff;           /* the largest vertex difference, in cells */
	bool layout;                 /* the GPU mesh has its densities' triangle and vertex counts */
};

/* Whether every stated bound holds. */
static bool cmp_ok(const struct mesh_cmp *r)
{
	return r->layout && r->certain_differ == 0 && r->certain_vert_missing == 0 && r->vert_far == 0 &&
	       r->vert_off_edge == 0 && r->bad_index == 0 && r->zero_area == 0 &&
	       r->count_differ <= (uint64_t)MC_MAX_TRIS * r->ambiguous_differ;
}

static void cmp_print(const char *what, const struct mesh_cmp *r)
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

/* The GPU mesh gm (made from the GPU's densities dg) against the reference
 * cm (made from dc), within bound: fills r.  -1 when out of memory. */
static int mesh_vs_reference(const struct grid *g, float iso, const float *dg, const struct mesh *gm, const float *dc,
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
	for (int z = 0; z < lg.oz; z++)
		for (int y = 0; y < lg.oy; y++)
			for (int x = 0; x < lg.ox; x++)
				for (int k = 0; k < 7; k++) {
					int q[3] = { x + nb[k][0], y + nb[k][1], z + nb[k][2] };
					if (q[0] < -m || q[1] < -m || q[2] < -m || q[0] > g->nx + m || q[1] > g->ny + m ||
					    q[2] > g->nz + m)
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

static int mesh_copy(struct mesh *dst, const struct mesh *src)
{
	if (mesh_alloc(dst, src->nverts, src->ntris) < 0)
		return -1;
	memcpy(dst->pos, src->pos, 12 * (size_t)src->nverts);
	memcpy(dst->nrm, src->nrm, 12 * (size_t)src->nverts);
	memcpy(dst->idx, src->idx, 12 * (size_t)src->ntris);
	return 0;
}

static bool mesh_same(const struct mesh *a, const struct mesh *b)
{
	return a->ntris == b->ntris && a->nverts == b->nverts && !memcmp(a->idx, b->idx, 12 * (size_t)a->ntris) &&
	       !memcmp(a->pos, b->pos, 12 * (size_t)a->nverts);
}

/* The comparison itself, on one field's meshes: another driver's densities
 * (these, a few samples nearest the iso level moved across it) pass, with
 * a mesh that differs; real errors fail: a reference sample far from the
 * iso level on its wrong side, a GPU index changed, repeated or dropped, a
 * vertex moved by 1% of a cell. */
static void check_comparison(const char *what, const struct grid *g, float iso, const float *dg, const float *dc,
			     const struct mesh *gm, const struct mesh *cm, double bound, struct border_ctx *bc, int closed)
{
	size_t nd = (size_t)grid_dens_count(g);
	float *d2 = malloc(4 * nd);
	struct mesh other = { 0 }, bad = { 0 };
	struct mesh_cmp r;
	CHECK(d2 != NULL, "%s: self-check: out of memory", what);
	if (!d2)
		return;
	/* another driver: the 6 corners nearest the iso level across it */
	enum { NEAREST = 6 };
	long pick[NEAREST];
	double how_near[NEAREST];
	for (int k = 0; k < NEAREST; k++) {
		pick[k] = -1;
		how_near[k] = INFINITY;
	}
	for (int z = 0; z <= g->nz; z++)
		for (int y = 0; y <= g->ny; y++)
			for (int x = 0; x <= g->nx; x++) {
				long i = grid_dens_index(g, x, y, z);
				double a = fabs((double)dc[i] - iso);
				if (!(a > 0.0) || a >= how_near[NEAREST - 1])
					continue;
				int k = NEAREST - 1;
				for (; k > 0 && how_near[k - 1] > a; k--) {
					how_near[k] = how_near[k - 1];
					pick[k] = pick[k - 1];
				}
				how_near[k] = a;
				pick[k] = i;
			}
	memcpy(d2, dc, 4 * nd);
	for (int k = 0; k < NEAREST; k++)
		if (pick[k] >= 0)
			d2[pick[k]] = 2.0f * iso - dc[pick[k]];
	double err2 = 0;
	for (size_t i = 0; i < nd; i++)
		err2 = fmax(err2, fabs((double)dg[i] - d2[i]));
	CHECK(mc_ref_extract(g, d2, iso, &other) == 0, "%s: self-check: extract", what);
	CHECK(mesh_vs_reference(g, iso, dg, gm, d2, &other, BOUND_K * err2, &r) == 0, "%s: self-check", what);
	cmp_print("  self-check: another driver", &r);
	CHECK(cmp_ok(&r) && r.ambiguous_differ > 0 && !mesh_same(cm, &other),
	      "%s: self-check: %d samples nearest iso (up to %.2g from it) across it: the reference changes (%u/%u "
	      "triangles/vertices, was %u/%u), in %llu ambiguous cells, and the GPU mesh passes against it",
	      what, NEAREST, how_near[NEAREST - 1], other.ntris, other.nverts, cm->ntris, cm->nverts,
	      (unsigned long long)r.ambiguous_differ);
	mesh_free(&other);

	/* a reference sample far from the iso level (1000 x the bound and more),
	 * next to the surface, on its wrong side: the honest bound catches it */
	long far = -1;
	for (int z = 0; z <= g->nz && far < 0; z++)
		for (int y = 0; y <= g->ny && far < 0; y++)
			for (int x = 0; x < g->nx && far < 0; x++) {
				long i = grid_dens_index(g, x, y, z), j = grid_dens_index(g, x + 1, y, z);
				if ((dc[i] > iso) != (dc[j] > iso) && fabs((double)dc[i] - iso) > 1000.0 * bound + 1e-6 &&
				    fabs((double)dc[j] - iso) > 1000.0 * bound + 1e-6)
					far = i;
			}
	CHECK(far >= 0, "%s: self-check: a sample far from the iso level next to the surface", what);
	if (far >= 0) {
		memcpy(d2, dc, 4 * nd);
		d2[far] = 2.0f * iso - dc[far];
		CHECK(mc_ref_extract(g, d2, iso, &other) == 0, "%s: self-check: extract", what);
		CHECK(mesh_vs_reference(g, iso, dg, gm, d2, &other, bound, &r) == 0, "%s: self-check", what);
		CHECK(!cmp_ok(&r) && r.certain_differ > 0,
		      "%s: self-check: a reference sample %.2g from the iso level on its wrong side is caught", what,
		      fabs((double)dc[far] - iso));
		mesh_free(&other);
	}
	free(d2);

	/* the GPU mesh wrong: each corruption must fail the comparison, and the
	 * index ones the topology too */
	struct topo t;
	uint32_t k = gm->ntris / 2, v = gm->idx[3 * k];
	static const char *const names[] = { "an index changed", "an index repeated", "a triangle dropped",
					     "a vertex moved by 1% of a cell" };
	for (int c = 0; c < 4; c++) {
		if (mesh_copy(&bad, gm) < 0) {
			CHECK(0, "%s: self-check: out of memory", what);
			return;
		}
		if (c == 0) {
			uint32_t w = (v + 1) % bad.nverts;
			for (int n = 0; n < 3 && (w == bad.idx[3 * k + 1] || w == bad.idx[3 * k + 2]); n++)
				w = (w + 1) % bad.nverts;
			bad.idx[3 * k] = w;
		} else if (c == 1)
			bad.idx[3 * k + 2] = bad.idx[3 * k];
		else if (c == 2)
			bad.ntris--;
		else
			bad.pos[3 * v] += 0.01f * g->cell;
		CHECK(mesh_vs_reference(g, iso, dg, &bad, dc, cm, bound, &r) == 0, "%s: self-check", what);
		bool caught = !cmp_ok(&r);
		if (c < 2) {
			mesh_topology(&bad, closed ? NULL : border_edge, bc, &t);
			caught = caught && (t.unmatched || t.duplicated || t.degenerate);
		}
		CHECK(caught, "%s: self-check: %s is caught", what, names[c]);
		mesh_free(&bad);
	}
}

/* One field on one grid, every check. closed: surface never touches the border.
 * self_check: the comparison with the reference is itself checked too. */
static void check_field(const char *what, const struct params *p, const struct grid *g, int closed, bool self_check)
{
	char err[512] = "";
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(g, p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "%s: pipeline_create: %s", what, err);
	if (!pl) {
		terrain_destroy(tr);
		edits_destroy(ed);
		return;
	}
	CHECK(fixture_run(pl, p) == 0, "%s: pipeline_run", what);
	long nd = grid_dens_count(g);
	float *dg = malloc(sizeof(float) * (size_t)nd), *dc = malloc(sizeof(float) * (size_t)nd);
	CHECK(pipeline_read_density(pl, dg) == 0, "%s: read density", what);
	noise_set_init(&ns, p->seed);
	density_ref_volume(p, &ns, ed, g->origin, g->cell, g->nx, g->ny, g->nz, dc);
	double dmax = 0, scale = 0;
	for (long i = 0; i < nd; i++) {
		double e = fabs((double)dg[i] - dc[i]);
		if (!isnan(dmax) && !(e <= dmax))
			dmax = e; /* a NaN counts, and stays */
		scale = fmax(scale, fabs((double)dc[i]));
	}
	CHECK(dmax <= 1e-5 * fmax(scale, 1.0) + 1e-6, "%s: GPU vs CPU density max error %g (scale %g)", what, dmax, scale);

	struct extract_stats st;
	CHECK(pipeline_read_stats(pl, &st) == 0, "%s: stats", what);
	CHECK(!st.overflow, "%s: unexpected overflow", what);
	struct mesh gm, cm_g, cm_c;
	CHECK(pipeline_read_mesh(pl, &gm) == 0, "%s: read mesh", what);
	CHECK(mc_ref_extract(g, dg, p->iso, &cm_g) == 0, "%s: CPU MC on GPU densities", what);
	CHECK(mc_ref_extract(g, dc, p->iso, &cm_c) == 0, "%s: CPU reference", what);
	printf("%-28s grid %3dx%3dx%3d: GPU %7u tris %7u verts, CPU %7u tris %7u verts, density err %.2g\n", what,
	       g->nx, g->ny, g->nz, gm.ntris, gm.nverts, cm_c.ntris, cm_c.nverts, dmax);
	CHECK(gm.ntris > 0, "%s: no triangles", what);
	/* the same Marching Cubes on the same densities: identical mesh */
	CHECK(gm.ntris == cm_g.ntris && gm.nverts == cm_g.nverts, "%s: GPU %u/%u vs CPU-on-GPU-densities %u/%u", what,
	      gm.ntris, gm.nverts, cm_g.ntris, cm_g.nverts);
	if (gm.ntris == cm_g.ntris && gm.nverts == cm_g.nverts) {
		CHECK(memcmp(gm.idx, cm_g.idx, (size_t)gm.ntris * 12) == 0, "%s: indices differ", what);
		CHECK(max_pos_diff(&gm, &cm_g) <= 1e-4 * g->cell, "%s: positions differ by %g", what, max_pos_diff(&gm, &cm_g));
		CHECK(max_nrm_diff(&gm, &cm_g) <= 1e-3, "%s: normals differ by %g", what, max_nrm_diff(&gm, &cm_g));
	}
	/* the full CPU reference (its own densities, libm's sin and cos):
	 * exactly the same away from the iso level, within the stated bound
	 * near it (see mesh_vs_reference) */
	double bound = BOUND_K * dmax;
	struct mesh_cmp mr;
	CHECK(mesh_vs_reference(g, p->iso, dg, &gm, dc, &cm_c, bound, &mr) == 0, "%s: comparison: out of memory", what);
	cmp_print(what, &mr);
	CHECK(mr.layout && mr.bad_index == 0, "%s: GPU %u/%u triangles/vertices, its densities' Marching Cubes %u/%u", what,
	      gm.ntris, gm.nverts, cm_g.ntris, cm_g.nverts);
	CHECK(mr.certain_differ == 0 && mr.certain_vert_missing == 0,
	      "%s: away from the iso level (bound %.2g) %llu cells and %llu vertices differ from the CPU reference", what,
	      bound, (unsigned long long)mr.certain_differ, (unsigned long long)mr.certain_vert_missing);
	CHECK(mr.vert_far == 0 && mr.vert_off_edge == 0,
	      "%s: %llu vertices beyond cell x (1e-4 + bound / |d0 - d1|) of the reference's (worst %.2f of it), %llu "
	      "off their edge",
	      what, (unsigned long long)mr.vert_far, mr.worst_ratio, (unsigned long long)mr.vert_off_edge);
	CHECK(mr.count_differ <= (uint64_t)MC_MAX_TRIS * mr.ambiguous_differ,
	      "%s: GPU %u triangles vs the CPU reference's %u: more than %d per differing ambiguous cell (%llu)", what,
	      gm.ntris, cm_c.ntris, MC_MAX_TRIS, (unsigned long long)mr.ambiguous_differ);
	CHECK(mr.zero_area == 0, "%s: %llu triangles of zero area away from the iso level", what,
	      (unsigned long long)mr.zero_area);
	/* watertight: every interior edge shared by exactly two triangles,
	 * consistent winding; no triangle repeats an index */
	struct border_ctx bc = { g };
	struct topo t;
	mesh_topology(&gm, closed ? NULL : border_edge, &bc, &t);
	CHECK(t.bad_index == 0 && t.duplicated == 0 && t.unmatched == 0 && t.degenerate == 0,
	      "%s: not watertight: %llu bad indices, %llu duplicated, %llu unmatched of %llu edges, %llu degenerate", what,
	      (unsigned long long)t.bad_index, (unsigned long long)t.duplicated, (unsigned long long)t.unmatched,
	      (unsigned long long)t.edges, (unsigned long long)t.degenerate);
	if (self_check)
		check_comparison(what, g, p->iso, dg, dc, &gm, &cm_c, bound, &bc, closed);
	CHECK(pipeline_check_guards(pl) == 0, "%s: output buffer canaries overwritten", what);

	/* atomic append and no compaction give the same triangles */
	struct params q = *p;
	q.compaction = COMPACTION_ATOMIC;
	CHECK(fixture_run(pl, &q) == 0, "%s: atomic run", what);
	struct extract_stats sa;
	pipeline_read_stats(pl, &sa);
	CHECK(sa.triangles == gm.ntris, "%s: atomic append %u triangles vs HP %u", what, sa.triangles, gm.ntris);
	if (g->nx <= 64) {
		q.compaction = COMPACTION_NONE;
		CHECK(fixture_run(pl, &q) == 0, "%s: no-compaction run", what);
		struct mesh nm;
		CHECK(pipeline_read_mesh(pl, &nm) == 0, "%s: read no-compaction mesh", what);
		uint32_t real = 0;
		for (uint32_t i = 0; i < nm.ntris; i++) {
			const float *a = nm.pos + 9 * (size_t)i;
			if (memcmp(a, a + 3, 12) || memcmp(a, a + 6, 12))
				real++;
		}
		CHECK(nm.ntris == 5u * (uint32_t)(g->nx * g->ny * g->nz), "%s: no compaction draws 5 per cell", what);
		CHECK(real <= gm.ntris && real + gm.ntris / 200 + 2 >= gm.ntris, "%s: no compaction %u real triangles vs %u",
		      what, real, gm.ntris);
		mesh_free(&nm);
	}
	mesh_free(&gm);
	mesh_free(&cm_g);
	mesh_free(&cm_c);
	free(dg);
	free(dc);
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
}

static void preset(struct params *p, const char *name)
{
	char err[256];
	params_defaults(p);
	if (params_apply_preset(p, name, err, sizeof(err)) < 0) {
		fprintf(stderr, "%s\n", err);
		exit(1);
	}
	p->ao_rays = 0; /* AO is per-vertex shading, not geometry; keeps the test fast */
}

static void check_worst_case(void)
{
	struct params p;
	params_defaults(&p);
	char err[256];
	params_set(&p, "field", "checker", err, sizeof(err));
	p.closed = false; /* every cell of the grid is a checkerboard cell */
	p.vol_height = 1.0f;
	p.grid = 40;
	p.field_scale = 0.25f;
	p.vol_size = 40 * 0.25f;
	p.vol_x = p.vol_y = p.vol_z = 0.0f;
	struct grid g;
	grid_from_params(&g, &p);
	uint32_t caps[][2] = { { 0, 0 }, { 1000, 500 }, { 7, 100000 } };
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	for (int c = 0; c < 3; c++) {
		p.max_triangles = (int)caps[c][0];
		p.max_vertices = (int)caps[c][1];
		struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
		CHECK(pl != NULL, "checker: %s", err);
		if (!pl)
			break;
		CHECK(fixture_run(pl, &p) == 0, "checker run");
		struct extract_stats st;
		pipeline_read_stats(pl, &st);
		printf("checker cap %u/%u: needs %llu tris %llu verts, wrote %u/%u, overflow %d\n", st.triangle_capacity,
		       st.vertex_capacity, (unsigned long long)st.triangles_needed, (unsigned long long)st.vertices_needed,
		       st.triangles, st.vertices, st.overflow);
		CHECK(st.triangles_needed == 4ull * 40 * 40 * 40, "checker needs 4 triangles per cell (%llu)",
		      (unsigned long long)st.triangles_needed);
		CHECK(st.overflow, "checker overflow reported");
		CHECK(st.triangles == (st.triangles_needed < st.triangle_capacity ? st.triangles_needed : st.triangle_capacity),
		      "checker clamped triangles %u", st.triangles);
		CHECK(st.vertices <= st.vertex_capacity, "checker vertices %u <= capacity %u", st.vertices, st.vertex_capacity);
		CHECK(pipeline_check_guards(pl) == 0, "checker: wrote past a capacity");
		struct mesh m;
		CHECK(pipeline_read_mesh(pl, &m) == 0, "checker read");
		uint32_t bad = 0;
		for (uint32_t i = 0; i < m.ntris * 3; i++)
			bad += m.idx[i] >= m.nverts;
		CHECK(bad == 0, "checker: %u indices past the vertices written", bad);
		mesh_free(&m);
		/* the same through atomic append */
		struct params q = p;
		q.compaction = COMPACTION_ATOMIC;
		CHECK(fixture_run(pl, &q) == 0, "checker atomic run");
		pipeline_read_stats(pl, &st);
		CHECK(st.overflow && st.triangles <= st.triangle_capacity, "checker atomic clamped");
		CHECK(pipeline_check_guards(pl) == 0, "checker atomic: wrote past a capacity");
		pipeline_destroy(pl);
	}
	terrain_destroy(tr);
	edits_destroy(ed);
}

static void check_determinism(void)
{
	struct params p;
	params_defaults(&p);
	p.grid = 24;
	struct grid g;
	grid_from_params(&g, &p);
	char err[256];
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "determinism: %s", err);
	if (!pl) {
		terrain_destroy(tr);
		edits_destroy(ed);
		return;
	}
	struct mesh a, b, c;
	fixture_run(pl, &p);
	pipeline_read_mesh(pl, &a);
	fixture_run(pl, &p);
	pipeline_read_mesh(pl, &b);
	p.seed = 7;
	fixture_run(pl, &p);
	pipeline_read_mesh(pl, &c);
	CHECK(a.ntris == b.ntris && a.nverts == b.nverts && !memcmp(a.pos, b.pos, 12 * (size_t)a.nverts) &&
		      !memcmp(a.idx, b.idx, 12 * (size_t)a.ntris),
	      "same seed and parameters give the same mesh");
	CHECK(a.ntris != c.ntris || memcmp(a.pos, c.pos, 12 * (size_t)(a.nverts < c.nverts ? a.nverts : c.nverts)),
	      "another seed gives another mesh");
	mesh_free(&a);
	mesh_free(&b);
	mesh_free(&c);
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
}

/* The field's buffers let go after a run (pipeline_release_field): the mesh
 * stays readable as it was, the densities are not, and the next run makes
 * them again and gives the same mesh and densities; a stage after the
 * density's without it is refused. */
static void check_release(void)
{
	struct params p;
	params_defaults(&p);
	p.grid = 24;
	struct grid g;
	grid_from_params(&g, &p);
	char err[256];
	struct fixture_terrain ft;
	CHECK(fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) == 0, "release: %s", err);
	if (!ft.pl)
		return;
	size_t nd = (size_t)grid_dens_count(&g);
	float *da = malloc(nd * 4), *db = malloc(nd * 4);
	struct mesh a = { 0 }, kept = { 0 }, again = { 0 };
	CHECK(fixture_run(ft.pl, &p) == 0 && pipeline_read_mesh(ft.pl, &a) == 0 && pipeline_read_density(ft.pl, da) == 0,
	      "release: first run");
	pipeline_release_field(ft.pl);
	pipeline_release_field(ft.pl); /* twice is harmless */
	CHECK(pipeline_read_mesh(ft.pl, &kept) == 0, "release: the mesh is still readable");
	CHECK(kept.ntris == a.ntris && kept.nverts == a.nverts && a.ntris > 0 &&
		      !memcmp(kept.idx, a.idx, 12 * (size_t)a.ntris) && !memcmp(kept.pos, a.pos, 12 * (size_t)a.nverts),
	      "release: the mesh kept as it was (%u triangles)", kept.ntris);
	CHECK(pipeline_read_density(ft.pl, db) < 0, "release: no densities to read");
	CHECK(pipeline_run_stage(ft.pl, &p, PIPE_PYRAMID, err, sizeof(err)) < 0 && strstr(err, "released"),
	      "release: a pyramid stage without its density is refused (%s)", err);
	CHECK(fixture_run(ft.pl, &p) == 0 && pipeline_read_mesh(ft.pl, &again) == 0 &&
		      pipeline_read_density(ft.pl, db) == 0,
	      "release: the next run");
	CHECK(again.ntris == a.ntris && again.nverts == a.nverts && !memcmp(again.idx, a.idx, 12 * (size_t)a.ntris) &&
		      !memcmp(again.pos, a.pos, 12 * (size_t)a.nverts) && !memcmp(da, db, nd * 4),
	      "release: the next run gives the same mesh and densities");
	CHECK(pipeline_check_guards(ft.pl) == 0, "release: output canaries intact");
	mesh_free(&a);
	mesh_free(&kept);
	mesh_free(&again);
	free(da);
	free(db);
	fixture_terrain_close(&ft);
}

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
	long nd = grid_dens_count(g);
	float *dg = malloc(sizeof(float) * (size_t)nd), *dc = malloc(sizeof(float) * (size_t)nd);
	CHECK(pipeline_read_density(pl, dg) == 0, "%s: read density", what);
	noise_set_init(&ns, p->seed);
	density_ref_volume(p, &ns, ed, g->origin, g->cell, g->nx, g->ny, g->nz, dc);
	double dmax = 0, scale = 0;
	for (long i = 0; i < nd; i++) {
		double e = fabs((double)dg[i] - dc[i]);
		if (!isnan(dmax) && !(e <= dmax))
			dmax = e; /* a NaN counts, and stays */
		scale = fmax(scale, fabs((double)dc[i]));
	}
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
static void check_cache(void)
{
	struct params p;
	params_defaults(&p);
	set_kv(&p, "grid=16;ao_rays=0;warp_amp=0");
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "";
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "cache: pipeline_create: %s", err);
	if (!pl) {
		terrain_destroy(tr);
		edits_destroy(ed);
		return;
	}
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
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
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
	snprintf(kv, sizeof(kv), "grid=16;ao_rays=0;heightmap=%s;heightmap_scale=4%s%s;%s", hm_file, t->ctx[0] ? ";" : "",
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
		struct curve_set cs = { &cp, 1 };
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

static void check_terms(void)
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
static void check_curves_switch(void)
{
	struct params p;
	params_defaults(&p);
	set_kv(&p, "grid=16;ao_rays=0");
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "";
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "curves switch: %s", err);
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
		struct curve_set cs = { &cp, 1 };
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
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
}

int main(void)
{
	struct platform *plat = fixture_open();
	struct params p;
	struct grid g;
	const char *fields[] = { "torus", "bumps", "ripple" };
	int grids[] = { 8, 33, 64, 100 };
	for (int f = 0; f < 3; f++)
		for (int i = 0; i < 4; i++) {
			preset(&p, fields[f]);
			p.grid = grids[i];
			grid_from_params(&g, &p);
			char what[64];
			snprintf(what, sizeof(what), "%s", fields[f]);
			check_field(what, &p, &g, f == 0, f > 0 && grids[i] == 64);
		}
	/* open volumes: the surface runs into the border, interior edges still closed */
	const char *open_fields[] = { "bumps", "ripple" };
	for (int f = 0; f < 2; f++) {
		preset(&p, open_fields[f]);
		p.closed = false;
		p.grid = 33;
		grid_from_params(&g, &p);
		char what[64];
		snprintf(what, sizeof(what), "%s open", open_fields[f]);
		check_field(what, &p, &g, 0, false);
	}
	/* a non-cubic grid, off-centre */
	preset(&p, "torus");
	struct grid odd = { 37, 21, 50, { -1.13f, -0.61f, -1.31f }, 2.5f / 50.0f, 0, { 0, 0, 0 } };
	check_field("torus non-cubic", &p, &odd, 0, false);
	/* noise terrain (ALU Perlin, default GPU Gems density) */
	int tgrids[] = { 33, 100 };
	for (int i = 0; i < 2; i++) {
		params_defaults(&p);
		p.ao_rays = i == 0 ? 8 : 0; /* the AO vertex variant must give the same mesh */
		p.grid = tgrids[i];
		grid_from_params(&g, &p);
		check_field("noise terrain", &p, &g, 0, false);
	}
	check_worst_case();
	check_determinism();
	check_release();
	check_cache();
	check_terms();
	check_curves_switch();
	platform_close(plat);
	return tc_done("pipeline");
}
