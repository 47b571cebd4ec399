/* isoterra — the engine's storage buffers: made, and read back (densities,
 * the status block's counters, the mesh, the canaries after the output
 * buffers).  Read-back is for tests, export and end-of-run reports; never in
 * the frame loop. */
#include "extract_int.h"
#include "vertex.h"
#include "gpu.h"
#include "abi.h"

#include <stdlib.h>
#include <string.h>

GLuint extract_buffer(GLsizeiptr size, const void *data, GLenum usage)
{
	GLuint b = 0;
	glGenBuffers(1, &b);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
	glBufferData(GL_SHADER_STORAGE_BUFFER, size > 0 ? size : 4, data, usage);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	return b;
}

int pipeline_read_density(struct pipeline *pl, float *out)
{
	if (!pl->b_dens)
		return -1; /* released (pipeline_release_field) */
	return gpu_read_buffer(pl->b_dens, 0, (GLsizeiptr)grid_dens_count(&pl->g) * 4, out);
}

int pipeline_check_guards(struct pipeline *pl)
{
	uint32_t g[GUARD_BYTES / 4];
	int bad = 0;
	if (gpu_read_buffer(pl->b_idx, (GLintptr)pl->tri_cap * 12, GUARD_BYTES, g) < 0)
		return -1;
	for (size_t i = 0; i < GUARD_BYTES / 4; i++)
		bad += g[i] != GUARD_WORD;
	if (gpu_read_buffer(pl->b_verts, (GLintptr)(pl->verts_alloc * VERTEX_BYTES), GUARD_BYTES, g) < 0)
		return -1;
	for (size_t i = 0; i < GUARD_BYTES / 4; i++)
		bad += g[i] != GUARD_WORD;
	return bad ? 1 : 0;
}

int pipeline_read_stats(struct pipeline *pl, struct extract_stats *st)
{
	uint32_t s[ST_WORDS];
	memset(st, 0, sizeof(*st));
	if (gpu_read_buffer(pl->b_status, 0, sizeof(s), s) < 0)
		return -1;
	st->triangles_needed = s[ST_TRIS_NEEDED];
	st->vertices_needed = s[ST_VERTS_NEEDED];
	st->triangles = s[ST_TRIS_WRITTEN];
	st->vertices = s[ST_VERTS_WRITTEN];
	st->triangle_capacity = s[ST_TRI_CAP];
	st->vertex_capacity = s[ST_VERT_CAP];
	st->overflow = s[ST_OVERFLOW] != 0;
	return 0;
}

int pipeline_read_mesh(struct pipeline *pl, struct mesh *m)
{
	struct extract_stats st;
	memset(m, 0, sizeof(*m));
	if (pipeline_read_stats(pl, &st) < 0)
		return -1;
	bool indexed = pl->last_mode == COMPACTION_HP;
	uint32_t nv = indexed ? st.vertices : 3 * st.triangles;
	uint32_t nt = st.triangles;
	if (mesh_alloc(m, nv, nt) < 0)
		return -1;
	uint32_t *vb = malloc((size_t)VERTEX_BYTES * (nv ? nv : 1));
	if (!vb) {
		mesh_free(m);
		return -1;
	}
	int rc = gpu_read_buffer(pl->b_verts, 0, (GLsizeiptr)nv * VERTEX_BYTES, vb);
	if (rc == 0 && indexed)
		rc = gpu_read_buffer(pl->b_idx, 0, (GLsizeiptr)nt * 12, m->idx);
	else if (rc == 0)
		for (uint32_t i = 0; i < 3 * nt; i++)
			m->idx[i] = i;
	for (uint32_t i = 0; rc == 0 && i < nv; i++)
		vertex_unpack(vb + 4 * (size_t)i, m->pos + 3 * (size_t)i, m->nrm + 3 * (size_t)i, NULL);
	free(vb);
	if (rc < 0)
		mesh_free(m);
	return rc;
}
