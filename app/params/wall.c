/* isoterra — the video wall's geometry from its parameters (wall.h). */
#include "params.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "A" or "A,B" (B = A when absent) of non-negative numbers. */
static int parse_pair(const char *s, float out[2])
{
	char *end;
	double a = strtod(s, &end);
	double b = a;
	if (end == s || !isfinite(a) || a < 0)
		return -1;
	if (*end == ',') {
		const char *t = end + 1;
		b = strtod(t, &end);
		if (end == t || !isfinite(b) || b < 0)
			return -1;
	}
	if (*end)
		return -1;
	out[0] = (float)a;
	out[1] = (float)b;
	return 0;
}

/* "NxM" / "N,M" of non-negative integers (sep the separator). */
static int parse_ints(const char *s, char sep, int *a, int *b)
{
	char *end;
	long x = strtol(s, &end, 10);
	if (end == s || *end != sep || x < 0 || x > 4096)
		return -1;
	const char *t = end + 1;
	long y = strtol(t, &end, 10);
	if (end == t || *end || y < 0 || y > 4096)
		return -1;
	*a = (int)x;
	*b = (int)y;
	return 0;
}

int wall_view(const struct params *p, int w, int h, int across, struct wall_view *v, char *err, size_t errlen)
{
	memset(v, 0, sizeof(*v));
	if (parse_ints(p->wall, 'x', &v->cols, &v->rows) < 0 || v->cols < 1 || v->rows < 1 || v->cols > 64 ||
	    v->rows > 64) {
		snprintf(err, errlen, "wall: '%s' is not COLSxROWS (1..64 each)", p->wall);
		return -1;
	}
	if (parse_ints(p->tile, ',', &v->col, &v->row) < 0) {
		snprintf(err, errlen, "tile: '%s' is not C,R", p->tile);
		return -1;
	}
	if (v->col >= v->cols || v->row >= v->rows) {
		snprintf(err, errlen, "tile: %d,%d is not on a %dx%d wall (0,0 .. %d,%d)", v->col, v->row, v->cols,
			 v->rows, v->cols - 1, v->rows - 1);
		return -1;
	}
	if (across < 1 || v->col + across > v->cols) {
		snprintf(err, errlen, "outputs: %d tile(s) along the row from tile %d,%d run past the %dx%d wall", across,
			 v->col, v->row, v->cols, v->rows);
		return -1;
	}
	if (parse_pair(p->bezel, v->bezel) < 0) {
		snprintf(err, errlen, "bezel: '%s' is not X or X,Y pixels (>= 0)", p->bezel);
		return -1;
	}
	if (p->bezel_mm[0]) {
		float mm[2];
		int pw, ph;
		if (parse_pair(p->bezel_mm, mm) < 0) {
			snprintf(err, errlen, "bezel_mm: '%s' is not X or X,Y millimetres (>= 0)", p->bezel_mm);
			return -1;
		}
		if (!p->panel_mm[0]) {
			snprintf(err, errlen, "bezel_mm: needs panel_mm, the panel's active area WxH in millimetres");
			return -1;
		}
		if (parse_ints(p->panel_mm, 'x', &pw, &ph) < 0 || pw < 1 || ph < 1) {
			snprintf(err, errlen, "panel_mm: '%s' is not WxH millimetres", p->panel_mm);
			return -1;
		}
		v->bezel[0] = mm[0] * (float)w / (float)pw;
		v->bezel[1] = mm[1] * (float)h / (float)ph;
	} else if (p->panel_mm[0]) {
		snprintf(err, errlen, "panel_mm: '%s' is only used with bezel_mm", p->panel_mm);
		return -1;
	}
	if (v->bezel[0] > 16.0f * (float)w || v->bezel[1] > 16.0f * (float)h) {
		snprintf(err, errlen, "bezel: %.0f,%.0f pixels is more than 16 tiles of %dx%d", (double)v->bezel[0],
			 (double)v->bezel[1], w, h);
		return -1;
	}
	v->across = across;
	v->on = v->cols * v->rows > 1;
	if (!v->on)
		v->bezel[0] = v->bezel[1] = 0.0f;
	float fw = (float)wall_frame_width(v, w);
	if (!v->on) {
		v->vw = fw;
		v->vh = (float)h;
		v->aspect = fw / (float)h;
		v->ndc[0] = v->ndc[1] = -1.0f;
		v->ndc[2] = v->ndc[3] = 1.0f;
		return 0;
	}
	v->vw = (float)(v->cols * w) + (float)(v->cols - 1) * v->bezel[0];
	v->vh = (float)(v->rows * h) + (float)(v->rows - 1) * v->bezel[1];
	v->aspect = v->vw / v->vh;
	float x0 = (float)v->col * ((float)w + v->bezel[0]);
	float y0 = (float)v->row * ((float)h + v->bezel[1]); /* from the top */
	v->ndc[0] = 2.0f * x0 / v->vw - 1.0f;
	v->ndc[2] = 2.0f * (x0 + fw) / v->vw - 1.0f;
	v->ndc[3] = 1.0f - 2.0f * y0 / v->vh;
	v->ndc[1] = 1.0f - 2.0f * (y0 + (float)h) / v->vh;
	return 0;
}

int wall_clock_realtime(const struct params *p, char *err, size_t errlen)
{
	if (!strcmp(p->clock, "realtime"))
		return 1;
	if (!strcmp(p->clock, "auto"))
		return 0;
	snprintf(err, errlen, "clock: '%s' is not auto or realtime", p->clock);
	return -1;
}

int wall_frame_width(const struct wall_view *v, int w)
{
	return v->across * w + (int)lroundf((float)(v->across - 1) * v->bezel[0]);
}
