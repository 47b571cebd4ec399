/* isoterra — the streaming world's block memory, sized to what the blocks
 * hold (docs/RELIABILITY.md, "Memory").
 *
 * A block is generated into a staging slot of worst-case capacity
 * (block_tris triangles, 3/4 as many vertices; WORLD_STAGES of them) and
 * drawn from there until its status read-back says how many triangles and
 * vertices it wrote.  Then exactly that much is taken from the arena (its
 * vertices, then its indices, 32-byte aligned, first fit), copied there on
 * the GPU, and the block's draw command is pointed at it; the staging slot
 * is free again.  The arena is a list of chunks, buffers of a fixed size
 * (a sixteenth of the worst case, at most 4 MB, at least two worst-case
 * blocks) that are never re-made: when no chunk has a gap for a block, the
 * chunk with the most free bytes is packed (one chunk copied, not the
 * arena) if that makes room, else a chunk is added.  So making room costs
 * at most one chunk's copy — no frame copies the whole arena — and a chunk
 * is added only when every chunk holds more than its size less a block:
 * the chunks never hold more than twice their meshes plus one chunk.  The
 * status blocks (draw commands, counters) stay one per slot. */
#include "world_int.h"
#include "gpu.h"
#include "core.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ARENA_ALIGN 32 /* a whole vertex: base_vertex = offset / VERTEX_BYTES */
#define CHUNK_MOST (4 << 20)

static GLintptr round_up(GLintptr v, GLintptr a)
{
	return (v + a - 1) / a * a;
}

/* The arena bytes of a block: its vertices, then its indices. */
static GLintptr block_bytes(uint32_t tris, uint32_t verts)
{
	return round_up((GLintptr)verts * VERTEX_BYTES + (GLintptr)tris * 12, ARENA_ALIGN);
}

static GLuint new_buffer(GLenum target, GLsizeiptr size, GLenum usage)
{
	GLuint b = 0;
	glGenBuffers(1, &b);
	glBindBuffer(target, b);
	glBufferData(target, size, NULL, usage);
	glBindBuffer(target, 0);
	return b;
}

static long long test_start;

void world_test_arena_start(long long bytes)
{
	test_start = bytes;
}

