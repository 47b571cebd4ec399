/* isoterra — what the terrain's density bound (shaders/density_bound.glsl)
 * covers, and the size of the octaves a coarse level of detail may leave
 * out.  Used by the streaming world's coarse pre-pass and its far-LOD
 * octaves (app/scene/world_gen.c). */
#ifndef ISOTERRA_DENSITY_BOUND_H
#define ISOTERRA_DENSITY_BOUND_H

#include <stdbool.h>

#include "params.h"

struct edits;

/* Octaves the pre-pass evaluates at its lattice points (the rest bounded). */
#define DENSITY_BOUND_OCTAVES 3

/* Whether density_bound() bounds the field p describes with the edit state
 * ed: the procedural terrain (any shape, warp, floor, terraces, shelf,
 * marble, landing pad, the noise-painted control map) with ALU Perlin noise
 * and the geiss, fbm or turbulence sums; no curves, no heightmap, no
 * control map file, no scrolling.  Any other state: every block is
 * generated (no pre-pass). */
bool density_bound_supported(const struct params *p, const struct edits *ed);

/* The largest change to the density that leaving out octaves from..to-1 of
 * the noise term can make (their weights times the basis's bound, times
 * noise_amp); -1 where the fractal family has no such bound (the
 * multiplicative and ridged families, Worley, slope-damped). */
float density_octaves_bound(const struct params *p, int from, int to);

#endif
