/* isoterra — the uniform 2D spatial hash over the curves' quadratics
 * (thesis ch. 6): which quadratics can reach each cell.  See curves.h. */
#include "curves.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void curve_hash_padded_box(const struct curve_quads *q, int k, float box[4])
{
	float pad = q->prm[q->first[k]][0] + q->prm[q->first[k]][1];
	for (int i = 0; i < 2; i++) {
		float span = fmaxf(fabsf(q->box[k][i]), fabsf(q->box[k][i + 2]));
		float eps = 1e-5f * fmaxf(span, 1.0f) + 1e-4f * pad; /* rounding margin */
		box[i] = q->box[k][i] - pad - eps;
		box[i + 2] = q->box[k][i + 2] + pad + eps;
	}
}

void curve_hash_free(struct curve_hash *h)
{
	free(h->pivot);
	free(h->index);
	memset(h, 0, sizeof(*h));
}

static int cell_coord(float v, float origin, float cell, int dim)
{
	int c = (int)floorf((v - origin) / cell);
	return c < 0 ? 0 : (c >= dim ? dim - 1 : c);
}

int curve_hash_cell(const struct curve_hash *h, float x, float z)
{
	if (h->nall == 0)
		return -1;
	float lx = x - h->origin[0], lz = z - h->origin[1];
	if (!(lx >= 0.0f && lz >= 0.0f && lx < h->size[0] && lz < h->size[1]))
		return -1;
	int cx = (int)floorf(lx / h->cell[0]), cz = (int)floorf(lz / h->cell[1]);
	cx = cx >= h->dim ? h->dim - 1 : cx;
	cz = cz >= h->dim ? h->dim - 1 : cz;
	return cx + cz * h->dim;
}

/* The grid: the minimal rectangle around every padded box, dim x dim cells. */
static void hash_grid(const struct curve_quads *q, struct curve_hash *h)
{
	float lo[2] = { FLT_MAX, FLT_MAX }, hi[2] = { -FLT_MAX, -FLT_MAX };
	for (int k = 0; k < q->nquads; k++) {
		float b[4];
		curve_hash_padded_box(q, k, b);
		for (int i = 0; i < 2; i++) {
			lo[i] = fminf(lo[i], b[i]);
			hi[i] = fmaxf(hi[i], b[i + 2]);
		}
	}
	for (int i = 0; i < 2; i++) {
		h->origin[i] = lo[i];
		h->size[i] = fmaxf(hi[i] - lo[i], 1e-3f);
		h->cell[i] = h->size[i] / (float)h->dim;
	}
}

/* Cells x0..x1, z0..z1 of quadratic k's padded box. */
static void quad_cells(const struct curve_quads *q, const struct curve_hash *h, int k, int c[4])
{
	float b[4];
	curve_hash_padded_box(q, k, b);
	c[0] = cell_coord(b[0], h->origin[0], h->cell[0], h->dim);
	c[1] = cell_coord(b[2], h->origin[0], h->cell[0], h->dim);
	c[2] = cell_coord(b[1], h->origin[1], h->cell[1], h->dim);
	c[3] = cell_coord(b[3], h->origin[1], h->cell[1], h->dim);
}

/* The entries the cells will hold, from the boxes alone (one pass over the
 * quadratics, not over their cells). */
static long long hash_entries(const struct curve_quads *q, const struct curve_hash *h)
{
	long long total = 0;
	for (int k = 0; k < q->nquads; k++) {
		int c[4];
		quad_cells(q, h, k, c);
		total += (long long)(c[1] - c[0] + 1) * (c[3] - c[2] + 1);
	}
	return total;
}

/* Every quadratic into every cell its padded box overlaps: counts the
 * entries of each cell in pivot[2 c + 1] and, with fill, writes them to
 * index[] from each cell's start pivot[2 c]. */
static void hash_insert(const struct curve_quads *q, struct curve_hash *h, bool fill)
{
	int32_t *count = h->pivot; /* (start, count) pairs */
	int dim = h->dim;
	for (int k = 0; k < q->nquads; k++) {
		int b[4];
		quad_cells(q, h, k, b);
		for (int cz = b[2]; cz <= b[3]; cz++)
			for (int cx = b[0]; cx <= b[1]; cx++) {
				size_t c = (size_t)cx + (size_t)cz * (size_t)dim;
				if (fill)
					h->index[count[2 * c] + count[2 * c + 1]] = q->first[k];
				count[2 * c + 1]++;
			}
	}
}

