/* isoterra — test_pipeline: one test program in files by concern
 * (test_pipeline.c has main and the order of the checks); what they share. */
#ifndef ISOTERRA_PIPELINE_TEST_H
#define ISOTERRA_PIPELINE_TEST_H

#define TCHECK_SHARED /* one pair of counters for the program (test_pipeline.c) */
#include "app.h"
#include "tcheck.h"

#include <stdbool.h>
#include <stdint.h>

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
 *  - a sample is near the iso level when its reference density is within
 *    the bound, or its own (the GPU's) is on the iso level to the mesh's
 *    float precision: the vertices of two of its edges would round onto
 *    its corner (t under 4 x FLT_EPSILON x the coordinates in cells) and
 *    meet there;
 *  - a corner's inside bit depends on its sign and its six neighbours' (the
 *    debris filter, mc_ref.c): it is certain when none of the seven is
 *    near the iso level;
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
 *    a corner on the iso level, to float precision: an ambiguous one), and
 *    watertight
 *    (mesh_topology, test_pipeline.c). */
#define BOUND_K 2.0

struct mesh_cmp {
	double bound;                /* per sample: |reference - iso| <= bound may flip */
	uint64_t near_samples;       /* samples within the bound, or on the iso level to float precision */
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

/* test_pipeline_compare.c */
int mesh_vs_reference(const struct grid *g, float iso, const float *dg, const struct mesh *gm, const float *dc,
		      const struct mesh *cm, double bound, struct mesh_cmp *r);
bool cmp_ok(const struct mesh_cmp *r);
void cmp_print(const char *what, const struct mesh_cmp *r);

/* test_pipeline_cache.c */
void check_cache(void);
void check_terms(void);
void check_curves_switch(void);
void check_cut_cache(void);

/* test_pipeline.c */
extern struct noise_set ns;
/* The pipeline's densities as the GPU left them (dg) and the CPU
 * reference's at the same samples (dc), grid_dens_count(g) floats each
 * (the caller frees both), and the largest |dg - dc| (a NaN counts, and
 * stays): *dmax; *scale the largest |dc|. */
void density_vs_reference(struct pipeline *pl, struct edits *ed, const struct grid *g, const struct params *p,
			  const char *what, float **dg, float **dc, double *dmax, double *scale);

#endif
