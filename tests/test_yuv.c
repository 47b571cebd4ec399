/* isoterra — the V4L2 colour conversion on the GPU (hal/convert.c +
 * shaders/v4l2_convert.comp) against a CPU reference of the BT.601 / BT.709
 * limited-range formulas, for every output format, tight and padded lines,
 * even and odd sizes, a device size other than the frame's (scaled); the
 * asynchronous read-back ring and the paced sink.
 * Tolerance: 1 code value (rounding of float vs double). */
#include "app.h"
#include "convert.h"
#include "v4l2_out.h"
#include "hal.h"
#include "hal_config.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <math.h>
#include <string.h>

static uint32_t rng = 99;
static uint32_t rnd(void)
{
	rng = rng * 1664525u + 1013904223u;
	return rng >> 8;
}

/* CPU reference: img is top row first, RGBA8. */
static const uint8_t *px(const uint8_t *img, int w, int h, int x, int y)
{
	x = x < w ? x : w - 1;
	y = y < h ? y : h - 1;
	return img + 4 * ((size_t)y * w + x);
}
static double luma(const double c[3], double kr, double kb) { return kr * c[0] + (1 - kr - kb) * c[1] + kb * c[2]; }
static int q(double v) { v = floor(v + 0.5); return v < 0 ? 0 : v > 255 ? 255 : (int)v; }
static void avg(const uint8_t *img, int w, int h, int x, int y, int nx, int ny, double c[3])
{
	c[0] = c[1] = c[2] = 0;
	for (int j = 0; j < ny; j++)
		for (int i = 0; i < nx; i++)
			for (int k = 0; k < 3; k++)
				c[k] += px(img, w, h, x + i, y + j)[k] / 255.0 / (nx * ny);
}
static int Y(const double c[3], double kr, double kb) { return q(16 + 219 * luma(c, kr, kb)); }
static int Cb(const double c[3], double kr, double kb) { return q(128 + 112 * (c[2] - luma(c, kr, kb)) / (1 - kb)); }
static int Cr(const double c[3], double kr, double kb) { return q(128 + 112 * (c[0] - luma(c, kr, kb)) / (1 - kr)); }

static void reference(const struct frame_format *f, const uint8_t *img, uint8_t *out)
{
	int w = f->width, h = f->height;
	uint32_t bpl = f->bytesperline;
	double kr, kb;
	conv_matrix_k(f->matrix, &kr, &kb);
	memset(out, 0, f->sizeimage);
	int cw = (w + 1) / 2, ch = (h + 1) / 2;
	int xe = f->fmt == CF_YUYV || f->fmt == CF_UYVY ? 2 * cw : w; /* odd widths: the last pixel twice */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < xe; x++) {
			double c[3];
			avg(img, w, h, x, y, 1, 1, c);
			uint8_t *row = out + (size_t)y * bpl;
			switch (f->fmt) {
			case CF_RGB24: for (int k = 0; k < 3; k++) row[3 * x + k] = px(img, w, h, x, y)[k]; break;
			case CF_BGR24: for (int k = 0; k < 3; k++) row[3 * x + k] = px(img, w, h, x, y)[2 - k]; break;
			case CF_YUYV:
			case CF_UYVY: {
				int base = 4 * (x / 2), u = f->fmt == CF_UYVY;
				row[base + (x % 2 ? 2 : 0) + u] = (uint8_t)Y(c, kr, kb);
				if (x % 2 == 0) {
					double a[3];
					avg(img, w, h, x, y, 2, 1, a);
					row[base + 1 - u] = (uint8_t)Cb(a, kr, kb);
					row[base + 3 - u] = (uint8_t)Cr(a, kr, kb);
				}
				break;
			}
			default: row[x] = (uint8_t)Y(c, kr, kb); break;
			}
		}
	if (f->fmt == CF_NV12 || f->fmt == CF_NV21 || f->fmt == CF_YU12) {
		uint8_t *cp = out + (size_t)bpl * h;
		for (int y = 0; y < ch; y++)
			for (int x = 0; x < cw; x++) {
				double a[3];
				avg(img, w, h, 2 * x, 2 * y, 2, 2, a);
				int u = Cb(a, kr, kb), v = Cr(a, kr, kb);
				if (f->fmt == CF_YU12) {
					uint32_t cb = bpl / 2;
					cp[(size_t)y * cb + x] = (uint8_t)u;
					cp[(size_t)cb * ch + (size_t)y * cb + x] = (uint8_t)v;
				} else {
					int swap = f->fmt == CF_NV21;
					cp[(size_t)y * bpl + 2 * x + swap] = (uint8_t)u;
					cp[(size_t)y * bpl + 2 * x + 1 - swap] = (uint8_t)v;
				}
			}
	}
}

