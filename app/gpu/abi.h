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

/* ---- shader storage buffers (GL_SHADER_STORAGE_BUFFER binding points) ----
 * Eight binding points, 0..7, and at most six blocks in one pass: Mali's
 * Panfrost gives 8 of each (docs/PLATFORMS.md).  The passes that use the
 * two auxiliary buffers write no vertices or indices, so those share the
 * vertex and index points; whoever binds an auxiliary buffer there binds
 * the vertices or indices back before a pass that writes them
 * (extract/pipeline.c binds every point at the start of each stage). */
#define BIND_DENSITY 0     /* float per grid corner, one-sample margin (density.comp writes) */
#define BIND_HP_BASE 1     /* HistoPyramid level 0: one byte per owner cell, 4 a word */
#define BIND_HP_LEVELS 2   /* HistoPyramid levels 1..top (uvec2 sums), then the prefix sums */
#define BIND_VERTICES 3    /* output vertices (16 bytes each) */
#define BIND_INDICES 4     /* output triangles (3 uint each) */
#define BIND_STATUS 5      /* the status block below */
#define BIND_SIGNS 6       /* sign bit per density sample, 1 = inside (density pass writes, classify reads) */
#define BIND_CURVES 7      /* the curve spatial hash, one buffer of four sections (edit/curves_gl.c) */
#define BIND_AUX_A BIND_VERTICES /* pass-specific: curve bake output, curve test input, raw sign bits, parts */
#define BIND_AUX_B BIND_INDICES  /* pass-specific: curve bake tiles, curve test output, pre-pass verdicts */
#define BIND_TEST_OUT BIND_INDICES /* hp_test.comp's keys and prefix sums (tests) */
#define BIND_POINTS 8      /* binding points used: 0 .. BIND_POINTS-1 */

/* ---- uniform buffers --------------------------------------------------- */
#define UBIND_NOISE 0      /* noise rotations and seed keys (terrain/noise_gl.c) */
#define UBIND_MC_TABLES 1  /* Marching Cubes tables, packed (extract/pipeline.c, common.glsl) */
#define MC_TABLE_CASE_WORDS 2 /* per case: 15 edge ids of 4 bits (15 = none), the triangle count in bits 60..63 */

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
