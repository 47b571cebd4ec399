/* isoterra — Marching Cubes tables and the CPU reference extractor.
 *
 * Conventions (GPU Gems 3 ch.1, shared by the GPU shaders):
 *  - case byte: bit n set when corner n is inside rock (density > iso);
 *  - corners v0 (0,0,0) v1 (0,1,0) v2 (1,1,0) v3 (1,0,0), v4..v7 = v0..v3 + z;
 *  - edges e0 v0-v1, e1 v1-v2, e2 v2-v3, e3 v3-v0, e4..e7 the same on
 *    v4..v7, e8..e11 v0-v4, v1-v5, v2-v6, v3-v7;
 *  - each cell owns the vertices on its edges 3, 0, 8 (+x, +y, +z from v0):
 *    vertex slots 0/1/2; the vertices of a grid are numbered cell by cell in
 *    linear order over (nx+1)*(ny+1)*(nz+1) owner cells, slot order x, y, z;
 *  - triangles are listed cell by cell in linear order (x fastest), in table
 *    order within a cell, counter-clockwise seen from the air side.
 *
 * The triangulation table is generated (mc_tables.c) from one rule applied
 * per cube face — on a face with two diagonal inside corners, the inside
 * corners are separated — so neighbouring cells always agree on shared faces
 * and the mesh is watertight. */
#ifndef ISOTERRA_MC_H
#define ISOTERRA_MC_H

#include <stdint.h>
#include "core.h"

#define MC_MAX_TRIS 5 /* per cell, checked when the table is built */

struct mc_tables {
	uint8_t tri_count[256];
	int8_t tri[256][MC_MAX_TRIS * 3]; /* edge ids, -1 = unused */
	int8_t corner[8][3];              /* corner offsets */
	int8_t edge_corner[12][2];
	int8_t edge_owner[12][4];         /* owner cell offset x,y,z and slot */
};

/* Builds the tables (a few microseconds; always the same result). */
void mc_tables_build(struct mc_tables *t);

/* Corner (x, y, z) of the margin density volume inside: above iso with one
 * of its six neighbours above too, or below with all six above (the debris
 * rule of shaders/mc_debris.comp); 1 or 0. */
int mc_ref_inside(const struct grid *g, const float *dens, float iso, int x, int y, int z);

/* CPU Marching Cubes over a margin density volume (see grid.h); output in
 * exactly the GPU's order.  0, or -1 when out of memory. */
int mc_ref_extract(const struct grid *g, const float *dens, float iso, struct mesh *out);

#endif
