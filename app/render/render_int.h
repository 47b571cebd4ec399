/* isoterra — app/render's private interfaces: the passes over a finished
 * frame (upscale.c): the upscale that brings a frame drawn at a lower
 * resolution (the governor's render scale) to the full size of the render
 * target, and the edge smoothing of --antialias fxaa; and a mesh's draw
 * split into parts (parts.c). */
#ifndef ISOTERRA_RENDER_INT_H
#define ISOTERRA_RENDER_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <GLES3/gl31.h>

struct upscale {
	GLuint prog, tex, fbo; /* the low-resolution copy, sampled */
	int w, h;              /* the texture's size (the target's) */
	GLint l_src_px, l_tex_px, l_alpha, l_quarter;
};

/* At the target's size w x h, drawing with fragment shader fs
 * (upscale.frag, or fxaa.frag).  0, or -1 with err. */
int upscale_init(struct upscale *u, const char *fs, int w, int h, char *err, size_t errlen);
/* Copies the lower-left sw x sh of target (resolving it if multisampled)
 * and draws it back over the whole w x h target, upscaled.  0 or -1. */
int upscale_run(struct upscale *u, GLuint target, int sw, int sh);
/* The two halves of upscale_run: the copy into the texture, and the
 * texture drawn over the whole target, blended with weight alpha below 1
 * (u_alpha of the fragment shader). */
void upscale_grab(struct upscale *u, GLuint target, int sw, int sh);
int upscale_draw(struct upscale *u, GLuint target, int sw, int sh, float alpha);
/* The whole texture (rotate.frag) over target's w x h, turned quarter
 * quarter turns clockwise.  0 or -1. */
int upscale_draw_rotated(struct upscale *u, GLuint target, int w, int h, int quarter);
void upscale_free(struct upscale *u);

/* ---- a mesh drawn in parts (parts.c, shaders/draw_parts.comp) -------------
 * A software rasterizer bins all of a draw's triangles before it rasterizes
 * any of them: llvmpipe held 19.9 MB of bins for the no-flag picture's
 * 121 504 triangles.  Drawn as parts of RENDER_PART_TRIANGLES (render.h),
 * each finished before the next is binned, it holds one part's.  The parts are made on
 * the GPU from the mesh's indirect command (no read-back): as many as the
 * mesh's capacity needs, at most PARTS_MAX (larger parts then); those past
 * the mesh's end draw nothing. */
#define PARTS_MAX 64
#define PART_BYTES 20 /* a part's command: DrawElements- or DrawArraysIndirectCommand, padded */

struct draw_parts {
	GLuint prog, buf;
	GLint l_src, l_part, l_parts, l_indexed;
};

/* Parts of at least `triangles` (> 0) for a mesh of at most capacity
 * triangles, and the triangles in each. */
uint32_t parts_plan(uint32_t capacity, uint32_t triangles, uint32_t *per_part);
/* Writes the parts of the indirect command at byte offset in src
 * (indexed: DrawElements, else DrawArrays) into dp->buf, PART_BYTES apart,
 * with the plan's numbers; the compute program and buffer are made at the
 * first call.  0, or -1 (logged). */
int parts_split(struct draw_parts *dp, GLuint src, GLintptr offset, bool indexed, uint32_t parts, uint32_t per_part);
void parts_free(struct draw_parts *dp);

#endif
