/* isoterra — the engine's buffers: their capacities planned, made (the
 * Marching Cubes tables uploaded, a canary after each output), and read
 * back (densities, the status block's counters, the mesh, the canaries).
 * Read-back is for tests, export and end-of-run reports; never in the
 * frame loop. */
#include "extract_int.h"
#include "vertex.h"
#include "gpu.h"
#include "mc.h"
#include "core.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The Marching Cubes tables as a uniform block (common.glsl's McTables,
 * std140): per case two words of the pair of uvec4 entries, the case's 15
 * edge ids at 4 bits (15 = none) and its triangle count in the top 4 bits;
 * then the edge owners and corners as ivec4.  A uniform block, not a
 * storage block: 2368 bytes that every pass reads and none writes, and a
 * storage block fewer for the boards' 8 (docs/PLATFORMS.md). */
static void upload_tables(struct pipeline *pl)
{
	struct mc_tables t;
	mc_tables_build(&t);
	uint32_t buf[256 * MC_TABLE_CASE_WORDS + 12 * 4 + 8 * 4];
	uint32_t *w = buf;
	for (int i = 0; i < 256; i++) {
		uint64_t v = (uint64_t)t.tri_count[i] << 60;
		for (int j = 0; j < MC_MAX_TRIS * 3; j++)
			v |= (uint64_t)(t.tri[i][j] < 0 ? 15 : t.tri[i][j]) << (4 * j);
		*w++ = (uint32_t)v;
		*w++ = (uint32_t)(v >> 32);
	}
	for (int e = 0; e < 12; e++)
		for (int j = 0; j < 4; j++)
			*w++ = (uint32_t)(int32_t)t.edge_owner[e][j];
	for (int c = 0; c < 8; c++) {
		for (int j = 0; j < 3; j++)
			*w++ = (uint32_t)(int32_t)t.corner[c][j];
		*w++ = 0;
	}
	glGenBuffers(1, &pl->b_tables);
	glBindBuffer(GL_UNIFORM_BUFFER, pl->b_tables);
	glBufferData(GL_UNIFORM_BUFFER, sizeof(buf), buf, GL_STATIC_DRAW);
	glBindBuffer(GL_UNIFORM_BUFFER, 0);
}

static void write_guard(GLintptr at)
{
	uint32_t g[GUARD_BYTES / 4];
	for (size_t i = 0; i < GUARD_BYTES / 4; i++)
		g[i] = GUARD_WORD;
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, at, GUARD_BYTES, g);
}

int extract_vertex_room(struct pipeline *pl, uint64_t verts, char *err, size_t errlen)
{
	if (verts <= pl->verts_alloc)
		return 0;
	uint64_t bytes = verts * VERTEX_BYTES;
	if (bytes > (uint64_t)pl->max_ssbo || bytes > 0x7fffffffu) {
		snprintf(err, errlen, "vertex buffer of %llu MB exceeds the GL limit (%d MB); lower --grid",
			 (unsigned long long)(bytes >> 20), pl->max_ssbo >> 20);
		return -1;
	}
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_verts);
	glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(bytes + GUARD_BYTES), NULL, GL_DYNAMIC_DRAW);
	write_guard((GLintptr)bytes);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	if (glGetError() != GL_NO_ERROR) {
		snprintf(err, errlen, "cannot allocate %llu MB of vertex buffer", (unsigned long long)(bytes >> 20));
		return -1;
	}
	pl->verts_alloc = verts;
	return 0;
}

/* Output capacities: automatic = 16 triangles per cell of the largest
 * face, at least 64 Ki, never more than the field could ask for (5 per
 * cell, 3 vertices per owner cell) nor than the GL buffer limit. */
