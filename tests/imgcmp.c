/* isoterra — test helper: compare two images (PNG, XWD from xwd, binary PPM
 * from QEMU's screendump) with app/image.c's image_compare, or convert one
 * to PNG.
 *
 *   imgcmp A B [--threshold T] [--max-mean M] [--max-frac F] [--min-psnr DB]
 *              [--at X,Y] [--region X,Y,W,H] [--unturn DEG] [--diff OUT.png]
 *       prints "imgcmp: WxH mean_abs .. rmse .. psnr .. max .. frac_over(T) .."
 *       exit 0 within tolerance, 1 over it, 2 on bad input (sizes differ,
 *       unreadable file).  Defaults: T 24, M 1.0, F 0.005.  --min-psnr: the
 *       verdict is the PSNR alone.  --at: B is compared with the rectangle
 *       of A at X,Y of B's size (a video wall's tile in the whole screen).
 *       --region: only that rectangle of both is compared.  --unturn DEG: B
 *       was turned DEG (90, 180, 270) clockwise (--rotate); it is turned
 *       back before the comparison.
 *   imgcmp --to-png IN OUT.png
 *   imgcmp --info IN [X,Y,W,H] prints "WxH mean R G B" of the picture (or
 *                             of that rectangle)
 *   imgcmp --coverage IN EMPTY prints "coverage F horizon H": EMPTY is the
 *       same view with nothing in it (sky, water); a pixel of IN off by
 *       more than 24 in a channel is the subject's.  F: the fraction of
 *       such pixels; H: the horizon, the median over the columns of the
 *       first such pixel from the top, as a fraction of the height (1: a
 *       column with none)
 *       and "round R": how far the subject's outline is from a circle,
 *       the spread (standard deviation) of its distance from the
 *       subject's centroid over 360 directions, as a fraction of its mean
 *       (a disk of radius 100 pixels gives 0.003, a square 0.105; 1: no
 *       subject)
 *   imgcmp --sheet OUT.png COLS IN... a contact sheet: the pictures (all of
 *       one size) halved (2x2 box filter) and tiled COLS to a row, in
 *       order, 4 pixels of dark grey between and around them */
#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image.h"

static int read_file(const char *path, uint8_t **data, size_t *len, char *err, size_t errlen)
{
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "cannot open %s: %s", path, strerror(errno));
		return -1;
	}
	size_t cap = 1 << 20, n = 0;
	uint8_t *buf = malloc(cap);
	while (buf) {
		size_t got = fread(buf + n, 1, cap - n, f);
		n += got;
		if (n < cap)
			break;
		uint8_t *nb = realloc(buf, cap * 2);
		if (!nb) {
			free(buf);
			buf = NULL;
			break;
		}
		buf = nb;
		cap *= 2;
	}
	int bad = ferror(f);
	fclose(f);
	if (!buf || bad) {
		free(buf);
		snprintf(err, errlen, "cannot read %s", path);
		return -1;
	}
	*data = buf;
	*len = n;
	return 0;
}

