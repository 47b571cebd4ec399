/* isoterra — the video wall's geometry (docs/WALL.md): which part of one
 * virtual screen a process's frame shows.
 *
 * The virtual screen is COLS x ROWS tiles of the frame's size with the
 * bezel gap between neighbours: COLS*w + (COLS-1)*bx by ROWS*h +
 * (ROWS-1)*by pixels.  The camera is the whole screen's (its aspect, its
 * vertical field of view) and a frame shows a rectangle of it: an
 * off-axis frustum, so tiles meet without seams or parallax, and the
 * pixels behind the bezels are never drawn. */
#ifndef ISOTERRA_WALL_H
#define ISOTERRA_WALL_H

#include <stdbool.h>
#include <stddef.h>

struct params;

struct wall_view {
	bool on;       /* false: the frame is the whole screen (no wall) */
	int cols, rows, col, row; /* the wall and the frame's first tile */
	int across;    /* tiles the frame spans along the row (outputs of one board) */
	float bezel[2];/* hidden pixels between tiles, x and y */
	float vw, vh;  /* the virtual screen, pixels */
	float aspect;  /* vw / vh: the camera's */
	/* the frame's rectangle in the virtual screen's normalised device
	 * coordinates (x0, y0, x1, y1; y up, -1..1) */
	float ndc[4];
};

/* The view of the tile size w x h (the frame is `across` tiles along the
 * row from --tile, with the bezels between them: across*w + (across-1)*bx
 * wide).  Without a wall (1x1) v->on is false and the aspect the frame's.
 * 0, or -1 with err naming the parameter (--wall, --tile, --bezel, ...). */
int wall_view(const struct params *p, int w, int h, int across, struct wall_view *v, char *err, size_t errlen);
/* --clock realtime (else auto): 1, 0, or -1 with err for another word. */
int wall_clock_realtime(const struct params *p, char *err, size_t errlen);
/* The frame's size for `across` tiles of w x h (w for one). */
int wall_frame_width(const struct wall_view *v, int w);

#endif
