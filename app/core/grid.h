/* isoterra — the sampling grid of one extraction. */
#ifndef ISOTERRA_GRID_H
#define ISOTERRA_GRID_H

struct grid {
	int nx, ny, nz;    /* cells per axis */
	float origin[3];   /* world position of global corner (0,0,0) */
	float cell;        /* world size of a cell */
	int margin_extra;  /* density samples kept beyond the one-sample margin
	                      (ambient-occlusion rays of world blocks) */
	int base[3];       /* global index of this grid's corner (0,0,0): corner
	                      (i,j,k) is at origin + (base + (i,j,k)) * cell, so
	                      neighbouring blocks compute shared corners alike */
};

static inline int grid_margin(const struct grid *g) { return 1 + g->margin_extra; }

/* The world box of the grid's cells: corner (0,0,0) .. (nx,ny,nz). */
static inline void grid_box(const struct grid *g, float lo[3], float hi[3])
{
	const int n[3] = { g->nx, g->ny, g->nz };
	for (int a = 0; a < 3; a++) {
		lo[a] = g->origin[a] + g->cell * (float)g->base[a];
		hi[a] = lo[a] + g->cell * (float)n[a];
	}
}

/* Densities are stored with a margin of m = grid_margin() samples:
 * (nx+1+2m)*(ny+1+2m)*(nz+1+2m) values, x fastest; sample (i,j,k) (corner
 * indices, -m..n+m) lives at grid_dens_index().  With the default margin
 * of 1 that is (nx+3)*(ny+3)*(nz+3). */
static inline long grid_dens_index(const struct grid *g, int i, int j, int k)
{
	int m = grid_margin(g);
	return (long)(i + m) + (long)(g->nx + 1 + 2 * m) * ((long)(j + m) + (long)(g->ny + 1 + 2 * m) * (long)(k + m));
}
static inline long grid_dens_count(const struct grid *g)
{
	int m = grid_margin(g);
	return (long)(g->nx + 1 + 2 * m) * (g->ny + 1 + 2 * m) * (g->nz + 1 + 2 * m);
}

#endif
