/* isoterra — the GL implementation limits the program relies on, queried
 * instead of assumed (docs/PLATFORMS.md).
 *
 * The limits are read once, right after the context is made
 * (gl_limits_check), with the needs that no program declares (the abi.h
 * binding points, the 3D noise textures, the one shared array) checked
 * there.  What each pass uses (storage blocks, samplers, images, uniform
 * blocks and components per stage, its local size, its binding points,
 * its attributes) is the driver's own count: every program is introspected
 * (glGetProgramInterfaceiv / glGetProgramResourceiv) when it is linked or
 * loaded, and refused with one line when it needs more than the driver
 * gives (gl_limits_check_program).  No table of numbers to keep by hand.
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

/* What a linked program uses, as the driver reports it. */
struct gl_use {
	struct gl_stage_use use[GLS_COUNT];
	int ssbo_total;       /* active storage blocks, all stages */
	int max_binding;      /* highest storage buffer binding point, -1 = none */
	int max_ubo_binding;  /* highest uniform buffer binding point, -1 = none */
	int64_t ubo_bytes;    /* largest uniform block (GL_BUFFER_DATA_SIZE) */
	int max_unit;         /* highest texture unit a sampler is set to, -1 = none */
	int max_image_unit;   /* highest image unit, -1 = none */
	int local[3];         /* compute: local size */
	int attribs;          /* vertex attributes */
};

/* The driver's count for a linked program. */
void gl_limits_introspect(unsigned prog, bool compute, struct gl_use *out);

/* The passes the program and its tests build: sources and the #defines
 * that give each its largest use (every storage block a configuration can
 * declare).  tests/test_gl_limits.c builds them all. */
struct gl_pass {
	const char *name;            /* as messages name it: "mc_vertices.comp (WITH_AO)" */
	const char *cs, *vs, *fs;    /* compute shader, or vertex + fragment shaders */
	const char *defines;
	bool tests_only;             /* run by the tests, not by the program */
	/* instead of defines: the library that compiles the pass makes them
	 * (hal/convert.c, the V4L2 conversion) */
	void (*make_defines)(char *buf, size_t len);
};
const struct gl_pass *gl_limits_passes(size_t *count);

struct gl_limit {
	const char *name;   /* "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", "GL_MAX_COMPUTE_WORK_GROUP_SIZE[1]" */
	unsigned pname;     /* GLenum */
	int index;          /* indexed query (glGetInteger64i_v), -1 = plain */
	int64_t es31_min;   /* the OpenGL ES 3.1 minimum maximum (spec table 20.4x) */
};
const struct gl_limit *gl_limits_list(size_t *count);

/* What isoterra needs of limit i so far: for the limits a program's use
 * decides, the largest over the programs checked in this process (0 before
 * any), with who naming the pass; for the others, the fixed need and where
 * it comes from. */
int64_t gl_limits_need(size_t i, const char **who);

/* Queries every limit in the current context, applies the test-only
 * override ISOTERRA_GL_LIMIT_OVERRIDE="NAME=VALUE[,NAME=VALUE...]", keeps
 * the values for gl_limits_check_program and checks the fixed needs.  0
 * when they suffice; -1 with ONE line in err naming the limit, the value
 * needed and the value found.  have[] (gl_limits_list order, may be NULL)
 * receives the values as seen. */
int gl_limits_check(int64_t *have, char *err, size_t errlen);

/* A linked program (what names it in messages) against the limits kept by
 * gl_limits_check: 0, or -1 with one line in err naming the limit, the
 * value found, the program's need and the program.  Without a check
 * before (no limits kept) it only records the needs. */
int gl_limits_check_program(unsigned prog, bool compute, const char *what, char *err, size_t errlen);

#endif
