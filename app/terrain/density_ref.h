/* isoterra — CPU reference of the terrain's density function (plain C,
 * mirrors shaders/density.glsl term by term).  The edit state ed (curves,
 * heightmap; app/edit/edits.h) is read as it is: NULL means none. */
#ifndef ISOTERRA_DENSITY_REF_H
#define ISOTERRA_DENSITY_REF_H

#include <stdbool.h>

#include "params.h"
#include "noise.h"

struct edits;

float density_ref(const struct params *p, const struct noise_set *ns, const struct edits *ed, float x, float y,
		  float z);

/* Fills a (nx+3)*(ny+3)*(nz+3) volume (x fastest) with densities at
 * origin + (i-1, j-1, k-1) * cell, i.e. the corners of nx*ny*nz cells plus a
 * one-sample margin on every side, exactly as the GPU density pass does. */
/* heightmap.glsl: the heightmap's height at (x, z) (0 without one); detail:
 * with the fractal interpolation's noise (needs ns). */
float heightmap_ref_height(const struct edits *e, const struct params *p, const struct noise_set *ns, float x,
			   float z, bool detail);

void density_ref_volume(const struct params *p, const struct noise_set *ns, const struct edits *ed,
			const float origin[3], float cell, int nx, int ny, int nz, float *out);

#endif