/* The largest difference of got (NULL: 256) from the reference bytes of
 * img, and how many bytes differ. */
static int diff_reference(const struct frame_format *f, const uint8_t *img, const uint8_t *got, int *ndiff)
{
	uint8_t *want = malloc(f->sizeimage);
	int maxd = got ? 0 : 256;
	*ndiff = 0;
	reference(f, img, want);
	for (uint32_t i = 0; got && i < f->sizeimage; i++) {
		int d = abs((int)got[i] - (int)want[i]);
		maxd = d > maxd ? d : maxd;
		*ndiff += d > 0;
	}
	free(want);
	return maxd;
}

/* A source framebuffer holding img (GL rows bottom first). */
static GLuint upload(const uint8_t *img, int w, int h, GLuint *tex)
{
	uint8_t *flip = malloc((size_t)w * h * 4);
	for (int y = 0; y < h; y++)
		memcpy(flip + (size_t)(h - 1 - y) * w * 4, img + (size_t)y * w * 4, (size_t)w * 4);
	glGenTextures(1, tex);
	glBindTexture(GL_TEXTURE_2D, *tex);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, flip);
	free(flip);
	GLuint fbo;
	glGenFramebuffers(1, &fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	return fbo;
}

static void make_image(uint8_t *img, int w, int h)
{
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			uint8_t *p = img + 4 * ((size_t)y * w + x);
			if (y < h / 2) { /* smooth ramps and the extremes */
				p[0] = (uint8_t)(255 * x / (w - 1));
				p[1] = (uint8_t)(255 * y / (h / 2));
				p[2] = (uint8_t)(255 - p[0]);
			} else { /* noise */
				p[0] = (uint8_t)rnd();
				p[1] = (uint8_t)rnd();
				p[2] = (uint8_t)rnd();
			}
			p[3] = 255;
		}
	memset(img, 255, 16); /* white and black pixels */
	memset(img + 16, 0, 12);
}

static int sink_frames;
static void sink(void *user, const uint8_t *bytes, size_t size)
{
	(void)bytes;
	(void)size;
	(void)user;
	sink_frames++;
}

