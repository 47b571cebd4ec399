/* isoterra — YUV4MPEG2 (Y4M) stream writer: 4:2:0, full-range BT.601
 * ("C420jpeg"), for piping frames into ffmpeg. */
#ifndef ISOTERRA_Y4M_H
#define ISOTERRA_Y4M_H

#include <stdio.h>
#include "image.h"

struct y4m {
	FILE *f;
	int w, h, fps;
	unsigned char *buf;
	int own; /* close f at the end */
};

/* path "-" = stdout.  Width and height must be even.  0 or -1 with err. */
int y4m_open(struct y4m *y, const char *path, int w, int h, int fps, char *err, size_t errlen);
int y4m_write(struct y4m *y, const struct image *img);
int y4m_close(struct y4m *y);
/* RGB -> Y'CbCr 4:2:0 full range, the conversion y4m_write uses (tests). */
void y4m_convert(const struct image *img, unsigned char *yuv);

#endif
