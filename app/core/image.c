/* isoterra — RGBA8 images, PNG read/write with libpng, golden comparison. */
#include "image.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>

#include "atomic_file.h"
#include "log.h"

/* Largest accepted image edge; keeps w*h*4 far from overflowing. */
#define IMAGE_MAX_DIM 65536

void image_free(struct image *img)
{
	free(img->rgba);
	img->rgba = NULL;
	img->width = img->height = 0;
}

/* ---- libpng glue --------------------------------------------------------- */

struct png_ctx {
	FILE *f;
	char msg[200];
};

static void png_err_fn(png_structp png, png_const_charp msg)
{
	struct png_ctx *c = png_get_error_ptr(png);
	snprintf(c->msg, sizeof(c->msg), "%s", msg);
	png_longjmp(png, 1);
}

static void png_warn_fn(png_structp png, png_const_charp msg)
{
	(void)png;
	log_debug("libpng: %s", msg);
}

static void png_read_fn(png_structp png, png_bytep data, size_t len)
{
	struct png_ctx *c = png_get_io_ptr(png);
	if (fread(data, 1, len, c->f) != len)
		png_error(png, ferror(c->f) ? "read error" : "unexpected end of file (truncated PNG)");
}

static void png_write_fn(png_structp png, png_bytep data, size_t len)
{
	struct png_ctx *c = png_get_io_ptr(png);
	if (fwrite(data, 1, len, c->f) != len)
		png_error(png, strerror(errno));
}

static void png_flush_fn(png_structp png)
{
	(void)png;
}

int image_write_png_staged(const struct image *img, const char *path, struct atomic_file *af, char *err,
			   size_t errlen)
{
	af->f = NULL;
	af->tmp = NULL;
	if (!img || !img->rgba || img->width <= 0 || img->height <= 0 ||
	    img->width > IMAGE_MAX_DIM || img->height > IMAGE_MAX_DIM) {
		snprintf(err, errlen, "cannot write '%s': invalid image %dx%d", path,
		         img ? img->width : 0, img ? img->height : 0);
		return -1;
	}
	size_t w = (size_t)img->width, h = (size_t)img->height;
	png_bytep *rows = malloc(h * sizeof(*rows));
	if (!rows) {
		snprintf(err, errlen, "out of memory writing '%s'", path);
		return -1;
	}
	bool opaque = true;
	for (size_t i = 0; i < w * h && opaque; i++)
		opaque = img->rgba[i * 4 + 3] == 255;
	for (size_t y = 0; y < h; y++)
		rows[y] = img->rgba + y * w * 4;

	if (atomic_open(af, path, err, errlen) < 0) {
		free(rows);
		return -1;
	}
	struct png_ctx ctx = { .f = af->f };
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, png_err_fn, png_warn_fn);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	if (!info) {
		snprintf(err, errlen, "out of memory writing '%s'", path);
		png_destroy_write_struct(&png, NULL);
		atomic_abort(af);
		free(rows);
		return -1;
	}
	if (setjmp(png_jmpbuf(png))) {
		snprintf(err, errlen, "cannot write '%s': %s", path, ctx.msg);
		png_destroy_write_struct(&png, &info);
		atomic_abort(af);
		free(rows);
		return -1;
	}
	png_set_write_fn(png, &ctx, png_write_fn, png_flush_fn);
	png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8,
	             opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA,
	             PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	/* zlib level 1 and the "sub" filter on every row, not libpng's level 6
	 * and its trial of all five filters a row: the no-flag 1280x720 frame
	 * is written in 31 ms of CPU instead of 83 (level 3, all filters) or
	 * 312 (the defaults), and is 7 % larger than at level 3 (14 % than
	 * at 6) */
	png_set_compression_level(png, 1);
	png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
	png_write_info(png, info);
	if (opaque) /* RGB file from the RGBA buffer: drop the 4th byte */
		png_set_filler(png, 0, PNG_FILLER_AFTER);
	png_write_image(png, rows);
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	free(rows);
	return atomic_close(af, path, err, errlen);
}

