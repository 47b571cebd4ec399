/* isoterra — Y4M stream writer. */
#include "y4m.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static unsigned char clamp8(float v)
{
	return (unsigned char)(v < 0.0f ? 0 : v > 255.0f ? 255 : (int)(v + 0.5f));
}

void y4m_convert(const struct image *img, unsigned char *yuv)
{
	int w = img->width, h = img->height;
	unsigned char *Y = yuv, *U = yuv + (size_t)w * h, *V = U + (size_t)(w / 2) * (h / 2);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const unsigned char *p = img->rgba + ((size_t)y * w + x) * 4;
			Y[(size_t)y * w + x] = clamp8(0.299f * p[0] + 0.587f * p[1] + 0.114f * p[2]);
		}
	for (int y = 0; y < h / 2; y++)
		for (int x = 0; x < w / 2; x++) {
			float r = 0, g = 0, b = 0;
			for (int dy = 0; dy < 2; dy++)
				for (int dx = 0; dx < 2; dx++) {
					const unsigned char *p = img->rgba + ((size_t)(2 * y + dy) * w + 2 * x + dx) * 4;
					r += p[0];
					g += p[1];
					b += p[2];
				}
			r *= 0.25f;
			g *= 0.25f;
			b *= 0.25f;
			U[(size_t)y * (w / 2) + x] = clamp8(128.0f - 0.168736f * r - 0.331264f * g + 0.5f * b);
			V[(size_t)y * (w / 2) + x] = clamp8(128.0f + 0.5f * r - 0.418688f * g - 0.081312f * b);
		}
}

void y4m_rate(double fps, int *num, int *den)
{
	*num = 30;
	*den = 1;
	if (!(fps > 0.0) || fps > 1e6)
		return;
	/* the NTSC family: 24000:1001, 30000:1001, 60000:1001 */
	double ntsc = fps * 1.001;
	if (fabs(fps - round(fps)) > 1e-3 && fabs(ntsc - round(ntsc)) < 1e-5 * ntsc) {
		*num = (int)round(ntsc) * 1000;
		*den = 1001;
		return;
	}
	/* otherwise the continued fraction's last convergent with a denominator
	 * up to 1000 (fps is a float: 6 significant digits are all it holds) */
	double x = fps;
	long h0 = 1, k0 = 0, h1 = (long)floor(x), k1 = 1;
	for (int i = 0; i < 32 && fabs((double)h1 / (double)k1 - fps) > 1e-6 * fps; i++) {
		double frac = x - floor(x);
		if (frac < 1e-12)
			break;
		x = 1.0 / frac;
		long a = (long)floor(x);
		long h2 = a * h1 + h0, k2 = a * k1 + k0;
		if (k2 > 1000 || h2 > 1000000000L)
			break;
		h0 = h1;
		k0 = k1;
		h1 = h2;
		k1 = k2;
	}
	if (h1 > 0) {
		*num = (int)h1;
		*den = (int)k1;
	}
}

int y4m_open(struct y4m *y, const char *path, int w, int h, double fps, char *err, size_t errlen)
{
	memset(y, 0, sizeof(*y));
	if ((w & 1) || (h & 1)) {
		snprintf(err, errlen, "Y4M output needs an even --size (4:2:0), got %dx%d", w, h);
		return -1;
	}
	y->buf = malloc((size_t)w * h * 3 / 2);
	if (!y->buf) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	if (!strcmp(path, "-")) {
		y->f = stdout;
	} else {
		if (atomic_open(&y->af, path, err, errlen) < 0) {
			free(y->buf);
			y->buf = NULL;
			return -1;
		}
		y->f = y->af.f;
	}
	y->w = w;
	y->h = h;
	y4m_rate(fps, &y->fps_num, &y->fps_den);
	if (fprintf(y->f, "YUV4MPEG2 W%d H%d F%d:%d Ip A1:1 C420jpeg\n", w, h, y->fps_num, y->fps_den) < 0) {
		snprintf(err, errlen, "cannot write the Y4M header to '%s': %s", path, strerror(errno ? errno : EIO));
		y4m_free(y);
		return -1;
	}
	return 0;
}

int y4m_write(struct y4m *y, const struct image *img)
{
	if (img->width != y->w || img->height != y->h) {
		errno = EINVAL;
		return -1;
	}
	y4m_convert(img, y->buf);
	size_t n = (size_t)y->w * y->h * 3 / 2;
	errno = 0;
	if (fputs("FRAME\n", y->f) < 0 || fwrite(y->buf, 1, n, y->f) != n || (!y->af.f && fflush(y->f) != 0)) {
		if (!errno)
			errno = EIO;
		return -1;
	}
	return 0;
}

int y4m_finish(struct y4m *y, const char *path, char *err, size_t errlen)
{
	if (!y->f)
		return 0;
	FILE *f = y->f;
	y->f = NULL;
	if (y->af.f)
		return atomic_close(&y->af, path, err, errlen);
	errno = 0;
	if (fflush(f) != 0) {
		snprintf(err, errlen, "writing the Y4M stream to stdout failed: %s", strerror(errno ? errno : EIO));
		return -1;
	}
	return 0;
}

int y4m_commit(struct y4m *y, const char *path, char *err, size_t errlen)
{
	if (!y->af.tmp)
		return 0;
	return atomic_commit(&y->af, path, err, errlen);
}

void y4m_free(struct y4m *y)
{
	atomic_abort(&y->af);
	free(y->buf);
	memset(y, 0, sizeof(*y));
}
