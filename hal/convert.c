/* isoterra — GPU conversion and asynchronous read-back (see convert.h). */
#include "convert.h"

#include <linux/videodev2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define OUT_W 1024 /* texels per row of the packed output image (4 bytes each) */
#define MAX_SLOTS 4

static const struct {
	const char *name;
	uint32_t fourcc;
} fmts[CF_COUNT] = {
	[CF_YUYV] = { "YUYV", V4L2_PIX_FMT_YUYV },   [CF_UYVY] = { "UYVY", V4L2_PIX_FMT_UYVY },
	[CF_NV12] = { "NV12", V4L2_PIX_FMT_NV12 },   [CF_NV21] = { "NV21", V4L2_PIX_FMT_NV21 },
	[CF_YU12] = { "YU12", V4L2_PIX_FMT_YUV420 }, [CF_RGB24] = { "RGB24", V4L2_PIX_FMT_RGB24 },
	[CF_BGR24] = { "BGR24", V4L2_PIX_FMT_BGR24 },
};

void conv_shader_defines(enum conv_fmt fmt, char *buf, size_t len)
{
	size_t n = (size_t)snprintf(buf, len, "#define CONV_WG_SIZE %d\n#define FMT %du\n", CONV_WG_SIZE, (int)fmt);
	for (int i = 0; i < CF_COUNT && n < len; i++)
		n += (size_t)snprintf(buf + n, len - n, "#define F_%s %du\n", fmts[i].name, i);
}

void conv_shader_defines_yuyv(char *buf, size_t len)
{
	conv_shader_defines(CF_YUYV, buf, len);
}

const char *conv_fmt_name(enum conv_fmt f) { return f < CF_COUNT ? fmts[f].name : "?"; }
uint32_t conv_fmt_fourcc(enum conv_fmt f) { return f < CF_COUNT ? fmts[f].fourcc : 0; }
bool conv_fmt_is_yuv(enum conv_fmt f) { return f != CF_RGB24 && f != CF_BGR24; }

int conv_fmt_from_fourcc(uint32_t fourcc)
{
	for (int i = 0; i < CF_COUNT; i++)
		if (fmts[i].fourcc == fourcc)
			return i;
	return -1;
}

uint32_t conv_fmt_min_size(enum conv_fmt f, int h, uint32_t bpl)
{
	uint32_t ch = (uint32_t)(h + 1) / 2;
	switch (f) {
	case CF_NV12:
	case CF_NV21: return bpl * (uint32_t)h + bpl * ch;
	case CF_YU12: return bpl * (uint32_t)h + 2 * (bpl / 2) * ch;
	default: return bpl * (uint32_t)h;
	}
}

void conv_fmt_tight(enum conv_fmt f, int w, int h, uint32_t *bpl, uint32_t *size)
{
	uint32_t uw = (uint32_t)w;
	switch (f) {
	case CF_YUYV:
	case CF_UYVY: *bpl = 4 * ((uw + 1) / 2); break;
	case CF_RGB24:
	case CF_BGR24: *bpl = 3 * uw; break;
	case CF_YU12: *bpl = 2 * ((uw + 1) / 2); break;
	default: *bpl = uw + (uw & 1); break;
	}
	*size = conv_fmt_min_size(f, h, *bpl);
}

void conv_matrix_k(enum conv_matrix m, double *kr, double *kb)
{
	*kr = m == CM_BT709 ? 0.2126 : 0.299;
	*kb = m == CM_BT709 ? 0.0722 : 0.114;
}

struct slot {
	GLuint pbo;
	GLsync fence;
	bool busy;
	unsigned long seq;
};

struct gpu_conv {
	struct frame_format f;
	struct hal_gpu gpu;
	GLuint prog, src_tex, src_fbo, out_tex, out_fbo;
	int src_w, src_h, out_h;
	uint32_t words;
	GLint l_scaled, l_w, l_h, l_bpl, l_size, l_words, l_out_w, l_k;
	struct slot slots[MAX_SLOTS];
	int nslots;
	unsigned long seq;
	int mapped; /* slot index mapped by gpu_conv_ready, -1 none */
};

/* glGetError() != GL_NO_ERROR -> reports "what: GL error 0x..." and returns -1. */
static int gl_check(const struct gpu_conv *c, const char *what)
{
	GLenum e = glGetError();
	if (e == GL_NO_ERROR)
		return 0;
	hal_logf(&c->gpu.log, HAL_ERROR, "%s: GL error 0x%04x", what, e);
	while (glGetError() != GL_NO_ERROR)
		;
	return -1;
}

