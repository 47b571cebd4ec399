/* isoterra — an indexed triangle mesh in host memory (CPU reference output,
 * GPU read-back for tests and --export-mesh). */
#ifndef ISOTERRA_MESH_H
#define ISOTERRA_MESH_H

#include <stdint.h>
#include <stddef.h>

struct mesh {
	float *pos;      /* 3 floats per vertex, world space */
	float *nrm;      /* 3 floats per vertex, unit normal pointing into air */
	float *vis;      /* 2 floats per vertex, ambient and sun visibility 0 .. 1: a
	                  * GPU mesh's read-back has them, a CPU mesh NULL */
	uint32_t nverts;
	uint32_t *idx;   /* 3 indices per triangle, counter-clockwise seen from air */
	uint32_t ntris;
};

void mesh_free(struct mesh *m);
/* Allocates room for nv vertices and nt triangles; 0 or -1 (out of memory). */
int mesh_alloc(struct mesh *m, uint32_t nv, uint32_t nt);

#endif
