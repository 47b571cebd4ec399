// isoterra — the terrain's program for the extraction engine (its field
// provider: app/terrain/terrain.c; the seam: app/extract/field.h).
// Compiled with FIELD_PASS_DENSITY it is the density pass (main() in
// common.glsl), with FIELD_PASS_VERTICES the vertex pass with ambient
// occlusion (mc_vertices.comp), with FIELD_PASS_BOUND the streaming world's
// coarse pre-pass (block_bound.glsl); density.glsl defines the field.
#include "common.glsl"
#ifdef FIELD_PASS_VERTICES
#include "mc_vertices.comp"
#endif
#include "density.glsl"
#ifdef FIELD_PASS_BOUND
#include "density_bound.glsl" // the world's coarse pre-pass
#endif