int image_write_png_gray16(const char *path, const uint16_t *v, int w, int h, char *err, size_t errlen)
{
	if (!v || w <= 0 || h <= 0 || w > IMAGE_MAX_DIM || h > IMAGE_MAX_DIM) {
		snprintf(err, errlen, "cannot write '%s': invalid image %dx%d", path, w, h);
		return -1;
	}
	uint8_t *row = malloc((size_t)w * 2);
	if (!row) {
		snprintf(err, errlen, "out of memory writing '%s'", path);
		return -1;
	}
	struct atomic_file af;
	if (atomic_open(&af, path, err, errlen) < 0) {
		free(row);
		return -1;
	}
	struct png_ctx ctx = { .f = af.f };
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, png_err_fn, png_warn_fn);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	if (!info) {
		snprintf(err, errlen, "out of memory writing '%s'", path);
		png_destroy_write_struct(&png, NULL);
		atomic_abort(&af);
		free(row);
		return -1;
	}
	if (setjmp(png_jmpbuf(png))) {
		snprintf(err, errlen, "cannot write '%s': %s", path, ctx.msg);
		png_destroy_write_struct(&png, &info);
		atomic_abort(&af);
		free(row);
		return -1;
	}
	png_set_write_fn(png, &ctx, png_write_fn, png_flush_fn);
	png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
		     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_write_info(png, info);
	for (int y = 0; y < h; y++) {
		for (int x = 0; x < w; x++) {
			uint16_t s = v[(size_t)y * (size_t)w + (size_t)x];
			row[2 * x] = (uint8_t)(s >> 8); /* PNG is big-endian */
			row[2 * x + 1] = (uint8_t)(s & 0xff);
		}
		png_write_row(png, row);
	}
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	free(row);
	if (atomic_close(&af, path, err, errlen) < 0)
		return -1;
	return atomic_commit(&af, path, err, errlen);
}

int image_write_png(const struct image *img, const char *path, char *err, size_t errlen)
{
	struct atomic_file af;
	if (image_write_png_staged(img, path, &af, err, errlen) < 0)
		return -1;
	return atomic_commit(&af, path, err, errlen);
}

/* Opens path and checks the PNG signature; 0, or -1 with err. */
static int png_open(struct png_ctx *ctx, const char *path, char *err, size_t errlen)
{
	ctx->msg[0] = 0;
	ctx->f = fopen(path, "rb");
	if (!ctx->f) {
		snprintf(err, errlen, "cannot open '%s': %s", path, strerror(errno));
		return -1;
	}
	png_byte sig[8];
	size_t n = fread(sig, 1, sizeof(sig), ctx->f);
	if (n != sizeof(sig) || png_sig_cmp(sig, 0, sizeof(sig)) != 0) {
		if (ferror(ctx->f))
			snprintf(err, errlen, "cannot read '%s': %s", path, strerror(errno));
		else
			snprintf(err, errlen, "'%s' is not a PNG file", path);
		fclose(ctx->f);
		ctx->f = NULL;
		return -1;
	}
	return 0;
}

static png_structp png_reader(struct png_ctx *ctx, png_infop *info)
{
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, ctx, png_err_fn, png_warn_fn);
	*info = png ? png_create_info_struct(png) : NULL;
	if (!*info) {
		png_destroy_read_struct(&png, NULL, NULL);
		return NULL;
	}
	png_set_read_fn(png, ctx, png_read_fn);
	png_set_sig_bytes(png, 8);
	png_set_user_limits(png, IMAGE_MAX_DIM, IMAGE_MAX_DIM);
	/* the ancillary chunks nothing here uses (text, ICC profiles, suggested
	 * palettes, Exif) are skipped unread: libpng would allocate what their
	 * length field claims (up to 2 GB) before finding the file too short */
	static const png_byte skip[] = "iCCP\0iTXt\0sPLT\0tEXt\0zTXt\0eXIf";
	png_set_keep_unknown_chunks(png, PNG_HANDLE_CHUNK_NEVER, skip, (int)(sizeof(skip) / 5));
	return png;
}