/* The canary after each staging slot's capacity in buf (stride apart). */
static void write_guards(GLuint buf, GLintptr stride, GLintptr used)
{
	uint32_t g[STAGE_GUARD / 4];
	for (size_t i = 0; i < STAGE_GUARD / 4; i++)
		g[i] = STAGE_GUARD_WORD;
	glBindBuffer(GL_COPY_WRITE_BUFFER, buf);
	for (int s = 0; s < WORLD_STAGES; s++)
		glBufferSubData(GL_COPY_WRITE_BUFFER, stride * s + used, STAGE_GUARD, g);
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

/* The staging buffers for the current strides, with their canaries. */
static void make_stages(struct world *w)
{
	w->vbo = new_buffer(GL_SHADER_STORAGE_BUFFER, w->vstride * WORLD_STAGES, GL_DYNAMIC_DRAW);
	w->ibo = new_buffer(GL_SHADER_STORAGE_BUFFER, w->istride * WORLD_STAGES, GL_DYNAMIC_DRAW);
	write_guards(w->vbo, w->vstride, (GLintptr)w->vcap * VERTEX_BYTES);
	write_guards(w->ibo, w->istride, (GLintptr)w->tcap * 12);
}

/* The size of a new chunk: chunk_bytes, at least two worst-case blocks
 * (so a chunk that cannot take a block is more than half full), and at
 * least need.  A test's small start is taken as it is (many chunks). */
static GLintptr chunk_size(const struct world *w, GLintptr need)
{
	GLintptr c = w->chunk_bytes;
	if (test_start <= 0 && c < 2 * block_bytes(w->tcap, w->vcap))
		c = 2 * block_bytes(w->tcap, w->vcap);
	if (c < need)
		c = need;
	return round_up(c, 1 << 16);
}

/* A new, empty chunk of at least need bytes: its index, or -1. */
static int add_chunk(struct world *w, GLintptr need)
{
	if (w->nchunks == w->chunks_cap) {
		int n = w->chunks_cap ? 2 * w->chunks_cap : 8;
		struct arena_chunk *c = realloc(w->chunks, sizeof(*c) * (size_t)n);
		if (!c)
			return -1;
		w->chunks = c;
		w->chunks_cap = n;
	}
	GLintptr cap = chunk_size(w, need);
	GLuint b = new_buffer(GL_ARRAY_BUFFER, cap, GL_DYNAMIC_DRAW);
	if (gpu_check("block arena chunk") < 0) {
		glDeleteBuffers(1, &b);
		return -1;
	}
	w->chunks[w->nchunks] = (struct arena_chunk){ .buf = b, .cap = cap };
	w->arena_cap += cap;
	log_debug("world: block arena chunk %d of %lld KB (%lld KB in all, %lld KB of meshes)", w->nchunks,
		  (long long)(cap >> 10), (long long)(w->arena_cap >> 10), (long long)(w->arena_used >> 10));
	return w->nchunks++;
}

int pool_create(struct world *w, char *err, size_t errlen)
{
	w->mem = calloc((size_t)w->slots, sizeof(*w->mem));
	w->ord = calloc((size_t)w->slots, sizeof(*w->ord));
	if (!w->mem || !w->ord) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (int i = 0; i < w->slots; i++)
		w->mem[i].stage = -1;
	for (int i = 0; i < WORLD_STAGES; i++)
		w->stage_slot[i] = -1;
	/* chunks of a sixteenth of the worst case (at most 4 MB); the first
	 * one now */
	w->arena_max = (GLintptr)w->slots * block_bytes(w->tcap, w->vcap);
	w->chunk_bytes = test_start > 0 ? (GLintptr)test_start : round_up(w->arena_max / 16, 1 << 16);
	if (w->chunk_bytes > CHUNK_MOST)
		w->chunk_bytes = CHUNK_MOST;
	make_stages(w);
	w->status = new_buffer(GL_SHADER_STORAGE_BUFFER, w->sstride * w->slots, GL_DYNAMIC_DRAW);
	if (add_chunk(w, 0) < 0) {
		snprintf(err, errlen, "cannot allocate the block arena's first %lld KB", (long long)(w->chunk_bytes >> 10));
		return -1;
	}
	for (int i = 0; i < READBACKS; i++) {
		w->rb[i].buf = new_buffer(GL_COPY_WRITE_BUFFER, RB_BYTES, GL_STREAM_READ);
		w->rb[i].block = -1;
	}
	if (gpu_check("block pool") < 0) {
		snprintf(err, errlen, "cannot allocate the block pool (%d staging slots of %u triangles: %lld MB); lower --block-tris",
			 WORLD_STAGES, w->tcap, (long long)((w->vstride + w->istride) * WORLD_STAGES >> 20));
		return -1;
	}
	return 0;
}

int pool_grow(struct world *w)
{
	if (w->grow_tris <= w->tcap)
		return 0;
	for (int i = 0; i < WORLD_STAGES; i++)
		if (w->stage_slot[i] >= 0)
			return 0; /* a block is staged: later */
	uint32_t t = w->grow_tris + w->grow_tris / 4;
	if (t > BLOCK_TRIS_MAX)
		t = BLOCK_TRIS_MAX;
	GLuint old[2] = { w->vbo, w->ibo };
	uint32_t old_t = w->tcap;
	w->tcap = t;
	w->vcap = t / 4 * 3;
	plan_strides(w);
	make_stages(w);
	glDeleteBuffers(2, old);
	/* the arena may now grow to block_pool blocks of the new worst case */
	w->arena_max = (GLintptr)w->slots * block_bytes(w->tcap, w->vcap);
	w->st.stages_grown++;
	log_info("world: a block needed %u triangles: its slots grow from %u to %u (the field is finer than "
		 "--block-tris)", w->grow_tris, old_t, w->tcap);
	w->grow_tris = 0;
	return gpu_check("block staging growth") < 0 ? -1 : 1;
}

void pool_destroy(struct world *w)
{
	GLuint bufs[] = { w->vbo, w->ibo, w->status };
	for (size_t i = 0; i < sizeof(bufs) / sizeof(bufs[0]); i++)
		if (bufs[i])
			glDeleteBuffers(1, &bufs[i]);
	for (int i = 0; i < w->nchunks; i++)
		glDeleteBuffers(1, &w->chunks[i].buf);
	free(w->chunks);
	free(w->ord);
	free(w->mem);
}

int pool_free_stage(const struct world *w)
{
	for (int i = 0; i < WORLD_STAGES; i++)
		if (w->stage_slot[i] < 0)
			return i;
	return -1;
}

void pool_release(struct world *w, int slot)
{
	struct slot_mem *m = &w->mem[slot];
	if (m->stage >= 0)
		w->stage_slot[m->stage] = -1;
	if (m->bytes) {
		w->chunks[m->chunk].used -= m->bytes;
		w->arena_used -= m->bytes;
	}
	memset(m, 0, sizeof(*m));
	m->stage = -1;
}

void pool_target(struct world *w, int slot, int stage, struct pipeline_target *t)
{
	pool_release(w, slot); /* a block generated again: its old mesh is not drawn any more */
	w->mem[slot].stage = stage;
	w->stage_slot[stage] = slot;
	*t = (struct pipeline_target){
		.vbo = w->vbo, .ibo = w->ibo, .status = w->status,
		.vbo_offset = w->vstride * stage, .ibo_offset = w->istride * stage, .status_offset = w->sstride * slot,
		.vert_cap = w->vcap, .tri_cap = w->tcap,
		.first_index = (uint32_t)(w->istride * stage / 4), .base_vertex = (uint32_t)(w->vstride * stage / VERTEX_BYTES),
	};
}

void pool_mesh_at(const struct world *w, int slot, GLuint *vbo, GLintptr *voff, GLuint *ibo, GLintptr *ioff)
{
	const struct slot_mem *m = &w->mem[slot];
	if (m->stage >= 0) {
		*vbo = w->vbo;
		*ibo = w->ibo;
		*voff = w->vstride * m->stage;
		*ioff = w->istride * m->stage;
	} else {
		*vbo = *ibo = w->chunks[m->chunk].buf;
		*voff = m->off;
		*ioff = m->off + (GLintptr)m->verts * VERTEX_BYTES;
	}
}

/* Points slot's draw command (first index, base vertex) at its arena range. */
static void point_draw(struct world *w, int slot)
{
	const struct slot_mem *m = &w->mem[slot];
	uint32_t v[2] = { (uint32_t)((m->off + (GLintptr)m->verts * VERTEX_BYTES) / 4),
			  (uint32_t)(m->off / VERTEX_BYTES) };
	glBindBuffer(GL_COPY_WRITE_BUFFER, w->status);
	glBufferSubData(GL_COPY_WRITE_BUFFER, w->sstride * slot + (ST_DRAW_ELEMENTS + 2) * 4, sizeof(v), v);
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
}

static int by_place(const void *a, const void *b)
{
	const struct slot_mem *x = a, *y = b;
	if (x->chunk != y->chunk)
		return (x->chunk > y->chunk) - (x->chunk < y->chunk);
	return (x->off > y->off) - (x->off < y->off);
}

/* The live arena ranges sorted by chunk, then offset, into ord (slot
 * numbers in `stage`); their count. */
static int live_ranges(const struct world *w, struct slot_mem *ord)
{
	int n = 0;
	for (int s = 0; s < w->slots; s++)
		if (w->mem[s].bytes) {
			ord[n] = w->mem[s];
			ord[n].stage = s; /* the slot, carried through the sort */
			n++;
		}
	qsort(ord, (size_t)n, sizeof(*ord), by_place);
	return n;
}

/* The first gap of at least need bytes in chunk c, whose ranges are the n
 * of ord (sorted by offset), or -1. */
static GLintptr first_fit(const struct world *w, int c, const struct slot_mem *ord, int n, GLintptr need)
{
	GLintptr at = 0;
	for (int i = 0; i < n; i++) {
		if (ord[i].off - at >= need)
			return at;
		at = ord[i].off + ord[i].bytes;
	}
	return w->chunks[c].cap - at >= need ? at : -1;
}

/* Chunk c re-made at its size with its n meshes (ord, by offset) packed at
 * its start, their draw commands following: the meshes moved. */
static int pack_chunk(struct world *w, int c, const struct slot_mem *ord, int n)
{
	struct arena_chunk *k = &w->chunks[c];
	GLuint next = new_buffer(GL_COPY_WRITE_BUFFER, k->cap, GL_DYNAMIC_DRAW);
	if (gpu_check("block arena chunk") < 0) {
		glDeleteBuffers(1, &next);
		return -1;
	}
	glBindBuffer(GL_COPY_READ_BUFFER, k->buf);
	glBindBuffer(GL_COPY_WRITE_BUFFER, next);
	GLintptr at = 0;
	int moved = 0;
	for (int i = 0; i < n; i++) {
		int s = ord[i].stage;
		glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, ord[i].off, at, ord[i].bytes);
		moved += ord[i].off != at;
		w->mem[s].off = at;
		at += ord[i].bytes;
	}
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
	for (int i = 0; i < n; i++)
		point_draw(w, ord[i].stage);
	glDeleteBuffers(1, &k->buf);
	k->buf = next;
	w->st.arena_packed++;
	log_debug("world: block arena chunk %d packed: %d meshes, %lld of %lld KB", c, n, (long long)(k->used >> 10),
		  (long long)(k->cap >> 10));
	return gpu_check("block arena pack") < 0 ? -1 : moved;
}

