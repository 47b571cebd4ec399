/* isoterra — RGBA8 images and PNG files (libpng). */
#ifndef ISOTERRA_IMAGE_H
#define ISOTERRA_IMAGE_H

#include <stdint.h>
#include <stddef.h>
#include "atomic_file.h"

struct image {
	int width, height;
	uint8_t *rgba; /* width*height*4 bytes, top row first */
};

void image_free(struct image *img);
/* Writes an 8-bit RGB(A) PNG atomically: a temp file in the same directory,
 * fsync, then rename; nothing half-written on error.  0 or -1 with err. */
int image_write_png(const struct image *img, const char *path, char *err, size_t errlen);
/* The same PNG into a staged temp file beside path (atomic_close'd): the
 * caller commits it to path, or aborts it.  0 or -1 with err (no temp left). */
int image_write_png_staged(const struct image *img, const char *path, struct atomic_file *af, char *err,
			   size_t errlen);
/* Writes w*h 16-bit grayscale samples (a heightmap, a control map) as a
 * PNG, atomically as image_write_png.  0 or -1 with err. */
int image_write_png_gray16(const char *path, const uint16_t *v, int w, int h, char *err, size_t errlen);
/* Reads any PNG libpng understands into RGBA8 (palette, gray, 16-bit are
 * converted).  0 or -1 with a clear message in err. */
int image_read_png(struct image *img, const char *path, char *err, size_t errlen);
/* A PNG's width and height from its header, nothing decoded (to refuse a
 * size before spending memory on it).  0 or -1 with err. */
int image_read_png_size(const char *path, int *w, int *h, char *err, size_t errlen);
/* Reads a PNG as 16-bit grayscale samples (for heightmaps): *out has w*h
 * values; 8-bit input is scaled to 16 bits.  0 or -1 with err. */
int image_read_png_gray16(const char *path, uint16_t **out, int *w, int *h, char *err, size_t errlen);

/* Image comparison for golden tests. */
struct image_diff {
	double mean_abs;      /* mean absolute channel difference, 0..255 (RGB) */
	double rmse;          /* root mean square channel difference */
	double frac_over;     /* fraction of pixels with any channel diff > threshold */
	double psnr;          /* dB, RGB */
	int max_abs;
};
int image_compare(const struct image *a, const struct image *b, int threshold, struct image_diff *d);

#endif