void extract_plan_capacities(struct pipeline *pl, const struct params *p)
{
	const struct grid *g = &pl->g;
	uint64_t ncells = (uint64_t)g->nx * g->ny * g->nz;
	uint64_t fx = (uint64_t)(g->ny + 1) * (g->nz + 1), fy = (uint64_t)(g->nx + 1) * (g->nz + 1),
		 fz = (uint64_t)(g->nx + 1) * (g->ny + 1);
	uint64_t face = fx > fy ? (fx > fz ? fx : fz) : (fy > fz ? fy : fz);
	uint64_t tcap = p->max_triangles ? (uint64_t)p->max_triangles : 16 * face;
	if (!p->max_triangles && tcap < 65536)
		tcap = 65536;
	if (tcap > 5 * ncells)
		tcap = 5 * ncells;
	uint64_t vcap = p->max_vertices ? (uint64_t)p->max_vertices : tcap;
	if (vcap > 3 * (uint64_t)pl->owners)
		vcap = 3 * (uint64_t)pl->owners;
	if (tcap * 12 > (uint64_t)pl->max_ssbo)
		tcap = (uint64_t)pl->max_ssbo / 12;
	if (vcap * VERTEX_BYTES > (uint64_t)pl->max_ssbo)
		vcap = (uint64_t)pl->max_ssbo / VERTEX_BYTES;
	pl->tri_cap = (uint32_t)(tcap ? tcap : 1);
	pl->vert_cap = (uint32_t)(vcap ? vcap : 1);
}

/* The sign buffer's words: a bit per density sample, every z slab padded
 * to a multiple of SIGN_SLAB_ALIGN bits (shaders/common.glsl, sign_slab_bits). */
uint32_t extract_sign_words(const struct grid *g)
{
	int m2 = 1 + 2 * grid_margin(g);
	uint64_t slab_bits = (uint64_t)div_up((uint64_t)(g->nx + m2) * (g->ny + m2), SIGN_SLAB_ALIGN) * SIGN_SLAB_ALIGN;
	return (uint32_t)(slab_bits / 32 * (uint64_t)(g->nz + m2));
}

/* What a run needs and its outputs do not: the densities, the sign bits
 * (raw and filtered, the cut and near bits), the HistoPyramid.  0, or -1
 * with err. */
int extract_field_buffers(struct pipeline *pl, char *err, size_t errlen)
{
	pl->b_dens = extract_buffer((GLsizeiptr)grid_dens_count(&pl->g) * 4, NULL, GL_DYNAMIC_COPY);
	pl->b_signs = extract_buffer((GLsizeiptr)pl->sign_words * 4, NULL, GL_DYNAMIC_COPY);
	pl->b_signs_raw = extract_buffer((GLsizeiptr)pl->sign_words * 4, NULL, GL_DYNAMIC_COPY);
	/* level 0, the pyramid and the prefix sums (extract_int.h, hp_levels) */
	pl->b_hp = extract_buffer((GLsizeiptr)pl->hp.nodes * 8, NULL, GL_DYNAMIC_COPY);
	/* the far samples' cut bits and the near bits, the refine list
	 * (pipeline.c refine_pass) */
	pl->b_cut = extract_buffer((GLsizeiptr)pl->sign_words * 8, NULL, GL_DYNAMIC_COPY);
	pl->b_refine = extract_buffer((GLsizeiptr)(RF_HEAD + (uint64_t)pl->refine_cap + pl->sign_words) * 4, NULL,
				      GL_DYNAMIC_COPY);
	/* the debris filter's candidate list (an entry for each sign word at
	 * most), then every word's candidate bits */
	pl->b_debris = extract_buffer((GLsizeiptr)(DL_HEAD + 3 * (uint64_t)pl->sign_words) * 4, NULL, GL_DYNAMIC_COPY);
	if (gpu_check("the field's buffers") < 0) {
		snprintf(err, errlen, "cannot allocate the pipeline's field buffers (grid %dx%dx%d)", pl->g.nx, pl->g.ny,
			 pl->g.nz);
		return -1;
	}
	return 0;
}

void pipeline_release_field(struct pipeline *pl)
{
	GLuint *bufs[] = { &pl->b_dens, &pl->b_signs, &pl->b_signs_raw, &pl->b_hp, &pl->b_cut, &pl->b_refine, &pl->b_debris };
	for (size_t i = 0; i < ARRAY_SIZE(bufs); i++) {
		glDeleteBuffers(1, bufs[i]); /* 0 is ignored */
		*bufs[i] = 0;
	}
}

