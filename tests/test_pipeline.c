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
 * variant's densities match the CPU's.
 *
 * One program in three files: this one (the fields, the worst case,
 * determinism, release, and the order of the checks),
 * test_pipeline_compare.c (a mesh against the CPU reference within the
 * stated bound) and test_pipeline_cache.c (the program cache and the
 * density terms). */
#include "pipeline_test.h"
#include "cut_check.h"
#include "gpu_fixture.h"
#include "mesh_check.h"
#include "terrain.h"

#include <math.h>
#include <string.h>
#include <unistd.h>

/* the program's counters (tcheck.h), shared by its files */
int tc_pass, tc_fail;

struct noise_set ns;

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

void density_vs_reference(struct pipeline *pl, struct edits *ed, const struct grid *g, const struct params *p,
			  const char *what, float **dg, float **dc, double *dmax, double *scale)
{
	long nd = grid_dens_count(g);
	*dg = malloc(sizeof(float) * (size_t)nd);
	*dc = malloc(sizeof(float) * (size_t)nd);
	*dmax = 0;
	*scale = 0;
	if (!*dg || !*dc) {
		CHECK(false, "%s: out of memory", what);
		*dmax = NAN;
		return;
	}
	CHECK(pipeline_read_density(pl, *dg) == 0, "%s: read density", what);
	noise_set_init(&ns, p->seed);
	density_ref_volume(p, &ns, ed, g->origin, g->cell, g->nx, g->ny, g->nz, *dc);
	for (long i = 0; i < nd; i++)
		*scale = fmax(*scale, fabs((double)(*dc)[i]));
	/* the far samples the density pass may cut (tests/cut_check.h): the
	 * error counted near the surface and where nothing was cut; the cut
	 * ones held to their contract */
	int m2 = 2 * grid_margin(g) + 1;
	struct cut_stats st;
	cut_compare(p, g->nx + m2, g->ny + m2, g->nz + m2, *dg, *dc, 1e-5 * fmax(*scale, 1.0) + 1e-6, &st);
	*dmax = isnan(st.err_near) || isnan(st.err_far) ? NAN : fmax(st.err_near, st.err_far);
	CHECK(st.bad_sign == 0 && st.bad_rock == 0 && st.bad_near == 0,
	      "%s: cut samples with the wrong sign %zu, too shallow in rock %zu, near the surface %zu", what, st.bad_sign,
	      st.bad_rock, st.bad_near);
	if (st.cut)
		printf("  %s: %zu of %ld samples cut (within %.3g of the reference, exact near the surface)\n", what, st.cut,
		       nd, cut_bound(p));
}

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
	float *dg, *dc;
	double dmax, scale;
	density_vs_reference(pl, ed, g, p, what, &dg, &dc, &dmax, &scale);
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
		/* the stored normal is octahedral, 11 bits a coordinate
		 * (shaders/vertex.glsl): half a step (1/2046) in each, through
		 * the map's stretch (at most sqrt 6), moves a component by up
		 * to 1.7e-3 */
		CHECK(max_nrm_diff(&gm, &cm_g) <= 2.5e-3, "%s: normals differ by %g", what, max_nrm_diff(&gm, &cm_g));
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
	check_cut_cache();
	platform_close(plat);
	return tc_done("pipeline");
}
