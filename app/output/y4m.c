/* isoterra — Y4M stream writer. */
#include "y4m.h"

#include <errno.h>
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

int y4m_open(struct y4m *y, const char *path, int w, int h, int fps, char *err, size_t errlen)
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
		y->f = fopen(path, "wb");
		y->own = 1;
		if (!y->f) {
			snprintf(err, errlen, "cannot write '%s': %s", path, strerror(errno));
			free(y->buf);
			return -1;
		}
	}
	y->w = w;
	y->h = h;
	y->fps = fps > 0 ? fps : 30;
	if (fprintf(y->f, "YUV4MPEG2 W%d H%d F%d:1 Ip A1:1 C420jpeg\n", w, h, y->fps) < 0) {
		snprintf(err, errlen, "cannot write the Y4M header to '%s'", path);
		y4m_close(y);
		return -1;
	}
	return 0;
}

int y4m_write(struct y4m *y, const struct image *img)
{
	if (img->width != y->w || img->height != y->h)
		return -1;
	y4m_convert(img, y->buf);
	size_t n = (size_t)y->w * y->h * 3 / 2;
	if (fputs("FRAME\n", y->f) < 0 || fwrite(y->buf, 1, n, y->f) != n)
		return -1;
	return 0;
}

int y4m_close(struct y4m *y)
{
	int rc = 0;
	if (y->f) {
		if (fflush(y->f) != 0)
			rc = -1;
		if (y->own && fclose(y->f) != 0)
			rc = -1;
	}
	free(y->buf);
	memset(y, 0, sizeof(*y));
	return rc;
}
