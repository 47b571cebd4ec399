/* isoterra — the sampling grid of one extraction. */
#ifndef ISOTERRA_GRID_H
#define ISOTERRA_GRID_H

struct grid {
	int nx, ny, nz;    /* cells per axis */
	float origin[3];   /* world position of corner (0,0,0) */
	float cell;        /* world size of a cell */
};

/* Densities are stored with a one-sample margin: (nx+3)*(ny+3)*(nz+3)
 * values, x fastest; sample (i,j,k) (corner indices, -1..n+1) lives at
 * grid_dens_index(). */
static inline long grid_dens_index(const struct grid *g, int i, int j, int k)
{
	return (long)(i + 1) + (long)(g->nx + 3) * ((long)(j + 1) + (long)(g->ny + 3) * (long)(k + 1));
}
static inline long grid_dens_count(const struct grid *g)
{
	return (long)(g->nx + 3) * (g->ny + 3) * (g->nz + 3);
}

#endif