/* Where a mesh of need bytes goes: a gap in a chunk (first fit, chunk by
 * chunk); else the chunk with the most free bytes, packed, if they are
 * enough; else a new chunk.  0 with *chunk, *at; -1. */
static int place(struct world *w, GLintptr need, int *chunk, GLintptr *at)
{
	struct slot_mem *ord = w->ord;
	int n = live_ranges(w, ord), best = -1, best_i = 0, best_n = 0;
	GLintptr best_free = 0;
	for (int c = 0, i = 0; c < w->nchunks; c++) {
		int j = i;
		while (j < n && ord[j].chunk == c)
			j++;
		GLintptr free_bytes = w->chunks[c].cap - w->chunks[c].used;
		if (free_bytes >= need) {
			*at = first_fit(w, c, ord + i, j - i, need);
			if (*at >= 0) {
				*chunk = c;
				return 0;
			}
			if (free_bytes > best_free) {
				best = c;
				best_free = free_bytes;
				best_i = i;
				best_n = j - i;
			}
		}
		i = j;
	}
	if (best >= 0) { /* packed, its free bytes are one gap at its end */
		*chunk = best;
		*at = w->chunks[best].used;
		return pack_chunk(w, best, ord + best_i, best_n) < 0 ? -1 : 0;
	}
	*chunk = add_chunk(w, need);
	*at = 0;
	if (*chunk < 0)
		return -1;
	w->st.arena_grown++;
	return 0;
}