/* Counts -> each cell's start (prefix sum), counts back to 0; the total. */
static long hash_starts(struct curve_hash *h, size_t ncell)
{
	int32_t *count = h->pivot;
	long start = 0;
	for (size_t c = 0; c < ncell; c++) {
		count[2 * c] = (int32_t)start;
		start += count[2 * c + 1];
		count[2 * c + 1] = 0;
	}
	return start;
}

static int build_dim(const struct curve_quads *q, int dim, struct curve_hash *h, char *err, size_t errlen)
{
	memset(h, 0, sizeof(*h));
	if (dim < 1)
		dim = 1;
	h->dim = dim;
	h->nall = q->nquads;
	size_t ncell = (size_t)dim * (size_t)dim;
	h->pivot = calloc(2 * ncell, sizeof(int32_t));
	if (!h->pivot)
		goto oom;
	if (q->nquads == 0) {
		h->index = calloc(1, sizeof(int32_t));
		if (!h->index)
			goto oom;
		h->size[0] = h->size[1] = 1.0f;
		h->cell[0] = h->cell[1] = 1.0f / (float)dim;
		return 0;
	}
	hash_grid(q, h);
	/* sized before anything is filled: the index holds every cell's entries
	 * and the list of all quadratics */
	long long want = hash_entries(q, h);
	if ((want + q->nquads) * 4 > CURVE_TABLE_MAX_BYTES) {
		snprintf(err, errlen, "curve hash too large: %lld entries for %d curve pieces over %dx%d cells (at most "
			 "%ld: %ld MB); lower curve_hash_dim or narrow the curves", want, q->nquads, dim, dim,
			 CURVE_TABLE_MAX_BYTES / 4 - q->nquads, CURVE_TABLE_MAX_BYTES >> 20);
		curve_hash_free(h);
		return -1;
	}
	/* two passes: count, then fill */
	hash_insert(q, h, false);
	long total = hash_starts(h, ncell);
	h->index = malloc(sizeof(int32_t) * (size_t)(total + q->nquads));
	if (!h->index)
		goto oom;
	hash_insert(q, h, true);
	h->nindex = (int)total;
	h->all_offset = (int)total;
	for (int k = 0; k < q->nquads; k++)
		h->index[total + k] = q->first[k];
	for (size_t c = 0; c < ncell; c++)
		if (h->pivot[2 * c + 1] > h->max_per_cell)
			h->max_per_cell = h->pivot[2 * c + 1];
	return 0;
oom:
	curve_hash_free(h);
	snprintf(err, errlen, "out of memory building the curve hash");
	return -1;
}

int curve_hash_build(const struct curve_quads *q, int dim, struct curve_hash *h, char *err, size_t errlen)
{
	if (dim != 0)
		return build_dim(q, dim, h, err, errlen);
	/* auto: about four pieces a cell were they spread evenly, 16 .. 256
	 * cells a side; then finer (up to 1024) while a cell lists more than
	 * CURVE_CELL_MAX (roads bunch up in towns) */
	dim = (int)lrint(sqrt((double)q->nquads / 4.0));
	dim = dim < 16 ? 16 : dim > 256 ? 256 : dim;
	if (build_dim(q, dim, h, err, errlen) < 0)
		return -1;
	/* finer while it helps: a point that wide curves all reach keeps them
	 * in its cell however fine the grid (and the entries grow) */
	while (h->max_per_cell > CURVE_CELL_MAX && dim < 1024) {
		struct curve_hash f;
		char ferr[8];
		dim = dim * 3 / 2 > 1024 ? 1024 : dim * 3 / 2;
		if (build_dim(q, dim, &f, ferr, sizeof(ferr)) < 0)
			break; /* too large: the coarser grid stays */
		if (f.max_per_cell > h->max_per_cell * 9 / 10) {
			curve_hash_free(&f);
			break;
		}
		curve_hash_free(h);
		*h = f;
	}
	return 0;
}
