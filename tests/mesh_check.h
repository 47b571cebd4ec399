/* isoterra tests — mesh topology checks (independent of the extractor). */
#ifndef ISOTERRA_MESH_CHECK_H
#define ISOTERRA_MESH_CHECK_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "mesh.h"

static int mc_cmp_u64(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return x < y ? -1 : x > y;
}

struct topo {
	uint64_t edges;        /* directed edges */
	uint64_t duplicated;   /* directed edge used twice (inconsistent winding or non-manifold) */
	uint64_t unmatched;    /* directed edge whose reverse is missing (hole or border) */
	uint64_t bad_index;    /* index >= nverts */
	uint64_t degenerate;   /* triangle with a repeated index */
};

/* Every interior edge must be shared by exactly two triangles with opposite
 * directions.  is_border(a, b) lets the caller excuse edges on the volume
 * border (NULL: none excused). */
static inline void mesh_topology(const struct mesh *m, int (*is_border)(const struct mesh *, uint32_t, uint32_t, void *),
				 void *ctx, struct topo *t)
{
	memset(t, 0, sizeof(*t));
	uint64_t n = (uint64_t)m->ntris * 3;
	uint64_t *e = malloc(sizeof(uint64_t) * (n ? n : 1));
	if (!e) {
		t->unmatched = UINT64_MAX;
		return;
	}
	uint64_t k = 0;
	for (uint32_t i = 0; i < m->ntris; i++) {
		const uint32_t *v = m->idx + 3 * (size_t)i;
		if (v[0] >= m->nverts || v[1] >= m->nverts || v[2] >= m->nverts) {
			t->bad_index++;
			continue;
		}
		if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
			t->degenerate++;
		for (int j = 0; j < 3; j++)
			e[k++] = ((uint64_t)v[j] << 32) | v[(j + 1) % 3];
	}
	qsort(e, k, sizeof(uint64_t), mc_cmp_u64);
	t->edges = k;
	for (uint64_t i = 0; i < k; i++) {
		if (i + 1 < k && e[i] == e[i + 1])
			t->duplicated++;
		uint64_t rev = (e[i] << 32) | (e[i] >> 32);
		if (!bsearch(&rev, e, k, sizeof(uint64_t), mc_cmp_u64)) {
			uint32_t a = (uint32_t)(e[i] >> 32), b = (uint32_t)e[i];
			if (!is_border || !is_border(m, a, b, ctx))
				t->unmatched++;
		}
	}
	free(e);
}

#endif
