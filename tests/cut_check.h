/* isoterra — the tests' view of the density pass's far-sample cut
 * (app/extract/field.h `cuts`, shaders/fractal.glsl): where it may happen,
 * how far a cut sample may be from the CPU's value, and the check of one
 * volume against the reference.  Header-only, shared by test_density and
 * test_pipeline. */
#ifndef ISOTERRA_CUT_CHECK_H
#define ISOTERRA_CUT_CHECK_H

#include "params.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>

/* May the density pass leave samples approximate for p?  The fractal sums
 * of bounded octaves on the terrain field (the curves, which also turn it
 * off, are the caller's to leave out). */
static inline bool cut_may(const struct params *p)
{
	bool sum = p->fractal == FRACTAL_FBM || p->fractal == FRACTAL_GEISS || p->fractal == FRACTAL_TURBULENCE;
	return p->density_cut && p->field == FIELD_TERRAIN && sum && p->octaves > 1 && p->noise_amp != 0.0f;
}

/* The most the octaves can add: 1.11 (a bound of improved Perlin noise,
 * and of the texture basis and turbulence's terms: shaders/fractal.glsl)
 * times the octaves' weights times noise_amp. */
static inline double cut_bound(const struct params *p)
{
	double w = 1.0, tail = 0.0;
	double step = p->fractal == FRACTAL_FBM ? pow(p->lacunarity, -p->hurst) : p->gain;
	for (int i = 0; i < p->octaves; i++, w *= step)
		tail += w;
	return 1.11 * tail * fabs(p->noise_amp);
}

/* How far into the rock ambient occlusion sees no difference any more. */
static inline double cut_rock(const struct params *p)
{
	double rock = 0.0;
	if (p->ao_short_k > 0)
		rock = fmax(rock, 1.0 / p->ao_short_k);
	if (p->ao_long_k > 0)
		rock = fmax(rock, 1.0 / p->ao_long_k);
	return rock;
}

struct cut_stats {
	double err_near;   /* max |gpu - cpu| within two steps of a sign change */
	double err_far;    /* max |gpu - cpu| elsewhere, over the samples not cut */
	size_t at_far;     /* where */
	size_t cut;        /* samples off by more than tol and within the cut's bound */
	size_t bad_sign, bad_rock, bad_near;
	size_t first_bad;  /* the first of those (n when none) */
};

/* GPU (gv) against CPU (cv) over nx * ny * nz samples, x fastest.  Where
 * the field may cut (cut_may), a sample may differ by more than tol only
 * (1) on the CPU's side of the iso level, (2) by at most cut_bound, (3) on
 * the rock side at least cut_rock above the iso level on both sides, and
 * (4) with no sign change within two six-neighbour steps (the vertices and
 * normals read those).  Others count in err_far.
 *
 * The sign change of (4) is the one the GPU sees: the refine pass lists
 * the cut samples near the GPU's own sign changes.  A neighbour within tol
 * of the iso level may lie on the other side on the GPU (within the
 * tolerance: texture noise on a driver that filters with 8-bit weights),
 * and then there is no sign change there for the vertex pass to read; so
 * a neighbour on the other side counts where its side is certain (more
 * than tol from the iso level) or the GPU puts it there too. */
static inline void cut_compare(const struct params *p, int nx, int ny, int nz, const float *gv, const float *cv,
			       double tol, struct cut_stats *st)
{
	size_t n = (size_t)nx * ny * nz;
	bool cuts = cut_may(p);
	double bound = cuts ? cut_bound(p) : 0.0, rock = cut_rock(p);
	*st = (struct cut_stats){ .first_bad = n };
	for (size_t i = 0; i < n; i++) {
		bool in = cv[i] > p->iso, near = false;
		int x = (int)(i % (size_t)nx), y = (int)(i / (size_t)nx % (size_t)ny), z = (int)(i / ((size_t)nx * ny));
		for (int dz = -2; dz <= 2 && !near; dz++)
			for (int dy = -2; dy <= 2 && !near; dy++)
				for (int dx = -2; dx <= 2 && !near; dx++) {
					int xx = x + dx, yy = y + dy, zz = z + dz;
					if (abs(dx) + abs(dy) + abs(dz) > 2 || xx < 0 || yy < 0 || zz < 0 || xx >= nx ||
					    yy >= ny || zz >= nz)
						continue;
					size_t k = ((size_t)zz * ny + yy) * nx + xx;
					bool other = (cv[k] > p->iso) != in;
					near = other && (fabs((double)cv[k] - p->iso) > tol || (gv[k] > p->iso) != in);
				}
		double e = fabs((double)gv[i] - (double)cv[i]);
		if (near && !(e <= st->err_near))
			st->err_near = e; /* a NaN counts, and stays */
		if (!(e > tol) || !cuts || !(e <= bound)) { /* exact, or not a cut (NaN included) */
			if (!isnan(st->err_far) && !(e <= st->err_far))
				st->err_far = e, st->at_far = i;
			continue;
		}
		st->cut++;
		bool bad = false;
		if ((gv[i] > p->iso) != in)
			st->bad_sign++, bad = true;
		if (in && !(cv[i] >= p->iso + rock - 1e-5 * fabs(rock) && gv[i] >= p->iso + rock))
			st->bad_rock++, bad = true;
		if (near)
			st->bad_near++, bad = true;
		if (bad && st->first_bad == n)
			st->first_bad = i;
	}
}

#endif