static uint32_t be32(const uint8_t *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static int mask_shift(uint32_t m)
{
	int s = 0;
	if (!m)
		return 0;
	while (!(m & 1)) {
		m >>= 1;
		s++;
	}
	return s;
}

static uint8_t channel(uint32_t px, uint32_t mask)
{
	if (!mask)
		return 0;
	uint32_t v = (px & mask) >> mask_shift(mask);
	uint32_t max = mask >> mask_shift(mask);
	return (uint8_t)(v * 255u / max);
}

/* X Window Dump (XWDFileHeader, version 7), ZPixmap, 24/32 bits per pixel. */
static int read_xwd(struct image *img, const uint8_t *d, size_t n, const char *path, char *err, size_t errlen)
{
	if (n < 100) {
		snprintf(err, errlen, "%s: too short for an XWD header", path);
		return -1;
	}
	uint32_t h[25];
	for (int i = 0; i < 25; i++)
		h[i] = be32(d + 4 * i);
	uint32_t header_size = h[0], version = h[1], format = h[2], width = h[4], height = h[5];
	uint32_t byte_order = h[7], bpp = h[11], bpl = h[12], rmask = h[14], gmask = h[15], bmask = h[16];
	uint32_t ncolors = h[19];
	if (version != 7 || format != 2 || (bpp != 24 && bpp != 32) || !width || !height || width > 16384 ||
	    height > 16384) {
		snprintf(err, errlen, "%s: unsupported XWD (version %u, format %u, %u bpp, %ux%u)", path, version,
		         format, bpp, width, height);
		return -1;
	}
	size_t off = (size_t)header_size + (size_t)ncolors * 12;
	if (off > n || (size_t)bpl * height > n - off || bpl < width * (bpp / 8)) {
		snprintf(err, errlen, "%s: truncated XWD (%zu bytes)", path, n);
		return -1;
	}
	img->width = (int)width;
	img->height = (int)height;
	img->rgba = malloc((size_t)width * height * 4);
	if (!img->rgba) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (uint32_t y = 0; y < height; y++)
		for (uint32_t x = 0; x < width; x++) {
			const uint8_t *s = d + off + (size_t)y * bpl + (size_t)x * (bpp / 8);
			uint32_t px;
			if (bpp == 32)
				px = byte_order ? be32(s) : (uint32_t)s[0] | (uint32_t)s[1] << 8 | (uint32_t)s[2] << 16 | (uint32_t)s[3] << 24;
			else
				px = byte_order ? ((uint32_t)s[0] << 16 | (uint32_t)s[1] << 8 | s[2])
				                : ((uint32_t)s[0] | (uint32_t)s[1] << 8 | (uint32_t)s[2] << 16);
			uint8_t *o = img->rgba + ((size_t)y * width + x) * 4;
			o[0] = channel(px, rmask);
			o[1] = channel(px, gmask);
			o[2] = channel(px, bmask);
			o[3] = 255;
		}
	return 0;
}

static const uint8_t *ppm_token(const uint8_t *p, const uint8_t *end, long *v)
{
	for (;;) {
		while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r'))
			p++;
		if (p < end && *p == '#') {
			while (p < end && *p != '\n')
				p++;
			continue;
		}
		break;
	}
	if (p >= end || *p < '0' || *p > '9')
		return NULL;
	*v = 0;
	while (p < end && *p >= '0' && *p <= '9' && *v < 100000)
		*v = *v * 10 + (*p++ - '0');
	return p;
}

static int read_ppm(struct image *img, const uint8_t *d, size_t n, const char *path, char *err, size_t errlen)
{
	const uint8_t *p = d + 2, *end = d + n;
	long w = 0, h = 0, max = 0;
	if (!(p = ppm_token(p, end, &w)) || !(p = ppm_token(p, end, &h)) || !(p = ppm_token(p, end, &max)) ||
	    p >= end || w <= 0 || h <= 0 || w > 16384 || h > 16384 || max != 255) {
		snprintf(err, errlen, "%s: unsupported PPM header (want P6, maxval 255)", path);
		return -1;
	}
	p++; /* one whitespace byte */
	if ((size_t)(end - p) < (size_t)w * (size_t)h * 3) {
		snprintf(err, errlen, "%s: truncated PPM", path);
		return -1;
	}
	img->width = (int)w;
	img->height = (int)h;
	img->rgba = malloc((size_t)w * (size_t)h * 4);
	if (!img->rgba) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (size_t i = 0; i < (size_t)w * (size_t)h; i++) {
		img->rgba[4 * i + 0] = p[3 * i + 0];
		img->rgba[4 * i + 1] = p[3 * i + 1];
		img->rgba[4 * i + 2] = p[3 * i + 2];
		img->rgba[4 * i + 3] = 255;
	}
	return 0;
}

static int load(struct image *img, const char *path, char *err, size_t errlen)
{
	memset(img, 0, sizeof(*img));
	uint8_t *d;
	size_t n;
	if (read_file(path, &d, &n, err, errlen) < 0)
		return -1;
	int rc;
	if (n >= 8 && memcmp(d, "\x89PNG\r\n\x1a\n", 8) == 0)
		rc = image_read_png(img, path, err, errlen);
	else if (n >= 2 && d[0] == 'P' && d[1] == '6')
		rc = read_ppm(img, d, n, path, err, errlen);
	else if (n >= 8 && be32(d + 4) == 7)
		rc = read_xwd(img, d, n, path, err, errlen);
	else {
		snprintf(err, errlen, "%s: not a PNG, binary PPM or XWD file", path);
		rc = -1;
	}
	free(d);
	if (rc == 0) /* compare colour only */
		for (size_t i = 0; i < (size_t)img->width * img->height; i++)
			img->rgba[4 * i + 3] = 255;
	return rc;
}

/* img cut to its rectangle x, y, w, h (inside it).  0, or -1 out of memory. */
static int crop(struct image *img, int x, int y, int w, int h)
{
	struct image c = { w, h, malloc((size_t)w * h * 4) };
	if (!c.rgba)
		return -1;
	for (int r = 0; r < h; r++)
		memcpy(c.rgba + (size_t)r * w * 4, img->rgba + ((size_t)(y + r) * img->width + x) * 4, (size_t)w * 4);
	image_free(img);
	*img = c;
	return 0;
}

/* --coverage: pixel x, y is the subject's (off by more than 24 in a channel
 * from the empty view) */
static bool subject_at(const struct image *a, const struct image *b, int x, int y)
{
	const uint8_t *p = a->rgba + 4 * ((size_t)y * a->width + x), *q = b->rgba + 4 * ((size_t)y * b->width + x);
	return abs(p[0] - q[0]) > 24 || abs(p[1] - q[1]) > 24 || abs(p[2] - q[2]) > 24;
}

static int usage(void)
{
	fprintf(stderr, "usage: imgcmp A B [--threshold T] [--max-mean M] [--max-frac F] [--min-psnr DB] [--at X,Y] "
	                "[--region X,Y,W,H] [--unturn DEG] [--diff OUT.png]\n"
	                "       imgcmp --to-png IN OUT.png | imgcmp --info IN [X,Y,W,H] | imgcmp --coverage IN EMPTY\n"
	                "       imgcmp --sheet OUT.png COLS IN...\n");
	return 2;
}

int main(int argc, char **argv)
{
	char err[512];
	struct image a, b;
	if (argc == 4 && strcmp(argv[1], "--to-png") == 0) {
		if (load(&a, argv[2], err, sizeof(err)) < 0 || image_write_png(&a, argv[3], err, sizeof(err)) < 0) {
			fprintf(stderr, "imgcmp: %s\n", err);
			image_free(&a);
			return 2;
		}
		image_free(&a);
		return 0;
	}
	if ((argc == 3 || argc == 4) && strcmp(argv[1], "--info") == 0) {
		if (load(&a, argv[2], err, sizeof(err)) < 0) {
			fprintf(stderr, "imgcmp: %s\n", err);
			return 2;
		}
		int r[4] = { 0, 0, a.width, a.height };
		if (argc == 4 && (sscanf(argv[3], "%d,%d,%d,%d", &r[0], &r[1], &r[2], &r[3]) != 4 || r[0] < 0 || r[1] < 0 ||
				  r[2] < 1 || r[3] < 1 || r[0] + r[2] > a.width || r[1] + r[3] > a.height)) {
			fprintf(stderr, "imgcmp: --info: '%s' is not a rectangle X,Y,W,H inside the %dx%d picture\n", argv[3],
				a.width, a.height);
			image_free(&a);
			return 2;
		}
		double s[3] = { 0, 0, 0 };
		size_t np = (size_t)r[2] * (size_t)r[3];
		for (int y = r[1]; y < r[1] + r[3]; y++)
			for (int x = r[0]; x < r[0] + r[2]; x++)
				for (int c = 0; c < 3; c++)
					s[c] += a.rgba[4 * ((size_t)y * a.width + x) + c];
		printf("%dx%d mean %.1f %.1f %.1f\n", r[2], r[3], s[0] / np, s[1] / np, s[2] / np);
		image_free(&a);
		return 0;
	}
	if (argc >= 5 && strcmp(argv[1], "--sheet") == 0) {
		int cols = atoi(argv[3]), n = argc - 4, gap = 4;
		if (cols < 1) {
			fprintf(stderr, "imgcmp: --sheet: COLS must be a positive number\n");
			return 2;
		}
		struct image sheet = { 0 };
		int cw = 0, ch = 0, rows = (n + cols - 1) / cols;
		for (int i = 0; i < n; i++) {
			if (load(&a, argv[4 + i], err, sizeof(err)) < 0) {
				fprintf(stderr, "imgcmp: %s\n", err);
				image_free(&sheet);
				return 2;
			}
			if (i == 0) {
				cw = a.width / 2;
				ch = a.height / 2;
				sheet.width = gap + cols * (cw + gap);
				sheet.height = gap + rows * (ch + gap);
				sheet.rgba = malloc((size_t)sheet.width * sheet.height * 4);
				if (!sheet.rgba || cw < 1 || ch < 1) {
					fprintf(stderr, "imgcmp: --sheet: no room for a %dx%d sheet\n", sheet.width, sheet.height);
					image_free(&a);
					image_free(&sheet);
					return 2;
				}
				for (size_t k = 0; k < (size_t)sheet.width * sheet.height; k++)
					memcpy(sheet.rgba + 4 * k, (const uint8_t[]){ 40, 40, 44, 255 }, 4);
			} else if (a.width / 2 != cw || a.height / 2 != ch) {
				fprintf(stderr, "imgcmp: --sheet: %s is %dx%d, the first %dx%d\n", argv[4 + i], a.width,
					a.height, 2 * cw, 2 * ch);
				image_free(&a);
				image_free(&sheet);
				return 2;
			}
			int x0 = gap + (i % cols) * (cw + gap), y0 = gap + (i / cols) * (ch + gap);
			for (int y = 0; y < ch; y++)
				for (int x = 0; x < cw; x++)
					for (int c = 0; c < 4; c++) {
						const uint8_t *q = a.rgba + 4 * ((size_t)(2 * y) * a.width + 2 * x) + c;
						size_t row = 4 * (size_t)a.width;
						sheet.rgba[4 * ((size_t)(y0 + y) * sheet.width + x0 + x) + c] =
							(uint8_t)((q[0] + q[4] + q[row] + q[row + 4] + 2) / 4);
					}
			image_free(&a);
		}
		int rc = image_write_png(&sheet, argv[2], err, sizeof(err));
		if (rc < 0)
			fprintf(stderr, "imgcmp: %s\n", err);
		image_free(&sheet);
		return rc < 0 ? 2 : 0;
	}
	if (argc == 4 && strcmp(argv[1], "--coverage") == 0) {
		if (load(&a, argv[2], err, sizeof(err)) < 0 || load(&b, argv[3], err, sizeof(err)) < 0 ||
		    a.width != b.width || a.height != b.height) {
			fprintf(stderr, "imgcmp: --coverage: %s\n", err[0] ? err : "the pictures' sizes differ");
			return 2;
		}
		size_t on = 0;
		double sx = 0.0, sy = 0.0;
		int *top = malloc(sizeof(int) * (size_t)a.width);
		if (!top)
			return 2;
		for (int x = 0; x < a.width; x++) {
			top[x] = a.height;
			for (int y = 0; y < a.height; y++) {
				bool diff = subject_at(&a, &b, x, y);
				on += diff;
				if (diff) {
					sx += x;
					sy += y;
				}
				if (diff && top[x] == a.height)
					top[x] = y;
			}
		}
		/* the outline's distance from the subject's centroid in 360
		 * directions (the farthest subject pixel along each ray): its
		 * spread, as a fraction of its mean */
		double round = 1.0;
		if (on > 0) {
			double cx = sx / (double)on, cy = sy / (double)on, s1 = 0.0, s2 = 0.0;
			double far = (double)a.width + (double)a.height;
			for (int k = 0; k < 360; k++) {
				double dx = cos(k * 3.14159265358979 / 180.0), dy = sin(k * 3.14159265358979 / 180.0), r = 0.0;
				for (double t = 0.0; t < far; t += 0.5) {
					int x = (int)(cx + t * dx + 0.5), y = (int)(cy + t * dy + 0.5);
					if (x < 0 || y < 0 || x >= a.width || y >= a.height)
						break;
					if (subject_at(&a, &b, x, y))
						r = t;
				}
				s1 += r;
				s2 += r * r;
			}
			double mean = s1 / 360.0, var = s2 / 360.0 - mean * mean;
			round = mean > 0.0 ? sqrt(var > 0.0 ? var : 0.0) / mean : 1.0;
		}
		/* the median column (a partial selection sort up to the middle) */
		int m = a.width / 2;
		for (int i = 0; i <= m; i++)
			for (int j = i + 1; j < a.width; j++)
				if (top[j] < top[i]) {
					int t = top[i];
					top[i] = top[j];
					top[j] = t;
				}
		printf("coverage %.3f horizon %.3f round %.3f\n", (double)on / ((double)a.width * a.height),
		       (double)top[m] / a.height, round);
		free(top);
		image_free(&a);
		image_free(&b);
		return 0;
	}
	if (argc < 3 || argv[1][0] == '-' || argv[2][0] == '-')
		return usage();
	int threshold = 24;
	double max_mean = 1.0, max_frac = 0.005;
	const char *diff_path = NULL;
	double min_psnr = -1.0;
	int at_x = -1, at_y = -1, rg[4] = { -1, -1, -1, -1 }, unturn = 0;
	for (int i = 3; i < argc; i += 2) {
		if (i + 1 >= argc)
			return usage();
		if (strcmp(argv[i], "--region") == 0) {
			char tail;
			if (sscanf(argv[i + 1], "%d,%d,%d,%d%c", &rg[0], &rg[1], &rg[2], &rg[3], &tail) != 4 || rg[0] < 0 ||
			    rg[1] < 0 || rg[2] < 1 || rg[3] < 1)
				return usage();
			continue;
		}
		if (strcmp(argv[i], "--at") == 0) {
			char tail;
			if (sscanf(argv[i + 1], "%d,%d%c", &at_x, &at_y, &tail) != 2 || at_x < 0 || at_y < 0)
				return usage();
			continue;
		}
		char *end;
		errno = 0;
		double v = strtod(argv[i + 1], &end);
		bool num_ok = *end == 0 && errno == 0 && v >= 0;
		if (strcmp(argv[i], "--threshold") == 0 && num_ok && v <= 255)
			threshold = (int)v;
		else if (strcmp(argv[i], "--max-mean") == 0 && num_ok)
			max_mean = v;
		else if (strcmp(argv[i], "--max-frac") == 0 && num_ok && v <= 1)
			max_frac = v;
		else if (strcmp(argv[i], "--unturn") == 0 && num_ok && (v == 90 || v == 180 || v == 270))
			unturn = (int)v / 90;
		else if (strcmp(argv[i], "--min-psnr") == 0 && num_ok)
			min_psnr = v;
		else if (strcmp(argv[i], "--diff") == 0)
			diff_path = argv[i + 1];
		else
			return usage();
	}
	if (load(&a, argv[1], err, sizeof(err)) < 0) {
		fprintf(stderr, "imgcmp: %s\n", err);
		return 2;
	}
	if (load(&b, argv[2], err, sizeof(err)) < 0) {
		fprintf(stderr, "imgcmp: %s\n", err);
		image_free(&a);
		return 2;
	}
	int rc = 2;
	struct image_diff d;
	if (unturn) { /* B turned back: q quarter turns counter-clockwise */
		int w = b.width, h = b.height, ow = unturn & 1 ? h : w, oh = unturn & 1 ? w : h;
		uint32_t *out = malloc((size_t)w * h * 4), *in = (uint32_t *)b.rgba;
		if (!out) {
			fprintf(stderr, "imgcmp: out of memory\n");
			image_free(&a);
			image_free(&b);
			return 2;
		}
		/* out(x, y) of the upright picture: where the turn put it */
		for (int y = 0; y < oh; y++)
			for (int x = 0; x < ow; x++) {
				int bx = unturn == 1 ? oh - 1 - y : unturn == 2 ? ow - 1 - x : y;
				int by = unturn == 1 ? x : unturn == 2 ? oh - 1 - y : ow - 1 - x;
				out[(size_t)y * ow + x] = in[(size_t)by * w + bx];
			}
		free(b.rgba);
		b.rgba = (uint8_t *)out;
		b.width = ow;
		b.height = oh;
	}
	if (at_x >= 0) { /* A's rectangle at X,Y of B's size */
		if (at_x + b.width > a.width || at_y + b.height > a.height) {
			fprintf(stderr, "imgcmp: %dx%d at %d,%d is outside %s (%dx%d)\n", b.width, b.height, at_x, at_y,
			        argv[1], a.width, a.height);
			image_free(&a);
			image_free(&b);
			return 2;
		}
		if (crop(&a, at_x, at_y, b.width, b.height) < 0) {
			fprintf(stderr, "imgcmp: out of memory\n");
			image_free(&a);
			image_free(&b);
			return 2;
		}
	}
	if (rg[0] >= 0 && a.width == b.width && a.height == b.height) { /* both cut to the region */
		if (rg[0] + rg[2] > a.width || rg[1] + rg[3] > a.height) {
			fprintf(stderr, "imgcmp: region %d,%d,%d,%d is outside %dx%d\n", rg[0], rg[1], rg[2], rg[3], a.width,
			        a.height);
			image_free(&a);
			image_free(&b);
			return 2;
		}
		if (crop(&a, rg[0], rg[1], rg[2], rg[3]) < 0 || crop(&b, rg[0], rg[1], rg[2], rg[3]) < 0) {
			fprintf(stderr, "imgcmp: out of memory\n");
			image_free(&a);
			image_free(&b);
			return 2;
		}
	}
	if (a.width != b.width || a.height != b.height) {
		fprintf(stderr, "imgcmp: sizes differ: %s is %dx%d, %s is %dx%d\n", argv[1], a.width, a.height, argv[2],
		        b.width, b.height);
	} else if (image_compare(&a, &b, threshold, &d) < 0) {
		fprintf(stderr, "imgcmp: image_compare failed\n");
	} else {
		bool ok = min_psnr >= 0 ? d.psnr >= min_psnr : d.mean_abs <= max_mean && d.frac_over <= max_frac;
		printf("imgcmp: %dx%d mean_abs %.3f rmse %.3f psnr %.1f dB max %d frac_over(%d) %.5f -> %s "
		       "(limits: mean %.3f, frac %.5f)\n",
		       a.width, a.height, d.mean_abs, d.rmse, d.psnr, d.max_abs, threshold, d.frac_over,
		       ok ? "MATCH" : "DIFFERENT", max_mean, max_frac);
		rc = ok ? 0 : 1;
		if (diff_path) {
			struct image di = { a.width, a.height, malloc((size_t)a.width * a.height * 4) };
			if (di.rgba) {
				for (size_t i = 0; i < (size_t)a.width * a.height * 4; i++)
					di.rgba[i] = (i & 3) == 3 ? 255 : (uint8_t)abs((int)a.rgba[i] - (int)b.rgba[i]);
				if (image_write_png(&di, diff_path, err, sizeof(err)) < 0)
					fprintf(stderr, "imgcmp: %s\n", err);
				image_free(&di);
			}
		}
	}
	image_free(&a);
	image_free(&b);
	return rc;
}
