/* isoterra — YUV4MPEG2 (Y4M) stream writer: 4:2:0, full-range BT.601
 * ("C420jpeg"), for piping frames into ffmpeg. */
#ifndef ISOTERRA_Y4M_H
#define ISOTERRA_Y4M_H

#include <stdio.h>
#include "core.h"

struct y4m {
	FILE *f;               /* stdout, or af.f */
	int w, h;
	int fps_num, fps_den;  /* the header's exact frame rate */
	unsigned char *buf;
	struct atomic_file af; /* a file: written to a temp beside it */
};

/* path "-" = stdout (a stream, flushed each frame); a file is written to a
 * temp file beside it, renamed by y4m_commit.  Width and height must be
 * even.  0 or -1 with err. */
int y4m_open(struct y4m *y, const char *path, int w, int h, double fps, char *err, size_t errlen);
/* One frame: 0, or -1 with errno telling why. */
int y4m_write(struct y4m *y, const struct image *img);
/* The end of the stream: stdout flushed, a file closed and staged.  0 or -1 with err. */
int y4m_finish(struct y4m *y, const char *path, char *err, size_t errlen);
/* A staged file renamed onto path.  0 or -1 with err. */
int y4m_commit(struct y4m *y, const char *path, char *err, size_t errlen);
/* Frees; a temp file not committed is removed. */
void y4m_free(struct y4m *y);
/* The header's frame rate as an exact ratio: 29.97 -> 30000:1001, 0.2 ->
 * 1:5, 25 -> 25:1 (30:1 for a rate that is not positive). */
void y4m_rate(double fps, int *num, int *den);
/* RGB -> Y'CbCr 4:2:0 full range, the conversion y4m_write uses (tests). */
void y4m_convert(const struct image *img, unsigned char *yuv);

#endif
