/* isoterra — the extraction engine's field seam: what a density field gives
 * the engine (pipeline.h).  As in HPMC (Dyken et al.), the engine knows
 * nothing about what the field is: a provider names the GLSL program that
 * defines it and binds whatever that program reads; the engine runs the
 * density pass with it and extracts the surface.
 *
 * The program file (shaders/, GLSL ES 3.10) is written like this:
 *
 *     #include "common.glsl"          // the engine's grid uniforms; the density pass
 *     #ifdef FIELD_PASS_VERTICES
 *     #include "mc_vertices.comp"     // the engine's vertex pass
 *     #endif
 *     ... float density(vec3 ws) { ... }       // > 0 inside, world units
 *     ... float density_far(vec3 ws) { ... }   // without its finest detail
 *
 * The engine compiles it with one of
 *     FIELD_PASS_DENSITY   the density pass (main() in common.glsl): the
 *                          field at every corner of the grid and its margin
 *                          (with DENSITY_CUT or DENSITY_REFINE: `cuts`
 *                          below)
 *     FIELD_PASS_VERTICES  the vertex pass when it computes ambient
 *                          occlusion (WITH_AO; main() in mc_vertices.comp):
 *                          the long rays of a world block (AO_FAR_OUTSIDE)
 *                          read density_far() outside the block
 * defined, after the parameters' specialization #defines
 * (params_glsl_specialization: the enum terms as constants, TERM_<NAME>
 * 0|1) and the provider's own (`defines` below); the parameter
 * uniforms (u_<name>) are declared by the shader prelude and set by the
 * engine.  A program is compiled once per distinct set of #defines and
 * kept in the engine's cache (docs/PIPELINE.md, "Specialization").  A field may use the binding points, texture units and uniform
 * buffers app/gpu/abi.h gives no engine pass (BIND_CURVES, TEX_NOISE*,
 * TEX_HEIGHTMAP, UBIND_NOISE, ...). */
#ifndef ISOTERRA_FIELD_H
#define ISOTERRA_FIELD_H

#include <stddef.h>
#include <GLES3/gl31.h>

#include "params.h"

struct grid; /* core/grid.h */

struct field {
	const char *program; /* the program file, as above */
	/* Binds the field's resources and sets its uniforms on prog (the
	 * engine has set the grid and parameter uniforms); called before every
	 * dispatch of a program made from the file.  0, or -1 with err (left
	 * empty when the failure was already logged as a GL error). */
	int (*bind)(void *ctx, GLuint prog, const struct params *p, char *err, size_t errlen);
	/* Optional (NULL: none).  The provider's specialization for p: GLSL
	 * #define lines that switch off code its data leaves unused (say, no
	 * curves loaded), written to buf (NUL-terminated); called before
	 * every dispatch of a program made from the file, before bind.  The
	 * text is part of the program's cache key, so it must only carry
	 * on/off flags, never values that move (counts, positions): those are
	 * uniforms set in bind.  Returns the length written, or -1 with err
	 * (buf too small: err may stay empty). */
	int (*defines)(void *ctx, const struct params *p, char *buf, size_t len, char *err, size_t errlen);
	/* Optional (NULL: never).  True when the field's density pass may
	 * leave out the finest detail of samples far from the surface for p
	 * on grid g (the field may judge whether it pays on that grid):
	 * the engine then compiles it with DENSITY_CUT, where the field sets
	 * g_density_cut for such a sample (its sign must be exact, and its
	 * value within the ambient occlusion's saturation on the rock side:
	 * at least 1/ao_short_k and 1/ao_long_k above the iso level when the
	 * exact one is), and after the last slab runs the field's program
	 * with DENSITY_REFINE, which computes whole every cut sample within
	 * two samples of a sign change (common.glsl), so the surface's
	 * vertices and normals see exact values. */
	bool (*cuts)(void *ctx, const struct params *p, const struct grid *g);
	void *ctx;           /* the provider's, passed to bind and defines */
};

#endif