int main(void)
{
	struct platform *plat = fixture_open();
	char err[512];
	static const int sizes[][2] = { { 64, 48 }, { 37, 21 } };
	for (int s = 0; s < 2; s++) {
		int w = sizes[s][0], h = sizes[s][1];
		uint8_t *img = malloc((size_t)w * h * 4);
		make_image(img, w, h);
		GLuint tex, fbo = upload(img, w, h, &tex);
		for (int fmt = 0; fmt < CF_COUNT; fmt++)
			for (int m = 0; m < 2; m++)
				for (int pad = 0; pad < 3; pad++) {
					struct frame_format f = { .fmt = fmt, .width = w, .height = h, .matrix = m };
					conv_fmt_tight(fmt, w, h, &f.bytesperline, &f.sizeimage);
					if (pad) { /* a device with padded lines (by 12, or by 2: lines
						    * not 4-byte aligned, the packed 4:2:2 fallback) and a larger buffer */
						f.bytesperline += pad == 1 ? 12 : 2;
						f.sizeimage = conv_fmt_min_size(fmt, h, f.bytesperline) + 100;
					}
					struct gpu_conv *c = gpu_conv_create(&f, 2, hal_config_gpu(), err, sizeof(err));
					CHECK(c != NULL, "create %s: %s", conv_fmt_name(fmt), err);
					if (!c)
						continue;
					CHECK(gpu_conv_submit(c, fbo, w, h) == 1, "submit");
					const uint8_t *got = gpu_conv_ready(c, true);
					CHECK(got != NULL, "read-back %s", conv_fmt_name(fmt));
					int ndiff, maxd = diff_reference(&f, img, got, &ndiff);
					printf("%dx%d %-5s %s %s: max diff %d, %d of %u bytes differ\n", w, h, conv_fmt_name(fmt),
					       m ? "bt709" : "bt601", pad ? "padded" : "tight ", maxd, ndiff, f.sizeimage);
					CHECK(maxd <= 1, "%dx%d %s matrix %d pad %d: max diff %d", w, h, conv_fmt_name(fmt), m, pad, maxd);
					CHECK(ndiff <= (int)f.sizeimage / 50, "%s: %d bytes off by one (> 2%%)", conv_fmt_name(fmt), ndiff);
					gpu_conv_release(c);
					gpu_conv_destroy(c);
				}
		/* a device that takes a different size: the conversion scales.  A
		 * frame rendered at twice the size in 2x2 blocks of the image's
		 * pixels must give the image's own bytes (bilinear sampling at the
		 * blocks' centres), in every format. */
		if (s == 0) {
			int w2 = 2 * w, h2 = 2 * h;
			uint8_t *big = malloc((size_t)w2 * h2 * 4);
			for (int y = 0; y < h2; y++)
				for (int x = 0; x < w2; x++)
					memcpy(big + 4 * ((size_t)y * w2 + x), img + 4 * ((size_t)(y / 2) * w + x / 2), 4);
			GLuint btex, bfbo = upload(big, w2, h2, &btex);
			for (int fmt = 0; fmt < CF_COUNT; fmt++) {
				struct frame_format f = { .fmt = fmt, .width = w, .height = h, .matrix = CM_BT709 };
				conv_fmt_tight(fmt, w, h, &f.bytesperline, &f.sizeimage);
				struct gpu_conv *c = gpu_conv_create(&f, 2, hal_config_gpu(), err, sizeof(err));
				CHECK(c != NULL, "create %s: %s", conv_fmt_name(fmt), err);
				if (!c)
					continue;
				CHECK(gpu_conv_submit(c, bfbo, w2, h2) == 1, "submit scaled");
				const uint8_t *got = gpu_conv_ready(c, true);
				int ndiff, maxd = diff_reference(&f, img, got, &ndiff);
				printf("%dx%d frame -> %dx%d %-5s (scaled): max diff %d\n", w2, h2, w, h, conv_fmt_name(fmt),
				       maxd);
				CHECK(maxd <= 1, "scaled %s: max diff %d", conv_fmt_name(fmt), maxd);
				gpu_conv_release(c);
				gpu_conv_destroy(c);
			}
			glDeleteFramebuffers(1, &bfbo);
			glDeleteTextures(1, &btex);
			free(big);
		}
		/* the ring: three frames in flight without waiting, then in order */
		struct frame_format f = { .fmt = CF_YUYV, .width = w, .height = h };
		conv_fmt_tight(CF_YUYV, w, h, &f.bytesperline, &f.sizeimage);
		struct gpu_conv *c = gpu_conv_create(&f, 3, hal_config_gpu(), err, sizeof(err));
		int n = 0;
		for (int i = 0; i < 4; i++)
			n += gpu_conv_submit(c, fbo, w, h);
		CHECK(n == 3, "a ring of 3 takes 3 frames (%d), the 4th is dropped", n);
		CHECK(gpu_conv_pending(c) == 3, "3 pending");
		int got = 0;
		while (gpu_conv_ready(c, true)) {
			got++;
			gpu_conv_release(c);
		}
		CHECK(got == 3 && gpu_conv_pending(c) == 0, "3 frames came back (%d)", got);
		gpu_conv_destroy(c);
		/* the paced sink: 12 frames at 100 fps take >= 110 ms */
		if (s == 0) {
			struct v4l2_out *v = v4l2_out_open_bytes(&f, 100.0, sink, NULL, hal_config_gpu(), err, sizeof(err));
			CHECK(v != NULL, "sink: %s", err);
			uint64_t t0 = hal_now_ns();
			for (int i = 0; v && i < 12; i++)
				CHECK(v4l2_out_frame(v, fbo, w, h) == 0, "sink frame");
			double ms = (double)(hal_now_ns() - t0) / 1e6;
			struct v4l2_stats st;
			if (v)
				v4l2_out_stats(v, &st);
			v4l2_out_close(v);
			printf("sink: 12 frames at 100 fps in %.1f ms, %d delivered\n", ms, sink_frames);
			CHECK(ms >= 105.0, "paced: %.1f ms", ms);
			CHECK(sink_frames == 12, "every frame delivered (%d)", sink_frames);
		}
		glDeleteFramebuffers(1, &fbo);
		glDeleteTextures(1, &tex);
		free(img);
	}
	platform_close(plat);
	return tc_done("yuv");
}