/* The file opened and checked, and a reader on it (png_reader), or NULL
 * with err and the file closed. */
static png_structp png_begin(struct png_ctx *ctx, const char *path, png_infop *info, char *err, size_t errlen)
{
	if (png_open(ctx, path, err, errlen) < 0)
		return NULL;
	png_structp png = png_reader(ctx, info);
	if (!png) {
		snprintf(err, errlen, "out of memory reading '%s'", path);
		fclose(ctx->f);
	}
	return png;
}

int image_read_png_size(const char *path, int *w, int *h, char *err, size_t errlen)
{
	*w = *h = 0;
	struct png_ctx ctx;
	png_infop info;
	png_structp png = png_begin(&ctx, path, &info, err, errlen);
	if (!png)
		return -1;
	if (setjmp(png_jmpbuf(png))) {
		snprintf(err, errlen, "cannot read PNG '%s': %s", path, ctx.msg);
		png_destroy_read_struct(&png, &info, NULL);
		fclose(ctx.f);
		return -1;
	}
	png_read_info(png, info); /* the chunks before the image data: no decoding */
	*w = (int)png_get_image_width(png, info);
	*h = (int)png_get_image_height(png, info);
	png_destroy_read_struct(&png, &info, NULL);
	fclose(ctx.f);
	return 0;
}

int image_read_png(struct image *img, const char *path, char *err, size_t errlen)
{
	img->width = img->height = 0;
	img->rgba = NULL;
	struct png_ctx ctx;
	png_infop info;
	png_structp png = png_begin(&ctx, path, &info, err, errlen);
	if (!png)
		return -1;
	uint8_t *volatile pixels = NULL;
	png_bytep *volatile rows = NULL;
	if (setjmp(png_jmpbuf(png))) {
		snprintf(err, errlen, "cannot read PNG '%s': %s", path, ctx.msg);
		png_destroy_read_struct(&png, &info, NULL);
		free(pixels);
		free(rows);
		fclose(ctx.f);
		return -1;
	}
	png_read_info(png, info);
	png_set_expand(png);       /* palette -> RGB, gray < 8 bits -> 8, tRNS -> alpha */
	png_set_strip_16(png);
	png_set_gray_to_rgb(png);
	png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
	png_set_interlace_handling(png);
	png_read_update_info(png, info);
	png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
	if (png_get_channels(png, info) != 4 || png_get_bit_depth(png, info) != 8 ||
	    png_get_rowbytes(png, info) != (size_t)w * 4)
		png_error(png, "unsupported pixel format after conversion to RGBA8");
	pixels = malloc((size_t)w * h * 4);
	rows = malloc(h * sizeof(png_bytep));
	if (!pixels || !rows)
		png_error(png, "out of memory");
	for (png_uint_32 y = 0; y < h; y++)
		rows[y] = pixels + (size_t)y * w * 4;
	png_read_image(png, rows);
	png_read_end(png, NULL);
	png_destroy_read_struct(&png, &info, NULL);
	free(rows);
	fclose(ctx.f);
	img->width = (int)w;
	img->height = (int)h;
	img->rgba = pixels;
	return 0;
}

static const char *color_type_name(int ct)
{
	switch (ct) {
	case PNG_COLOR_TYPE_GRAY: return "gray";
	case PNG_COLOR_TYPE_GRAY_ALPHA: return "gray+alpha";
	case PNG_COLOR_TYPE_RGB: return "RGB";
	case PNG_COLOR_TYPE_RGB_ALPHA: return "RGBA";
	case PNG_COLOR_TYPE_PALETTE: return "palette";
	default: return "unknown";
	}
}