int pool_settle(struct world *w, int slot, uint32_t tris, uint32_t verts)
{
	struct slot_mem *m = &w->mem[slot];
	if (m->stage < 0)
		return 0; /* not staged (evicted or generated again meanwhile) */
	tris = tris < w->tcap ? tris : w->tcap;
	verts = verts < w->vcap ? verts : w->vcap;
	GLintptr need = block_bytes(tris, verts), at = 0;
	int c = -1;
	if (place(w, need, &c, &at) < 0)
		return -1;
	int stage = m->stage;
	glBindBuffer(GL_COPY_WRITE_BUFFER, w->chunks[c].buf);
	glBindBuffer(GL_COPY_READ_BUFFER, w->vbo);
	if (verts)
		glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, w->vstride * stage, at, (GLsizeiptr)verts * VERTEX_BYTES);
	glBindBuffer(GL_COPY_READ_BUFFER, w->ibo);
	if (tris)
		glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, w->istride * stage,
				    at + (GLintptr)verts * VERTEX_BYTES, (GLsizeiptr)tris * 12);
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
	w->stage_slot[stage] = -1;
	m->stage = -1;
	m->chunk = c;
	m->off = at;
	m->bytes = need;
	m->tris = tris;
	m->verts = verts;
	w->chunks[c].used += need;
	w->arena_used += need;
	point_draw(w, slot);
	return gpu_check("block settle");
}

