/* isoterra — the contract between the host and the shaders: binding points,
 * texture units and the words of the status block.  This one file is
 * included by the C code and pasted into every shader's prelude by the
 * shader loader (app/gpu/shader.c), so no binding or status index is written
 * as a number anywhere else.  Plain #defines only: it must read as C and as
 * GLSL ES 3.10.  The enums the shaders see come from the parameter table
 * (params_glsl_decls; the C side: params_enums.h, generated from the same
 * table). */
#ifndef ISOTERRA_ABI_H
#define ISOTERRA_ABI_H

/* ---- shader storage buffers (GL_SHADER_STORAGE_BUFFER binding points) ---- */
#define BIND_DENSITY 0     /* float per grid corner, one-sample margin (density.comp writes) */
#define BIND_HP_BASE 1     /* HistoPyramid level 0: one byte per owner cell, 4 a word */
#define BIND_HP_LEVELS 2   /* HistoPyramid levels 1..top (uvec2 sums), then the prefix sums */
#define BIND_MC_TABLES 3   /* Marching Cubes tables (extract/mc_tables.c) */
#define BIND_VERTICES 4    /* output vertices (32 bytes each) */
#define BIND_INDICES 5     /* output triangles (3 uint each) */
#define BIND_STATUS 6      /* the status block below */
#define BIND_TEST_OUT 7    /* hp_test.comp's keys and prefix sums (tests) */
#define BIND_CURVE_PIVOT 8 /* curve spatial hash: per cell (first, count) */
#define BIND_CURVE_INDEX 9 /* curve spatial hash: quadratic indices */
#define BIND_CURVE_CTRL 10 /* quadratic control points */
#define BIND_CURVE_PRM 11  /* per-quadratic profile parameters */
#define BIND_AUX_A 12      /* pass-specific: curve bake output, curve test input */
#define BIND_AUX_B 13      /* pass-specific: curve bake tiles, curve test output */
#define BIND_SIGNS 14      /* sign bit per density sample, 1 = inside (density pass writes, classify reads) */

/* ---- uniform buffers --------------------------------------------------- */
#define UBIND_NOISE 0      /* noise rotations and seed keys (terrain/noise_gl.c) */

/* ---- texture units ------------------------------------------------------ */
#define TEX_NOISE0 0       /* 16^3 repeating noise textures, three of them */
#define TEX_NOISE1 1
#define TEX_NOISE2 2
#define TEX_HEIGHTMAP 3    /* the heightmap (edit/curves_gl.c) */
#define TEX_CONTROL 4      /* the control map (edit/curves_gl.c) */
#define TEX_SURFACE 7      /* the generated surface texture (render/surface_tex.c) */
#define TEX_FRAME 0        /* the finished frame, read by the V4L2 conversion and the OSD's pass */

/* ---- image units ---------------------------------------------------------- */
#define IMG_CONVERT_OUT 0  /* the V4L2 conversion's output image */

/* ---- shading ------------------------------------------------------------ */
#define DETAIL_RANGE 25.0  /* world units: the detail normals fade out there (render.frag); farther meshes
			    * are drawn by the variant without them (render.c) */

/* ---- the status block (BIND_STATUS): indirect commands + counters --------- */
#define ST_DRAW_ELEMENTS 0   /* DrawElementsIndirectCommand: count, instances, first, baseVertex, baseInstance */
#define ST_DISPATCH_VERTS 8  /* DispatchIndirectCommand of the vertex pass (3 words) */
#define ST_DISPATCH_TRIS 12  /* DispatchIndirectCommand of the triangle pass (3 words) */
#define ST_DRAW_ARRAYS 16    /* DrawArraysIndirectCommand: count, instances, first, baseInstance */
#define ST_TRIS_NEEDED 20    /* what the field asked for */
#define ST_VERTS_NEEDED 21
#define ST_TRIS_WRITTEN 22   /* what was written (clamped to the capacities) */
#define ST_VERTS_WRITTEN 23
#define ST_TRI_CAP 24
#define ST_VERT_CAP 25
#define ST_OVERFLOW 26       /* 1 when the output was clamped */
#define ST_APPEND_COUNTER 27 /* atomic append (compaction=atomic|none): triangles */
#define ST_WORDS 32          /* the block's size in 32-bit words */
#define ST_BYTES (ST_WORDS * 4)

/* ---- vertex format -------------------------------------------------------- */
#define VERTEX_BYTES 16      /* vec3 position, uint normal (octahedral 12+12 bits) + AO (8 bits): shaders/vertex.glsl */

#endif
