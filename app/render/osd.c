/* isoterra — on-screen display (see osd.h). */
#include "osd.h"
#include "font.h"
#include "gpu.h"

#include <stdlib.h>
#include <string.h>

#define OSD_ROWS 2

struct osd {
	GLuint prog, vao, font;
	GLint l_text, l_box, l_fb, l_scale, l_bar, l_alpha, l_font;
};

struct osd *osd_create(char *err, size_t errlen)
{
	struct osd *o = calloc(1, sizeof(*o));
	if (!o) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	o->prog = gpu_graphics_program("osd.vert", "osd.frag", NULL, err, errlen);
	if (!o->prog) {
		free(o);
		return NULL;
	}
	o->l_text = glGetUniformLocation(o->prog, "u_text");
	o->l_box = glGetUniformLocation(o->prog, "u_box");
	o->l_fb = glGetUniformLocation(o->prog, "u_fb");
	o->l_scale = glGetUniformLocation(o->prog, "u_scale");
	o->l_bar = glGetUniformLocation(o->prog, "u_bar");
	o->l_alpha = glGetUniformLocation(o->prog, "u_alpha");
	o->l_font = glGetUniformLocation(o->prog, "u_font");
	/* the font as an R8UI texture: one 6x8 cell per character */
	enum { TW = FONT_COUNT * FONT_W };
	uint8_t texels[FONT_H][TW];
	for (int c = 0; c < FONT_COUNT; c++) {
		const uint8_t *g = font_glyph(FONT_FIRST + c);
		for (int y = 0; y < FONT_H; y++)
			for (int x = 0; x < FONT_W; x++)
				texels[y][c * FONT_W + x] = x < 5 && (g[y] >> (4 - x)) & 1;
	}
	glGenTextures(1, &o->font);
	glBindTexture(GL_TEXTURE_2D, o->font);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_R8UI, TW, FONT_H);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, TW, FONT_H, GL_RED_INTEGER, GL_UNSIGNED_BYTE, texels);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
	glBindTexture(GL_TEXTURE_2D, 0);
	glGenVertexArrays(1, &o->vao);
	if (gpu_check("OSD setup") < 0) {
		snprintf(err, errlen, "cannot set up the on-screen display (GL error)");
		osd_destroy(o);
		return NULL;
	}
	return o;
}

void osd_destroy(struct osd *o)
{
	if (!o)
		return;
	if (o->prog)
		glDeleteProgram(o->prog);
	if (o->font)
		glDeleteTextures(1, &o->font);
	if (o->vao)
		glDeleteVertexArrays(1, &o->vao);
	free(o);
}

static size_t row_len(const char *s)
{
	size_t n = s ? strlen(s) : 0;
	return n > OSD_COLS ? OSD_COLS : n;
}

int osd_fit_scale(int w, int h, int cols)
{
	int scale = h >= 1080 ? 4 : h >= 600 ? 3 : h >= 300 ? 2 : 1;
	/* the box (cols * 6 + 8 font pixels) and its margins (2 on each side) */
	while (scale > 1 && (cols * 6 + 8) * scale > w - 4 * scale)
		scale--;
	return scale;
}

static int draw_box(struct osd *o, GLuint fbo, int w, int h, bool right, const char *title, const char *value,
		    float bar, int scale, float alpha);

int osd_draw(struct osd *o, GLuint fbo, int w, int h, const char *title, const char *value, float bar, int scale,
	     float alpha)
{
	return draw_box(o, fbo, w, h, false, title, value, bar, scale, alpha);
}

int osd_draw_right(struct osd *o, GLuint fbo, int w, int h, const char *title, const char *value, float bar, int scale,
		   float alpha)
{
	return draw_box(o, fbo, w, h, true, title, value, bar, scale, alpha);
}

static int draw_box(struct osd *o, GLuint fbo, int w, int h, bool right, const char *title, const char *value,
		    float bar, int scale, float alpha)
{
	GLuint text[OSD_COLS * OSD_ROWS];
	const char *rows[OSD_ROWS] = { title, value };
	size_t cols = 1;
	for (int r = 0; r < OSD_ROWS; r++) {
		size_t n = row_len(rows[r]);
		if (n > cols)
			cols = n;
		for (size_t c = 0; c < OSD_COLS; c++)
			text[r * OSD_COLS + c] = c < n ? (unsigned char)rows[r][c] : ' ';
	}
	if (scale <= 0)
		scale = osd_fit_scale(w, h, (int)cols);
	/* box: 4 font pixels of margin, rows of 10, the bar (3 + margin) */
	float bw = (float)((cols * 6 + 8) * (size_t)scale);
	float bh = (float)((OSD_ROWS * 10 + 3 + 3 + (bar >= 0 ? 4 : 0)) * scale);
	if (bw > (float)w - 2 * scale)
		bw = (float)w - 2 * scale;
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glViewport(0, 0, w, h);
	glDisable(GL_DEPTH_TEST);
	glDisable(GL_CULL_FACE);
	glEnable(GL_BLEND);
	glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
	glUseProgram(o->prog);
	glUniform1uiv(o->l_text, OSD_COLS * OSD_ROWS, text);
	float x = right ? (float)w - bw - (float)(2 * scale) : (float)(2 * scale);
	glUniform4f(o->l_box, x < 0 ? 0.0f : x, (float)(2 * scale), bw, bh);
	glUniform2f(o->l_fb, (float)w, (float)h);
	glUniform1f(o->l_scale, (float)scale);
	glUniform1f(o->l_bar, bar < 0 ? -1.0f : bar > 1 ? 1.0f : bar);
	glUniform1f(o->l_alpha, alpha < 0 ? 0.0f : alpha > 1 ? 1.0f : alpha);
	glActiveTexture(GL_TEXTURE0);
	glBindTexture(GL_TEXTURE_2D, o->font);
	glUniform1i(o->l_font, 0);
	glBindVertexArray(o->vao);
	glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	glBindVertexArray(0);
	glBindTexture(GL_TEXTURE_2D, 0);
	glUseProgram(0);
	glDisable(GL_BLEND);
	return gpu_check("OSD draw");
}
