/* isoterra — PNG and PLY files: round trips, atomic writes, bad input. */
#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <png.h>

#include "edits.h"
#include "image.h"
#include "log.h"
#include "mesh.h"
#include "ply.h"
#include "tcheck.h"
#include "y4m.h"

static char dir[] = "/tmp/isoterra-test-io.XXXXXX";

static const char *tpath(const char *name)
{
	static char buf[16][512];
	static int k;
	k = (k + 1) % 16;
	snprintf(buf[k], sizeof(buf[k]), "%s/%s", dir, name);
	return buf[k];
}

static int count_entries(const char *d)
{
	DIR *dp = opendir(d);
	if (!dp)
		return -1;
	int n = 0;
	for (struct dirent *e; (e = readdir(dp)) != NULL;)
		n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
	closedir(dp);
	return n;
}

static long file_size(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

static int copy_prefix(const char *from, const char *to, long n)
{
	FILE *a = fopen(from, "rb"), *b = fopen(to, "wb");
	int rc = a && b ? 0 : -1;
	for (long i = 0; rc == 0 && i < n; i++) {
		int c = fgetc(a);
		if (c == EOF || fputc(c, b) == EOF)
			rc = -1;
	}
	if (a)
		fclose(a);
	if (b && fclose(b) != 0)
		rc = -1;
	return rc;
}

static void write_text(const char *path, const char *text, size_t len)
{
	FILE *f = fopen(path, "wb");
	CHECK(f && fwrite(text, 1, len, f) == len, "write %s", path);
	if (f)
		fclose(f);
}

/* A PNG written directly with libpng: gray or RGB at the given depth. */
static int write_raw_png(const char *path, int w, int h, int color_type, int depth, const uint8_t *data)
{
	FILE *f = fopen(path, "wb");
	if (!f)
		return -1;
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	if (!info || setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		fclose(f);
		return -1;
	}
	png_init_io(png, f);
	png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, depth, color_type, PNG_INTERLACE_NONE,
	             PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	png_write_info(png, info);
	int channels = color_type == PNG_COLOR_TYPE_RGB ? 3 : color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2 : 1;
	size_t stride = ((size_t)w * channels * depth + 7) / 8;
	for (int y = 0; y < h; y++)
		png_write_row(png, data + (size_t)y * stride);
	png_write_end(png, NULL);
	png_destroy_write_struct(&png, &info);
	return fclose(f) == 0 ? 0 : -1;
}

static int png_color_type_of(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return -1;
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	int ct = -1;
	if (info && !setjmp(png_jmpbuf(png))) {
		png_init_io(png, f);
		png_read_info(png, info);
		ct = png_get_color_type(png, info);
	}
	png_destroy_read_struct(&png, &info, NULL);
	fclose(f);
	return ct;
}

static void make_image(struct image *img, int w, int h, bool opaque)
{
	img->width = w;
	img->height = h;
	img->rgba = malloc((size_t)w * h * 4);
	uint32_t s = 12345;
	for (size_t i = 0; i < (size_t)w * h * 4; i++) {
		s = s * 1103515245u + 12345u;
		img->rgba[i] = (uint8_t)(s >> 16);
		if (opaque && i % 4 == 3)
			img->rgba[i] = 255;
	}
}

static void test_png_round_trip(void)
{
	char err[512];
	for (int opaque = 0; opaque < 2; opaque++) {
		struct image a, b;
		make_image(&a, 37, 23, opaque);
		const char *path = tpath(opaque ? "rgb.png" : "rgba.png");
		CHECK(image_write_png(&a, path, err, sizeof(err)) == 0, "write: %s", err);
		CHECK(png_color_type_of(path) == (opaque ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_RGB_ALPHA),
		      "color type %d", png_color_type_of(path));
		struct stat st;
		CHECK(stat(path, &st) == 0 && (st.st_mode & 0777) == (0666 & ~(mode_t)022) , "mode %o", st.st_mode & 0777);
		CHECK(image_read_png(&b, path, err, sizeof(err)) == 0, "read: %s", err);
		CHECK(b.width == 37 && b.height == 23 && b.rgba && !memcmp(a.rgba, b.rgba, 37 * 23 * 4),
		      "round trip (opaque %d) not byte-exact", opaque);
		image_free(&b);
		CHECK(b.rgba == NULL && b.width == 0, "image_free");
		image_free(&a);
	}
	/* overwrite an existing file */
	struct image a, b;
	make_image(&a, 16, 16, false);
	CHECK(image_write_png(&a, tpath("rgba.png"), err, sizeof(err)) == 0, "overwrite: %s", err);
	CHECK(image_read_png(&b, tpath("rgba.png"), err, sizeof(err)) == 0 && b.width == 16, "reread: %s", err);
	image_free(&b);
	CHECK(count_entries(dir) == 2, "stray files in %s: %d", dir, count_entries(dir));

	/* errors: no half-written files, no temp files left */
	char want[600];
	const char *nodir = tpath("no/such/dir/x.png");
	snprintf(want, sizeof(want), "cannot write '%s': No such file or directory", nodir);
	CHECK(image_write_png(&a, nodir, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	CHECK(access(nodir, F_OK) != 0, "file exists");
	CHECK(mkdir(tpath("isdir.png"), 0755) == 0, "mkdir");
	CHECK(image_write_png(&a, tpath("isdir.png"), err, sizeof(err)) == -1 && strstr(err, "cannot write '"),
	      "write over a directory: '%s'", err);
	CHECK(count_entries(dir) == 3, "temp file left behind: %d entries", count_entries(dir));
	rmdir(tpath("isdir.png"));
	struct image empty = { 0, 0, NULL };
	CHECK(image_write_png(&empty, tpath("e.png"), err, sizeof(err)) == -1 && strstr(err, "invalid image 0x0"),
	      "err '%s'", err);
	CHECK(access(tpath("e.png"), F_OK) != 0, "empty image written");
	image_free(&a);
}

static void test_png_bad_input(void)
{
	char err[512], want[600];
	struct image img;
	const char *trunc = tpath("trunc.png");
	long n = file_size(tpath("rgba.png"));
	CHECK(n > 100 && copy_prefix(tpath("rgba.png"), trunc, n / 2) == 0, "truncate");
	CHECK(image_read_png(&img, trunc, err, sizeof(err)) == -1 && strstr(err, "truncated") && strstr(err, trunc),
	      "err '%s'", err);
	CHECK(img.rgba == NULL, "image set on failure");
	CHECK(copy_prefix(tpath("rgba.png"), trunc, 20) == 0, "truncate header");
	CHECK(image_read_png(&img, trunc, err, sizeof(err)) == -1 && strstr(err, "truncated"), "err '%s'", err);

	const char *text = tpath("text.png");
	write_text(text, "hello, not a png\n", 17);
	snprintf(want, sizeof(want), "'%s' is not a PNG file", text);
	CHECK(image_read_png(&img, text, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	write_text(text, "", 0);
	CHECK(image_read_png(&img, text, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	uint16_t *hm;
	int w, h;
	CHECK(image_read_png_gray16(text, &hm, &w, &h, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	const char *missing = tpath("missing.png");
	snprintf(want, sizeof(want), "cannot open '%s': No such file or directory", missing);
	CHECK(image_read_png(&img, missing, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	CHECK(image_read_png(&img, dir, err, sizeof(err)) == -1 && strstr(err, dir), "directory: '%s'", err);

	/* corrupt data (flip a byte in the IDAT) -> CRC error, not a crash */
	const char *bad = tpath("crc.png");
	CHECK(copy_prefix(tpath("rgba.png"), bad, n) == 0, "copy");
	FILE *f = fopen(bad, "r+b");
	if (f) {
		fseek(f, n / 2, SEEK_SET);
		int c = fgetc(f);
		fseek(f, n / 2, SEEK_SET);
		fputc(c ^ 0x55, f);
		fclose(f);
	}
	CHECK(image_read_png(&img, bad, err, sizeof(err)) == -1 && strstr(err, "cannot read PNG"), "err '%s'", err);
}

static void test_gray16(void)
{
	char err[512];
	enum { W = 7, H = 5 };
	uint8_t raw[W * H * 2];
	uint16_t want[W * H];
	for (int i = 0; i < W * H; i++) {
		want[i] = (uint16_t)(i == 0 ? 0x1234 : i * 1871);
		raw[2 * i] = (uint8_t)(want[i] >> 8); /* PNG is big-endian */
		raw[2 * i + 1] = (uint8_t)want[i];
	}
	const char *p16 = tpath("h16.png");
	CHECK(write_raw_png(p16, W, H, PNG_COLOR_TYPE_GRAY, 16, raw) == 0, "write gray16");
	uint16_t *hm = NULL;
	int w = 0, h = 0;
	CHECK(image_read_png_gray16(p16, &hm, &w, &h, err, sizeof(err)) == 0, "read gray16: %s", err);
	CHECK(w == W && h == H && hm && !memcmp(hm, want, sizeof(want)), "gray16 values (hm[0] 0x%04x)", hm ? hm[0] : 0);
	free(hm);
	/* the RGBA reader takes the high byte */
	struct image img;
	CHECK(image_read_png(&img, p16, err, sizeof(err)) == 0, "rgba of gray16: %s", err);
	CHECK(img.rgba && img.rgba[0] == 0x12 && img.rgba[1] == 0x12 && img.rgba[2] == 0x12 && img.rgba[3] == 255,
	      "gray16 as rgba %02x %02x", img.rgba ? img.rgba[0] : 0, img.rgba ? img.rgba[3] : 0);
	image_free(&img);

	uint8_t g8[W * H];
	for (int i = 0; i < W * H; i++)
		g8[i] = (uint8_t)(i * 7);
	const char *p8 = tpath("h8.png");
	CHECK(write_raw_png(p8, W, H, PNG_COLOR_TYPE_GRAY, 8, g8) == 0, "write gray8");
	CHECK(image_read_png_gray16(p8, &hm, &w, &h, err, sizeof(err)) == 0, "read gray8: %s", err);
	bool ok = hm != NULL;
	for (int i = 0; ok && i < W * H; i++)
		ok = hm[i] == g8[i] * 257;
	CHECK(ok, "gray8 scaled to 16 bits");
	free(hm);

	uint8_t rgb[W * H * 3] = { 0 };
	const char *prgb = tpath("rgb8.png");
	CHECK(write_raw_png(prgb, W, H, PNG_COLOR_TYPE_RGB, 8, rgb) == 0, "write rgb");
	CHECK(image_read_png_gray16(prgb, &hm, &w, &h, err, sizeof(err)) == -1 &&
	      strstr(err, "color type is RGB; heightmaps must be 8- or 16-bit grayscale") && hm == NULL, "err '%s'", err);
	uint8_t g4[H * 4] = { 0 };
	const char *p4 = tpath("h4.png");
	CHECK(write_raw_png(p4, W, H, PNG_COLOR_TYPE_GRAY, 4, g4) == 0, "write gray4");
	CHECK(image_read_png_gray16(p4, &hm, &w, &h, err, sizeof(err)) == -1 &&
	      strstr(err, "bit depth is 4; heightmaps must be 8- or 16-bit grayscale"), "err '%s'", err);
	/* gray 4-bit through the RGBA reader: expanded and scaled */
	CHECK(image_read_png(&img, p4, err, sizeof(err)) == 0 && img.width == W && img.rgba[3] == 255, "gray4: %s", err);
	image_free(&img);
	const char *t16 = tpath("h16t.png");
	CHECK(copy_prefix(p16, t16, file_size(p16) - 20) == 0, "truncate gray16");
	CHECK(image_read_png_gray16(t16, &hm, &w, &h, err, sizeof(err)) == -1 && strstr(err, "truncated"),
	      "err '%s'", err);
}

static void make_mesh(struct mesh *m)
{
	CHECK(mesh_alloc(m, 5, 3) == 0, "mesh_alloc");
	for (uint32_t i = 0; i < 15; i++) {
		m->pos[i] = (float)i * 0.25f - 1.0f / 3.0f;
		m->nrm[i] = -(float)i / 7.0f;
	}
	const uint32_t idx[9] = { 0, 1, 2, 2, 1, 3, 4, 3, 1 };
	memcpy(m->idx, idx, sizeof(idx));
}

static void test_ply(void)
{
	char err[512], want[600];
	struct mesh a, b;
	make_mesh(&a);
	const char *path = tpath("m.ply");
	CHECK(ply_write(&a, path, err, sizeof(err)) == 0, "ply_write: %s", err);
	CHECK(ply_read(&b, path, err, sizeof(err)) == 0, "ply_read: %s", err);
	CHECK(b.nverts == 5 && b.ntris == 3 && !memcmp(a.pos, b.pos, 15 * sizeof(float)) &&
	      !memcmp(a.nrm, b.nrm, 15 * sizeof(float)) && !memcmp(a.idx, b.idx, 9 * sizeof(uint32_t)),
	      "PLY round trip");
	mesh_free(&b);

	/* the bytes: header, then little-endian floats */
	static char buf[4096];
	FILE *f = fopen(path, "rb");
	size_t n = f ? fread(buf, 1, sizeof(buf), f) : 0;
	if (f)
		fclose(f);
	const char *hdr_end = strstr(buf, "end_header\n");
	CHECK(!strncmp(buf, "ply\nformat binary_little_endian 1.0\n", 36) && hdr_end, "header");
	CHECK(strstr(buf, "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
	                  "property float nx\nproperty float ny\nproperty float nz\nelement face 3\n"
	                  "property list uchar uint vertex_indices\nend_header\n") != NULL, "header body");
	if (hdr_end) {
		size_t body = (size_t)(hdr_end + 11 - buf);
		CHECK(n == body + 5 * 24 + 3 * 13, "size %zu", n);
		uint32_t bits;
		memcpy(&bits, &a.pos[0], 4);
		const uint8_t *v = (const uint8_t *)buf + body;
		CHECK(v[0] == (bits & 0xff) && v[3] == bits >> 24, "vertex 0 x not little-endian");
		const uint8_t *fc = v + 5 * 24 + 13; /* second face: 3, 2, 1, 3 */
		CHECK(fc[0] == 3 && fc[1] == 2 && fc[2] == 0 && fc[5] == 1 && fc[9] == 3 && fc[12] == 0, "face bytes");

		/* corrupt copies */
		const char *bad = tpath("bad.ply");
		write_text(bad, buf, n - 1);
		CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && strstr(err, "truncated PLY body"), "err '%s'", err);
		CHECK(b.pos == NULL && b.nverts == 0, "mesh set on failure");
		write_text(bad, buf, n);
		f = fopen(bad, "ab");
		if (f) {
			fputc(0, f);
			fclose(f);
		}
		CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && strstr(err, "oversized PLY body"), "err '%s'", err);
		buf[body + 5 * 24 + 13] = 4; /* a quad */
		write_text(bad, buf, n);
		snprintf(want, sizeof(want), "'%s': face 1 has 4 vertices (only triangles supported)", bad);
		CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
		buf[body + 5 * 24 + 13] = 3;
		buf[body + 5 * 24 + 13 + 5] = 9; /* vertex 9 of 5 */
		write_text(bad, buf, n);
		snprintf(want, sizeof(want), "'%s': face 1 references vertex 9 of 5", bad);
		CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
		CHECK(b.pos == NULL, "mesh set on failure");
	}
	const char *bad = tpath("bad.ply");
	const char *ascii = "ply\nformat ascii 1.0\nelement vertex 0\nend_header\n";
	write_text(bad, ascii, strlen(ascii));
	snprintf(want, sizeof(want), "'%s': PLY format ascii 1.0 not supported (only binary_little_endian 1.0)", bad);
	CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	const char *dbl = "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty double x\nend_header\n";
	write_text(bad, dbl, strlen(dbl));
	CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && strstr(err, "unsupported PLY header line 'property double x'"),
	      "err '%s'", err);
	write_text(bad, "hello\n", 6);
	snprintf(want, sizeof(want), "'%s' is not a PLY file", bad);
	CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	write_text(bad, "ply\nformat binary_little_endian 1.0\n", 36);
	CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && strstr(err, "truncated or malformed PLY header"),
	      "err '%s'", err);
	const char *huge = "ply\nformat binary_little_endian 1.0\nelement vertex 99999999999\n";
	write_text(bad, huge, strlen(huge));
	CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && strstr(err, "unsupported PLY header line 'element vertex 9"),
	      "err '%s'", err);
	const char *big = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
	                  "property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
	                  "property float nz\nelement face 4000000000\nproperty list uchar uint vertex_indices\n"
	                  "end_header\n";
	write_text(bad, big, strlen(big));
	CHECK(ply_read(&b, bad, err, sizeof(err)) == -1 && strstr(err, "truncated PLY body"), "err '%s'", err);

	/* bad mesh: nothing written */
	a.idx[4] = 5;
	const char *p2 = tpath("bad_idx.ply");
	CHECK(ply_write(&a, p2, err, sizeof(err)) == -1 && strstr(err, "triangle 1 references vertex 5 of 5"),
	      "err '%s'", err);
	CHECK(access(p2, F_OK) != 0, "bad mesh written");
	a.idx[4] = 1;
	const char *nodir = tpath("nope/m.ply");
	snprintf(want, sizeof(want), "cannot write '%s': No such file or directory", nodir);
	CHECK(ply_write(&a, nodir, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
	mesh_free(&a);

	/* empty mesh, and a large one (several write chunks) */
	struct mesh e = { 0 };
	CHECK(ply_write(&e, tpath("e.ply"), err, sizeof(err)) == 0 && ply_read(&b, tpath("e.ply"), err, sizeof(err)) == 0 &&
	      b.nverts == 0 && b.ntris == 0, "empty mesh: %s", err);
	mesh_free(&b);
	CHECK(mesh_alloc(&a, 5000, 4000) == 0, "alloc");
	for (uint32_t i = 0; i < 15000; i++) {
		a.pos[i] = (float)i;
		a.nrm[i] = (float)-i;
	}
	for (uint32_t i = 0; i < 12000; i++)
		a.idx[i] = (i * 7919u) % 5000u;
	CHECK(ply_write(&a, tpath("big.ply"), err, sizeof(err)) == 0 && ply_read(&b, tpath("big.ply"), err, sizeof(err)) == 0,
	      "big: %s", err);
	CHECK(b.nverts == 5000 && b.ntris == 4000 && !memcmp(a.pos, b.pos, 15000 * 4) && !memcmp(a.nrm, b.nrm, 15000 * 4) &&
	      !memcmp(a.idx, b.idx, 12000 * 4), "big round trip");
	mesh_free(&a);
	mesh_free(&b);
}

static void test_compare(void)
{
	struct image a, b;
	struct image_diff d;
	make_image(&a, 10, 10, false);
	make_image(&b, 10, 10, false);
	CHECK(image_compare(&a, &b, 0, &d) == 0 && d.mean_abs == 0 && d.rmse == 0 && d.max_abs == 0 &&
	      d.frac_over == 0 && isinf(d.psnr), "identical");
	b.rgba[4 * 7 + 3] ^= 0xff; /* alpha is ignored */
	CHECK(image_compare(&a, &b, 0, &d) == 0 && d.max_abs == 0, "alpha ignored");
	/* pixel 3: +10 on red, pixel 4: -4 on blue */
	b.rgba[4 * 3 + 0] = a.rgba[4 * 3 + 0] < 128 ? a.rgba[4 * 3 + 0] + 10 : a.rgba[4 * 3 + 0] - 10;
	b.rgba[4 * 4 + 2] = a.rgba[4 * 4 + 2] < 128 ? a.rgba[4 * 4 + 2] + 4 : a.rgba[4 * 4 + 2] - 4;
	CHECK(image_compare(&a, &b, 5, &d) == 0, "compare");
	CHECK(d.max_abs == 10, "max %d", d.max_abs);
	CHECK_NEAR(d.mean_abs, 14.0 / 300.0, 1e-12, "mean_abs");
	CHECK_NEAR(d.rmse, sqrt(116.0 / 300.0), 1e-12, "rmse");
	CHECK_NEAR(d.frac_over, 0.01, 1e-12, "frac_over (threshold 5)");
	CHECK_NEAR(d.psnr, 20.0 * log10(255.0 / sqrt(116.0 / 300.0)), 1e-9, "psnr");
	CHECK(image_compare(&a, &b, 3, &d) == 0 && fabs(d.frac_over - 0.02) < 1e-12, "threshold 3: %g", d.frac_over);
	CHECK(image_compare(&a, &b, 10, &d) == 0 && d.frac_over == 0, "threshold 10: %g", d.frac_over);
	struct image c;
	make_image(&c, 10, 11, false);
	CHECK(image_compare(&a, &c, 0, &d) == -1, "size mismatch");
	image_free(&a);
	image_free(&b);
	image_free(&c);
}

/* Staged files: nothing at the target until commit; abort leaves nothing. */
static void test_staged(void)
{
	char err[512];
	struct image a = { 0 };
	make_image(&a, 8, 4, true);
	const char *t = tpath("staged.png");
	FILE *f = fopen(t, "w");
	fputs("previous", f);
	fclose(f);
	int before = count_entries(dir);
	struct atomic_file af;
	CHECK(image_write_png_staged(&a, t, &af, err, sizeof(err)) == 0, "staged: %s", err);
	struct image b = { 0 };
	CHECK(image_read_png(&b, t, err, sizeof(err)) == -1 && count_entries(dir) == before + 1,
	      "the target is untouched while staged");
	atomic_abort(&af);
	CHECK(count_entries(dir) == before, "abort removes the temp");
	CHECK(image_write_png_staged(&a, t, &af, err, sizeof(err)) == 0 && atomic_commit(&af, t, err, sizeof(err)) == 0 &&
	      image_read_png(&b, t, err, sizeof(err)) == 0 && b.width == 8 && count_entries(dir) == before,
	      "commit: %s", err);
	image_free(&b);
	image_free(&a);
}

/* Y4M headers carry the exact frame rate. */
static void test_y4m_rate(void)
{
	static const struct { float fps; int num, den; } cases[] = {
		{ 29.97f, 30000, 1001 }, { 23.976f, 24000, 1001 }, { 59.94f, 60000, 1001 }, { 0.2f, 1, 5 },
		{ 25.0f, 25, 1 },	 { 12.5f, 25, 2 },	   { 1000.0f, 1000, 1 },    { 0.1f, 1, 10 },
		{ 30.0f, 30, 1 },	 { 7.3f, 73, 10 },
	};
	for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		int num, den;
		y4m_rate(cases[i].fps, &num, &den);
		CHECK(num == cases[i].num && den == cases[i].den, "fps %g: %d:%d, want %d:%d", (double)cases[i].fps, num,
		      den, cases[i].num, cases[i].den);
	}
}

static void put_be32(unsigned char *p, uint32_t v)
{
	p[0] = (unsigned char)(v >> 24);
	p[1] = (unsigned char)(v >> 16);
	p[2] = (unsigned char)(v >> 8);
	p[3] = (unsigned char)v;
}

static uint32_t crc32_of(const unsigned char *p, size_t n)
{
	uint32_t c = 0xffffffffu;
	for (size_t i = 0; i < n; i++) {
		c ^= p[i];
		for (int k = 0; k < 8; k++)
			c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
	}
	return c ^ 0xffffffffu;
}

/* A heightmap too large is refused from its header: the file holds no
 * image data at all (an empty IDAT), so a reader that decodes first fails
 * otherwise. */
static void test_heightmap_header(void)
{
	unsigned char png[8 + 25 + 12 + 12] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
	unsigned char *ihdr = png + 8;
	put_be32(ihdr, 13);
	memcpy(ihdr + 4, "IHDR", 4);
	put_be32(ihdr + 8, 16385);
	put_be32(ihdr + 12, 16385);
	ihdr[16] = 8; /* 8-bit gray, deflate, adaptive filters, not interlaced */
	put_be32(ihdr + 21, crc32_of(ihdr + 4, 17));
	unsigned char *idat = ihdr + 25, *iend = idat + 12; /* an empty IDAT */
	memcpy(idat + 4, "IDAT", 4);
	put_be32(idat + 8, crc32_of(idat + 4, 4));
	memcpy(iend + 4, "IEND", 4);
	put_be32(iend + 8, crc32_of(iend + 4, 4));
	const char *t = tpath("huge.png");
	FILE *f = fopen(t, "wb");
	CHECK(f && fwrite(png, 1, sizeof(png), f) == sizeof(png) && fclose(f) == 0, "write huge.png");
	struct heightmap hm;
	memset(&hm, 0, sizeof(hm));
	char err[512], want[600];
	snprintf(want, sizeof(want), "heightmap '%s' is 16385x16385; 2x2 to 16384x16384 samples are supported", t);
	CHECK(heightmap_load(t, &hm, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
}

int main(void)
{
	if (!mkdtemp(dir)) {
		perror("mkdtemp");
		return 1;
	}
	umask(022);
	test_png_round_trip();
	test_png_bad_input();
	test_gray16();
	test_ply();
	test_compare();
	test_staged();
	test_y4m_rate();
	test_heightmap_header();
	char cmd[300];
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "cannot remove %s\n", dir);
	return tc_done("test_io");
}
