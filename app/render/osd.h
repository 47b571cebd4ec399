/* isoterra — on-screen display: a parameter name and its value over the
 * picture (embedded bitmap font, app/font.c), drawn into any framebuffer. */
#ifndef ISOTERRA_OSD_H
#define ISOTERRA_OSD_H

#include <stddef.h>
#include <GLES3/gl31.h>

#define OSD_COLS 40

struct osd;
/* Needs a current GLES 3.1 context.  NULL with err. */
struct osd *osd_create(char *err, size_t errlen);
void osd_destroy(struct osd *o);
/* Draws two text rows (title, value; cut at OSD_COLS characters) and, when
 * bar >= 0, a bar at bar (0..1) into framebuffer fbo of w x h pixels,
 * top-left, scale framebuffer pixels per font pixel (0 = from h), faded by
 * alpha.  Leaves the framebuffer bound.  0 or -1. */
int osd_draw(struct osd *o, GLuint fbo, int w, int h, const char *title, const char *value, float bar, int scale,
	     float alpha);
/* The same in the top-right corner (the battery, app/power.h). */
int osd_draw_right(struct osd *o, GLuint fbo, int w, int h, const char *title, const char *value, float bar, int scale,
		   float alpha);
/* The font scale (framebuffer pixels per font pixel) for a box of `cols`
 * columns in a w x h frame: from the height (1 below 300 rows, 2, 3 from
 * 600, 4 from 1080), lowered until the box fits the width (small screens:
 * 320x240, 480x320), never below 1. */
int osd_fit_scale(int w, int h, int cols);

#endif