int extract_create_buffers(struct pipeline *pl, char *err, size_t errlen)
{
	if (extract_field_buffers(pl, err, errlen) < 0)
		return -1;
	pl->b_idx = extract_buffer((GLsizeiptr)pl->tri_cap * 12 + GUARD_BYTES, NULL, GL_DYNAMIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_idx);
	write_guard((GLintptr)pl->tri_cap * 12);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	uint32_t zero[ST_WORDS] = { 0 };
	pl->b_status = extract_buffer(sizeof(zero), zero, GL_DYNAMIC_DRAW);
	glGenBuffers(1, &pl->b_verts);
	upload_tables(pl);
	if (gpu_check("pipeline buffers") < 0 || extract_vertex_room(pl, pl->vert_cap, err, errlen) < 0) {
		if (!err[0])
			snprintf(err, errlen, "cannot allocate the pipeline's GPU buffers (grid %d)", pl->g.nx);
		return -1;
	}
	return 0;
}

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

/* The counters of a status block from its word ST_TRIS_NEEDED on. */
static void stats_from(const uint32_t *s, struct extract_stats *st)
{
	memset(st, 0, sizeof(*st));
	st->triangles_needed = s[ST_TRIS_NEEDED - ST_TRIS_NEEDED];
	st->vertices_needed = s[ST_VERTS_NEEDED - ST_TRIS_NEEDED];
	st->triangles = s[ST_TRIS_WRITTEN - ST_TRIS_NEEDED];
	st->vertices = s[ST_VERTS_WRITTEN - ST_TRIS_NEEDED];
	st->triangle_capacity = s[ST_TRI_CAP - ST_TRIS_NEEDED];
	st->vertex_capacity = s[ST_VERT_CAP - ST_TRIS_NEEDED];
	st->overflow = s[ST_OVERFLOW - ST_TRIS_NEEDED] != 0;
}

#define WATCH_WORDS (ST_OVERFLOW - ST_TRIS_NEEDED + 1)

int pipeline_read_stats(struct pipeline *pl, struct extract_stats *st)
{
	uint32_t s[WATCH_WORDS];
	memset(st, 0, sizeof(*st));
	if (gpu_read_buffer(pl->b_status, ST_TRIS_NEEDED * 4, sizeof(s), s) < 0)
		return -1;
	stats_from(s, st);
	return 0;
}

int pipeline_watch_stats(struct pipeline *pl)
{
	if (!pl->b_watch)
		pl->b_watch = extract_buffer(WATCH_WORDS * 4, NULL, GL_STREAM_READ);
	glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
	glBindBuffer(GL_COPY_READ_BUFFER, pl->b_status);
	glBindBuffer(GL_COPY_WRITE_BUFFER, pl->b_watch);
	glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, ST_TRIS_NEEDED * 4, 0, WATCH_WORDS * 4);
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
	if (pl->watch_fence)
		glDeleteSync(pl->watch_fence);
	pl->watch_fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
	return gpu_check("the run's counts") < 0 || !pl->watch_fence ? -1 : 0;
}

int pipeline_watched_stats(struct pipeline *pl, bool wait, struct extract_stats *st)
{
	if (!pl->watch_fence)
		return 0;
	uint32_t s[WATCH_WORDS];
	int got = gpu_fence_read(&pl->watch_fence, pl->b_watch, sizeof(s), s, wait);
	if (got > 0)
		stats_from(s, st);
	return got;
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
	m->vis = malloc(sizeof(float) * 2 * (nv ? nv : 1));
	if (!vb || !m->vis) {
		free(vb);
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
		vertex_unpack(vb + 4 * (size_t)i, m->pos + 3 * (size_t)i, m->nrm + 3 * (size_t)i, m->vis + 2 * (size_t)i,
			      m->vis + 2 * (size_t)i + 1);
	free(vb);
	if (rc < 0)
		mesh_free(m);
	return rc;
}
