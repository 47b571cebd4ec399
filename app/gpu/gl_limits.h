/* isoterra — the GL implementation limits the program relies on, checked
 * once at start instead of assumed (docs/PLATFORMS.md).
 *
 * Each GPU pass (a compute shader, or a vertex + fragment pair) lists what
 * it uses: storage blocks, samplers, images, uniform blocks and components
 * per stage, its local size and its highest storage-buffer binding.  Every
 * checked limit's need is derived from that list (the largest user wins) or
 * from the binding points of abi.h; tests/test_gl_limits.c compiles each
 * pass and compares the list with what the driver reports for the real
 * shaders, so the list cannot drift from shaders/.
 *
 * Not named "limits.h": app/gpu is on the include path, and a limits.h
 * there would hide the C library's <limits.h>. */
#ifndef ISOTERRA_GL_LIMITS_H
#define ISOTERRA_GL_LIMITS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum gl_stage { GLS_COMPUTE, GLS_VERTEX, GLS_FRAGMENT, GLS_COUNT };

struct gl_stage_use {
	int ssbo;       /* shader storage blocks */
	int samplers;   /* sampler uniforms (texture image units) */
	int images;     /* image uniforms */
	int ubos;       /* uniform blocks */
	int components; /* default-block uniform components (scalars; arrays count every element) */
};

struct gl_pass {
	const char *name;            /* as messages name it: "mc_vertices.comp (WITH_AO)" */
	const char *cs, *vs, *fs;    /* compute shader, or vertex + fragment shaders */
	const char *defines;         /* the #defines that give the pass its largest use */
	bool tests_only;             /* run by the tests, not by the program */
	struct gl_stage_use use[GLS_COUNT];
	int local[3];                /* compute: local size */
	int max_binding;             /* highest storage buffer binding point, -1 = none */
	int attribs;                 /* vertex attributes */
};

/* The passes, tests-only ones included (they are not checked at start). */
const struct gl_pass *gl_limits_passes(size_t *count);

struct gl_limit {
	const char *name;   /* "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", "GL_MAX_COMPUTE_WORK_GROUP_SIZE[1]" */
	unsigned pname;     /* GLenum */
	int index;          /* indexed query (glGetInteger64i_v), -1 = plain */
	int64_t es31_min;   /* the OpenGL ES 3.1 minimum maximum (spec table 20.4x) */
};
const struct gl_limit *gl_limits_list(size_t *count);

/* What isoterra needs of limit i, and the pass (or abi.h name) behind it. */
int64_t gl_limits_need(size_t i, const char **who);

/* Queries every limit in the current context, applies the test-only
 * override ISOTERRA_GL_LIMIT_OVERRIDE="NAME=VALUE[,NAME=VALUE...]" and
 * compares.  0 when all suffice; -1 with ONE line in err naming the limit,
 * the value needed and the value found.  have[] (gl_limits_list order, may
 * be NULL) receives the values as seen. */
int gl_limits_check(int64_t *have, char *err, size_t errlen);

#endif