void gpu_conv_destroy(struct gpu_conv *c)
{
	if (!c)
		return;
	if (c->mapped >= 0)
		gpu_conv_release(c);
	for (int i = 0; i < c->nslots; i++) {
		if (c->slots[i].fence)
			glDeleteSync(c->slots[i].fence);
		if (c->slots[i].pbo)
			glDeleteBuffers(1, &c->slots[i].pbo);
	}
	GLuint fb[2] = { c->src_fbo, c->out_fbo }, tx[2] = { c->src_tex, c->out_tex };
	glDeleteFramebuffers(2, fb);
	glDeleteTextures(2, tx);
	if (c->prog)
		glDeleteProgram(c->prog);
	free(c);
}

static GLuint make_target(GLuint *tex, int w, int h, GLenum filter)
{
	GLuint fbo;
	glGenTextures(1, tex);
	glBindTexture(GL_TEXTURE_2D, *tex);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, (GLint)filter);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, (GLint)filter);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
	glBindTexture(GL_TEXTURE_2D, 0);
	glGenFramebuffers(1, &fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
	GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	return st == GL_FRAMEBUFFER_COMPLETE ? fbo : (glDeleteFramebuffers(1, &fbo), 0u);
}

struct gpu_conv *gpu_conv_create(const struct frame_format *f, int nslots, const struct hal_gpu *gpu, char *err,
				 size_t errlen)
{
	if (!gpu || !gpu->compile) {
		snprintf(err, errlen, "the V4L2 conversion needs a shader compiler");
		return NULL;
	}
	if (f->fmt >= CF_COUNT || f->width < 2 || f->height < 2 || nslots < 1 || nslots > MAX_SLOTS ||
	    f->sizeimage < conv_fmt_min_size(f->fmt, f->height, f->bytesperline)) {
		snprintf(err, errlen, "bad frame format for the GPU conversion");
		return NULL;
	}
	struct gpu_conv *c = calloc(1, sizeof(*c));
	if (!c) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	c->f = *f;
	c->gpu = *gpu;
	c->mapped = -1;
	c->nslots = nslots;
	char defs[CONV_DEFINES_MAX];
	conv_shader_defines(f->fmt, defs, sizeof(defs)); /* one program per format */
	c->prog = gpu->compile(gpu->user, "v4l2_convert.comp", defs, err, errlen);
	if (!c->prog) {
		free(c);
		return NULL;
	}
	c->l_scaled = glGetUniformLocation(c->prog, "u_scaled");
	c->l_w = glGetUniformLocation(c->prog, "u_w");
	c->l_h = glGetUniformLocation(c->prog, "u_h");
	c->l_bpl = glGetUniformLocation(c->prog, "u_bpl");
	c->l_size = glGetUniformLocation(c->prog, "u_size");
	c->l_words = glGetUniformLocation(c->prog, "u_words");
	c->l_out_w = glGetUniformLocation(c->prog, "u_out_w");
	c->l_k = glGetUniformLocation(c->prog, "u_k");
	c->words = (f->sizeimage + 3) / 4;
	c->out_h = (int)((c->words + OUT_W - 1) / OUT_W);
	c->out_fbo = make_target(&c->out_tex, OUT_W, c->out_h, GL_NEAREST);
	size_t bytes = (size_t)OUT_W * 4 * (size_t)c->out_h;
	for (int i = 0; i < nslots; i++) {
		glGenBuffers(1, &c->slots[i].pbo);
		glBindBuffer(GL_PIXEL_PACK_BUFFER, c->slots[i].pbo);
		glBufferData(GL_PIXEL_PACK_BUFFER, (GLsizeiptr)bytes, NULL, GL_STREAM_READ);
	}
	glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
	if (!c->out_fbo || gl_check(c, "V4L2 conversion setup") < 0) {
		snprintf(err, errlen, "cannot set up the V4L2 conversion buffers (%dx%d %s)", f->width, f->height,
			 conv_fmt_name(f->fmt));
		gpu_conv_destroy(c);
		return NULL;
	}
	return c;
}

