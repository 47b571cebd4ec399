/* isoterra — host mesh storage. */
#include "mesh.h"

#include <stdlib.h>
#include <string.h>

void mesh_free(struct mesh *m)
{
	free(m->pos);
	free(m->nrm);
	free(m->vis);
	free(m->idx);
	memset(m, 0, sizeof(*m));
}

int mesh_alloc(struct mesh *m, uint32_t nv, uint32_t nt)
{
	memset(m, 0, sizeof(*m));
	m->pos = malloc(sizeof(float) * 3 * (nv ? nv : 1));
	m->nrm = malloc(sizeof(float) * 3 * (nv ? nv : 1));
	m->idx = malloc(sizeof(uint32_t) * 3 * (nt ? nt : 1));
	if (!m->pos || !m->nrm || !m->idx) {
		mesh_free(m);
		return -1;
	}
	m->nverts = nv;
	m->ntris = nt;
	return 0;
}