int image_read_png_gray16(const char *path, uint16_t **out, int *w_out, int *h_out, char *err, size_t errlen)
{
	*out = NULL;
	*w_out = *h_out = 0;
	struct png_ctx ctx;
	png_infop info;
	png_structp png = png_begin(&ctx, path, &info, err, errlen);
	if (!png)
		return -1;
	uint8_t *volatile raw = NULL;
	uint16_t *volatile samples = NULL;
	png_bytep *volatile rows = NULL;
	if (setjmp(png_jmpbuf(png))) {
		snprintf(err, errlen, "cannot read heightmap '%s': %s", path, ctx.msg);
		png_destroy_read_struct(&png, &info, NULL);
		free(raw);
		free(samples);
		free(rows);
		fclose(ctx.f);
		return -1;
	}
	png_read_info(png, info);
	int ct = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
	if (ct != PNG_COLOR_TYPE_GRAY && ct != PNG_COLOR_TYPE_GRAY_ALPHA) {
		snprintf(ctx.msg, sizeof(ctx.msg), "color type is %s; heightmaps must be 8- or 16-bit grayscale",
		         color_type_name(ct));
		png_longjmp(png, 1);
	}
	if (depth != 8 && depth != 16) {
		snprintf(ctx.msg, sizeof(ctx.msg), "bit depth is %d; heightmaps must be 8- or 16-bit grayscale",
		         depth);
		png_longjmp(png, 1);
	}
	if (ct == PNG_COLOR_TYPE_GRAY_ALPHA)
		png_set_strip_alpha(png);
	png_set_interlace_handling(png);
	png_read_update_info(png, info);
	png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
	size_t bps = depth == 16 ? 2 : 1;
	if (png_get_channels(png, info) != 1 || png_get_rowbytes(png, info) != (size_t)w * bps)
		png_error(png, "unsupported pixel format");
	raw = malloc((size_t)w * h * bps);
	samples = malloc((size_t)w * h * sizeof(uint16_t));
	rows = malloc(h * sizeof(png_bytep));
	if (!raw || !samples || !rows)
		png_error(png, "out of memory");
	for (png_uint_32 y = 0; y < h; y++)
		rows[y] = raw + (size_t)y * w * bps;
	png_read_image(png, rows);
	png_read_end(png, NULL);
	/* PNG samples are big-endian: decode bytewise, whatever the host. */
	for (size_t i = 0; i < (size_t)w * h; i++)
		samples[i] = bps == 2 ? (uint16_t)(raw[2 * i] << 8 | raw[2 * i + 1]) : (uint16_t)(raw[i] * 257);
	png_destroy_read_struct(&png, &info, NULL);
	free(raw);
	free(rows);
	fclose(ctx.f);
	*out = samples;
	*w_out = (int)w;
	*h_out = (int)h;
	return 0;
}

/* ---- comparison ---------------------------------------------------------- */

int image_compare(const struct image *a, const struct image *b, int threshold, struct image_diff *d)
{
	memset(d, 0, sizeof(*d));
	if (!a->rgba || !b->rgba || a->width != b->width || a->height != b->height ||
	    a->width <= 0 || a->height <= 0)
		return -1;
	size_t n = (size_t)a->width * (size_t)a->height;
	double sum = 0, sum2 = 0;
	size_t over = 0;
	int max = 0;
	for (size_t i = 0; i < n; i++) {
		const uint8_t *pa = a->rgba + i * 4, *pb = b->rgba + i * 4;
		int pmax = 0;
		for (int c = 0; c < 3; c++) {
			int diff = abs((int)pa[c] - (int)pb[c]);
			sum += diff;
			sum2 += (double)diff * diff;
			if (diff > pmax)
				pmax = diff;
		}
		if (pmax > threshold)
			over++;
		if (pmax > max)
			max = pmax;
	}
	double cnt = (double)n * 3.0;
	d->mean_abs = sum / cnt;
	d->rmse = sqrt(sum2 / cnt);
	d->frac_over = (double)over / (double)n;
	d->max_abs = max;
	d->psnr = sum2 == 0 ? INFINITY : 20.0 * log10(255.0 / d->rmse);
	return 0;
}
