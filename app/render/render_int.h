/* isoterra — app/render's private interfaces: the passes over a finished
 * frame (upscale.c): the upscale that brings a frame drawn at a lower
 * resolution (the governor's render scale) to the full size of the render
 * target, and the edge smoothing of --antialias fxaa. */
#ifndef ISOTERRA_RENDER_INT_H
#define ISOTERRA_RENDER_INT_H

#include <stddef.h>
#include <GLES3/gl31.h>

struct upscale {
	GLuint prog, tex, fbo; /* the low-resolution copy, sampled */
	int w, h;              /* the texture's size (the target's) */
	GLint l_src_px, l_tex_px;
};

/* At the target's size w x h, drawing with fragment shader fs
 * (upscale.frag, or fxaa.frag).  0, or -1 with err. */
int upscale_init(struct upscale *u, const char *fs, int w, int h, char *err, size_t errlen);
/* Copies the lower-left sw x sh of target (resolving it if multisampled)
 * and draws it back over the whole w x h target, upscaled.  0 or -1. */
int upscale_run(struct upscale *u, GLuint target, int sw, int sh);
void upscale_free(struct upscale *u);

#endif