/* Faults of the staging canaries in buf. */
static int check_guards(GLuint buf, GLintptr stride, GLintptr used, const char *what)
{
	int bad = 0;
	for (int s = 0; s < WORLD_STAGES; s++) {
		uint32_t g[STAGE_GUARD / 4];
		if (gpu_read_buffer(buf, stride * s + used, STAGE_GUARD, g) < 0)
			return -1;
		for (size_t i = 0; i < STAGE_GUARD / 4; i++)
			if (g[i] != STAGE_GUARD_WORD) {
				log_error("world: staging slot %d: the %s canary overwritten", s, what);
				bad++;
				break;
			}
	}
	return bad;
}

int world_check_pool(struct world *w)
{
	int gv = check_guards(w->vbo, w->vstride, (GLintptr)w->vcap * VERTEX_BYTES, "vertex");
	int gi = check_guards(w->ibo, w->istride, (GLintptr)w->tcap * 12, "index");
	if (gv < 0 || gi < 0)
		return -1;
	int bad = gv + gi;
	struct slot_mem *ord = w->ord;
	int n = live_ranges(w, ord);
	GLintptr sum = 0, end = 0, caps = 0;
	for (int c = 0, i = 0; c < w->nchunks; c++) {
		GLintptr in_chunk = 0;
		end = 0;
		for (; i < n && ord[i].chunk == c; i++) {
			const struct slot_mem *m = &ord[i];
			if (m->off < end || m->off + m->bytes > w->chunks[c].cap || m->bytes < block_bytes(m->tris, m->verts) ||
			    m->off % ARENA_ALIGN || m->tris > w->tcap || m->verts > w->vcap) {
				log_error("world: slot %d: chunk %d bytes %lld..%lld (%u triangles, %u vertices) overlap another "
					  "or lie outside the chunk's %lld", m->stage, c, (long long)m->off,
					  (long long)(m->off + m->bytes), m->tris, m->verts, (long long)w->chunks[c].cap);
				bad++;
			}
			end = m->off + m->bytes;
			in_chunk += m->bytes;
		}
		if (in_chunk != w->chunks[c].used) {
			log_error("world: chunk %d: %lld bytes in use, its meshes hold %lld", c, (long long)w->chunks[c].used,
				  (long long)in_chunk);
			bad++;
		}
		sum += in_chunk;
		caps += w->chunks[c].cap;
	}
	for (int i = 0; i < n; i++)
		if (ord[i].chunk < 0 || ord[i].chunk >= w->nchunks) {
			log_error("world: slot %d: in chunk %d of %d", ord[i].stage, ord[i].chunk, w->nchunks);
			bad++;
		}
	if (sum != w->arena_used || caps != w->arena_cap) {
		log_error("world: arena bytes in use %lld of %lld, the meshes hold %lld, the chunks %lld",
			  (long long)w->arena_used, (long long)w->arena_cap, (long long)sum, (long long)caps);
		bad++;
	}
	return bad;
}

int world_test_compact(struct world *w)
{
	struct slot_mem *ord = w->ord;
	int n = live_ranges(w, ord), moved = 0;
	for (int c = 0, i = 0; c < w->nchunks && moved >= 0; c++) {
		int j = i;
		while (j < n && ord[j].chunk == c)
			j++;
		int r = pack_chunk(w, c, ord + i, j - i);
		moved = r < 0 ? -1 : moved + r;
		i = j;
	}
	return moved;
}