int gpu_conv_submit(struct gpu_conv *c, GLuint src_fbo, int sw, int sh)
{
	int s = -1;
	for (int i = 0; i < c->nslots; i++)
		if (!c->slots[i].busy && i != c->mapped) {
			s = i;
			break;
		}
	if (s < 0)
		return 0;
	if (sw != c->src_w || sh != c->src_h) { /* (re)create the resolve target */
		GLuint fb = c->src_fbo, tx = c->src_tex;
		if (fb)
			glDeleteFramebuffers(1, &fb);
		if (tx)
			glDeleteTextures(1, &tx);
		c->src_fbo = make_target(&c->src_tex, sw, sh, GL_LINEAR);
		c->src_w = sw;
		c->src_h = sh;
		if (!c->src_fbo) {
			c->src_w = 0;
			hal_logf(&c->gpu.log, HAL_ERROR, "V4L2 conversion: cannot create a %dx%d source texture", sw, sh);
			return -1;
		}
	}
	/* resolve (multisampled) / copy the frame into a texture */
	glBindFramebuffer(GL_READ_FRAMEBUFFER, src_fbo);
	glBindFramebuffer(GL_DRAW_FRAMEBUFFER, c->src_fbo);
	glBlitFramebuffer(0, 0, sw, sh, 0, 0, sw, sh, GL_COLOR_BUFFER_BIT, GL_NEAREST);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);

	double kr, kb;
	conv_matrix_k(c->f.matrix, &kr, &kb);
	glUseProgram(c->prog);
	glActiveTexture(GL_TEXTURE0 + c->gpu.tex_frame); /* the shader's binding: the frame's unit */
	glBindTexture(GL_TEXTURE_2D, c->src_tex);
	glUniform1i(c->l_scaled, sw != c->f.width || sh != c->f.height);
	glUniform1ui(c->l_w, (GLuint)c->f.width);
	glUniform1ui(c->l_h, (GLuint)c->f.height);
	glUniform1ui(c->l_bpl, c->f.bytesperline);
	glUniform1ui(c->l_size, c->f.sizeimage);
	glUniform1ui(c->l_words, c->words);
	glUniform1ui(c->l_out_w, OUT_W);
	glUniform2f(c->l_k, (float)kr, (float)kb);
	glBindImageTexture(c->gpu.img_out, c->out_tex, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
	glDispatchCompute((c->words + CONV_WG_SIZE - 1) / CONV_WG_SIZE, 1, 1);
	glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_PIXEL_BUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
	glBindTexture(GL_TEXTURE_2D, 0);
	glActiveTexture(GL_TEXTURE0);
	glUseProgram(0);

	/* start the read-back into the slot's pixel buffer; fence it */
	glBindFramebuffer(GL_READ_FRAMEBUFFER, c->out_fbo);
	glBindBuffer(GL_PIXEL_PACK_BUFFER, c->slots[s].pbo);
	glPixelStorei(GL_PACK_ALIGNMENT, 4);
	glReadPixels(0, 0, OUT_W, c->out_h, GL_RGBA, GL_UNSIGNED_BYTE, (void *)0);
	glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
	glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
	c->slots[s].fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
	if (!c->slots[s].fence || gl_check(c, "V4L2 conversion") < 0)
		return -1;
	glFlush();
	c->slots[s].busy = true;
	c->slots[s].seq = ++c->seq;
	return 1;
}

int gpu_conv_pending(const struct gpu_conv *c)
{
	int n = 0;
	for (int i = 0; i < c->nslots; i++)
		n += c->slots[i].busy;
	return n;
}

const uint8_t *gpu_conv_ready(struct gpu_conv *c, bool wait)
{
	if (c->mapped >= 0)
		return NULL;
	int s = -1;
	for (int i = 0; i < c->nslots; i++)
		if (c->slots[i].busy && (s < 0 || c->slots[i].seq < c->slots[s].seq))
			s = i;
	if (s < 0)
		return NULL;
	GLenum r = glClientWaitSync(c->slots[s].fence, GL_SYNC_FLUSH_COMMANDS_BIT, wait ? 2000000000ull : 0);
	if (r == GL_TIMEOUT_EXPIRED)
		return NULL;
	if (r == GL_WAIT_FAILED) {
		gl_check(c, "V4L2 read-back fence");
		return NULL;
	}
	glDeleteSync(c->slots[s].fence);
	c->slots[s].fence = 0;
	glBindBuffer(GL_PIXEL_PACK_BUFFER, c->slots[s].pbo);
	void *ptr = glMapBufferRange(GL_PIXEL_PACK_BUFFER, 0, (GLsizeiptr)c->f.sizeimage, GL_MAP_READ_BIT);
	glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
	c->slots[s].busy = false;
	if (!ptr) {
		gl_check(c, "V4L2 read-back map");
		return NULL;
	}
	c->mapped = s;
	return ptr;
}

int gpu_conv_release(struct gpu_conv *c)
{
	if (c->mapped < 0)
		return 0;
	glBindBuffer(GL_PIXEL_PACK_BUFFER, c->slots[c->mapped].pbo);
	GLboolean ok = glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
	glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
	c->mapped = -1;
	return ok ? 0 : -1;
}
