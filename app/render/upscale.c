/* isoterra — the passes over a finished frame (render_int.h): a frame
 * drawn into the lower-left part of the render target is resolved into a
 * texture and drawn back over the whole target, with shaders/upscale.frag
 * ("sharp bilinear": one tap, the blend squeezed to 1.5 pixels) or, at
 * full size, shaders/fxaa.frag (edge smoothing).  The overlays and the
 * sinks that come after see a full-size frame. */
#include "render_int.h"
#include "gpu.h"

#include <stdio.h>
#include <string.h>

int upscale_init(struct upscale *u, const char *fs, int w, int h, char *err, size_t errlen)
{
	memset(u, 0, sizeof(*u));
	u->prog = gpu_graphics_program("upscale.vert", fs, NULL, err, errlen);
	if (!u->prog)
		return -1;
	u->w = w;
	u->h = h;
	u->l_src_px = glGetUniformLocation(u->prog, "u_src_px");
	u->l_tex_px = glGetUniformLocation(u->prog, "u_tex_px");
	u->l_alpha = glGetUniformLocation(u->prog, "u_alpha");
	u->l_quarter = glGetUniformLocation(u->prog, "u_quarter"); /* rotate.frag's */
	glUseProgram(u->prog);
	glUniform1i(glGetUniformLocation(u->prog, "u_src"), TEX_FRAME);
	glUseProgram(0);
	glGenTextures(1, &u->tex);
	glBindTexture(GL_TEXTURE_2D, u->tex);
	gpu_texture_2d_storage(GL_RGBA8, w, h, GL_LINEAR);
	glBindTexture(GL_TEXTURE_2D, 0);
	glGenFramebuffers(1, &u->fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, u->fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, u->tex, 0);
	GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	if (st != GL_FRAMEBUFFER_COMPLETE || gpu_check("upscale target") < 0) {
		snprintf(err, errlen, "cannot create the %dx%d texture of %s (framebuffer status 0x%x)", w, h, fs, st);
		upscale_free(u);
		return -1;
	}
	return 0;
}

void upscale_grab(struct upscale *u, GLuint target, int sw, int sh)
{
	glBindFramebuffer(GL_READ_FRAMEBUFFER, target);
	glBindFramebuffer(GL_DRAW_FRAMEBUFFER, u->fbo);
	glBlitFramebuffer(0, 0, sw, sh, 0, 0, sw, sh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

int upscale_draw(struct upscale *u, GLuint target, int sw, int sh, float alpha)
{
	glBindFramebuffer(GL_FRAMEBUFFER, target);
	glViewport(0, 0, u->w, u->h);
	glDisable(GL_DEPTH_TEST);
	if (alpha < 1.0f) { /* over the frame there, its alpha kept */
		glEnable(GL_BLEND);
		glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
	} else {
		glDisable(GL_BLEND);
	}
	glUseProgram(u->prog);
	glUniform2f(u->l_src_px, (float)sw, (float)sh);
	glUniform2f(u->l_tex_px, (float)u->w, (float)u->h);
	glUniform1f(u->l_alpha, alpha);
	glActiveTexture(GL_TEXTURE0 + TEX_FRAME);
	glBindTexture(GL_TEXTURE_2D, u->tex);
	glDrawArrays(GL_TRIANGLES, 0, 3);
	glBindTexture(GL_TEXTURE_2D, 0);
	glDisable(GL_BLEND);
	return gpu_check("full-screen pass");
}

int upscale_draw_rotated(struct upscale *u, GLuint target, int w, int h, int quarter)
{
	glBindFramebuffer(GL_FRAMEBUFFER, target);
	glViewport(0, 0, w, h);
	glDisable(GL_DEPTH_TEST);
	glDisable(GL_BLEND);
	glUseProgram(u->prog);
	glUniform1i(u->l_quarter, quarter);
	glActiveTexture(GL_TEXTURE0 + TEX_FRAME);
	glBindTexture(GL_TEXTURE_2D, u->tex);
	glDrawArrays(GL_TRIANGLES, 0, 3);
	glBindTexture(GL_TEXTURE_2D, 0);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	return gpu_check("rotated pass");
}

int upscale_run(struct upscale *u, GLuint target, int sw, int sh)
{
	upscale_grab(u, target, sw, sh);
	return upscale_draw(u, target, sw, sh, 1.0f);
}

void upscale_free(struct upscale *u)
{
	if (u->prog)
		glDeleteProgram(u->prog);
	if (u->tex)
		glDeleteTextures(1, &u->tex);
	if (u->fbo)
		glDeleteFramebuffers(1, &u->fbo);
	memset(u, 0, sizeof(*u));
}
