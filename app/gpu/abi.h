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
 * Four binding points, 0..3 (the OpenGL ES 3.1 minimum), and at most four
 * blocks in any pass of the default volume or the world; a pass that
 * carves curves takes a fifth, BIND_CURVES (Mali's Panfrost gives 8).  A
 * point is a role, not a buffer: each pass binds what it reads and writes
 * right before its dispatch (extract/pipeline.c), so the names below that
 * share a number are the roles of different passes. */
#define BIND_FIELD 0       /* what a pass reads of the field: the densities, or their sign bits */
#define BIND_HP 1          /* the HistoPyramid: level 0, levels 1..top, the prefix sums (hp.glsl) */
#define BIND_OUT 2         /* what a pass writes: vertices, indices, sign bits, a bake, ... */
#define BIND_STATUS 3      /* the status block below */
#define BIND_CURVES 4      /* the curve spatial hash, one buffer of four sections (edit/curves_gl.c) */
#define BIND_POINTS 5      /* binding points used: 0 .. BIND_POINTS-1 (4 without curves) */

#define BIND_DENSITY BIND_FIELD  /* float per grid corner, one-sample margin (the density pass writes) */
#define BIND_SIGNS BIND_FIELD    /* sign bit per density sample, 1 = inside (classification, indices read) */
#define BIND_SIGNS_OUT BIND_OUT  /* the density pass's raw sign bits, the debris filter's filtered ones */
#define BIND_VERTICES BIND_OUT   /* output vertices (16 bytes each) */
#define BIND_INDICES BIND_OUT    /* output triangles (3 uint each) */
#define BIND_AUX_IN BIND_HP      /* pass-specific input: the pre-pass's boxes, bake tiles, test input */
#define BIND_AUX_OUT BIND_OUT    /* pass-specific output: the pre-pass's verdicts, the bake, the parts, tests */
#define BIND_CUT BIND_HP         /* the density pass's cut bits (1 = a far sample whose finest octaves were left
				  * out, common.glsl), then the debris filter's near bits: the refine passes read them */
#define BIND_REFINE BIND_OUT     /* the refine list: refine_mark.comp writes it, the field's refine variant reads it */
#define BIND_CASE_SIGNS BIND_HP  /* the comparison methods (atomic append, no compaction): the filtered sign bits
				  * for the cells' cases, beside the densities (they build no pyramid) */
#define BIND_DEBRIS BIND_STATUS  /* the debris filter's candidate list: mc_debris.comp writes it, mc_debris_flood.comp
				  * reads it (neither reads the status block) */

/* ---- the debris filter's candidate list (BIND_DEBRIS) ----------------------
 * A header, then an entry of two words for each sign word with candidates
 * (samples that may belong to debris of more than two samples): its
 * index and its candidate bits.  A word is listed once: room for all of
 * them.  Then, from word DL_HEAD + 2 * u_sign_words on, the candidate bits
 * of every sign word (DL_BITS): the flood's growth stops at an inside
 * sample that is no candidate (a debris component's samples all are).
 * extract/buffers.c sizes it; mc_debris.comp writes it,
 * mc_debris_flood.comp reads it. */
#define DEBRIS_SPAN 6   /* debris: a component of inside samples spanning at most this many along each axis */
#define DEBRIS_BOX (2 * DEBRIS_SPAN + 1) /* the box its growth runs in, samples an edge (within a world block's
					 * density margin of 1 + 6: a decision at a block's last sample reads 6 on) */
#define DL_DISPATCH 0u /* DispatchIndirectCommand of the flood pass (3 words) */
#define DL_COUNT 3u    /* entries */
#define DL_HEAD 4u     /* the header's words */
#define DL_BITS(sign_words) (DL_HEAD + 2u * (sign_words)) /* the candidate bits' first word */

/* ---- the refine list (BIND_REFINE): the cut samples near the surface ------
 * A header, then u_refine_cap sample entries (a sample's bit index in the
 * sign buffer), then word entries (a sign word whose samples the list had
 * no room for; its cut bits hold them): shaders/refine_mark.comp writes
 * it, common.glsl (DENSITY_REFINE) reads it, extract/pipeline.c sizes it. */
#define RF_DISPATCH 0u /* DispatchIndirectCommand of the refine pass (3 words) */
#define RF_SAMPLES 3u /* sample entries asked for (may pass the capacity: the rest went into word entries) */
#define RF_WORDS 4u   /* word entries */
#define RF_HEAD 8u    /* the header's words */

/* ---- the far samples' cut (shaders/fractal.glsl, terrain/terrain.c) -------- */
#define CUT_LAST_OCTAVE 2    /* the cut is tried before octaves 0 .. this one only */
#define CUT_NOISE_BOUND 1.11 /* |an octave's noise term| is below this (fractal.glsl) */

/* ---- compute work groups -------------------------------------------------- */
#define WG_SIZE 64         /* invocations of every 1D compute pass's work group (local_size_x); the host
			    * divides its dispatch sizes by it */
#define SIGN_SLAB_ALIGN 64 /* bits: a z slab of the sign buffer is padded to a multiple of this (two
			    * words; common.glsl sign_slab_bits, extract/pipeline.c sign_words) */

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
#define TEX_ROADS 6        /* the curves' road map: Θ, surface, height (edit/curves_gl.c, render.frag) */
#define TEX_SURFACE 7      /* the generated surface texture (render/surface_tex.c) */
#define TEX_FRAME 0        /* the finished frame, read by the V4L2 conversion and the OSD's pass */
#define NOISE_TEX_SIZE 16  /* the 3D noise textures' edge, texels (terrain/noise.c, noise_gl.c) */

/* ---- image units ---------------------------------------------------------- */
#define IMG_CONVERT_OUT 0  /* the V4L2 conversion's output image */

/* ---- curves ------------------------------------------------------------- */
#define CURVE_KIND_TUNNEL 3 /* the kind (a curve's params .z) that bores instead of shaping the surface
			     * (edit/curves.h enum curve_kind, curves.glsl) */
#define CURVE_KIND_BRIDGE 4 /* the kind that adds a deck instead of shaping the surface */
#define ROAD_SURFACE_ASPHALT 1 /* a curve's params .w, the road map's green (edit/curves.h enum curve_surface, */
#define ROAD_SURFACE_GRAVEL 2  /* curve_bake.comp, render.frag); 0: none (rivers) */
#define ROAD_SURFACE_DIRT 3
#define ROAD_SURFACE_BALLAST 4

/* ---- shading ------------------------------------------------------------ */
#define DETAIL_RANGE 25.0  /* world units: the detail normals fade out there (render.frag); farther meshes
			    * are drawn by the variant without them (render.c) */
#define DETAIL_FINE_SHARE 0.25 /* the finer of the two detail scales fades out at this share of DETAIL_RANGE;
				* farther meshes are drawn by the variant without it (render.c) */

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
#define VERTEX_BYTES 16      /* vec3 position, one word: normal, AO, sun (shaders/vertex.glsl) */
#define VERTEX_OCT_BITS 11   /* bits per octahedral normal coordinate (bits 0-21) */
#define VERTEX_OCT_STEPS 2046 /* codes 0 .. 2046 of each: 0.0 is code 1023 exactly */
/* bits 22-26: ambient visibility, 27-31: sun visibility (0 .. 31 = 0 .. 1) */

#endif
