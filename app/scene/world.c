/* isoterra — the streaming world (GPU Gems 3 ch.1 §2).
 *
 * Blocks are block_cells^3 cells; a level-L block covers block_size * 2^L
 * world units.  Every level is planned out to lod_distance of its own
 * blocks (the coarsest to view_distance) inside the frustum and the band of
 * heights where the surface can be.  Coarse blocks are generated with a
 * small density bias (eroded by lod_bias of their cells), so where a finer
 * block exists it lies outside the coarse surface and wins the depth test:
 * no cracks between levels, and the coarse level still fills the screen
 * while finer blocks stream in.  A finer block rises out of the rock over
 * fade_time after it is generated and sinks back over the last 20% of its
 * level's range (moved along its normals behind the coarser surface, no
 * dither), so levels change without popping and without dotted seams.
 *
 * Blocks are generated nearest first into a pool of block_pool slots (a
 * status/indirect block each; the meshes in an arena at their real sizes,
 * world_pool.c); when the pool is full the farthest block that is not
 * wanted, or is farther than the one asked for, gives its slot up.  Whether
 * a block turned out empty is learnt a few frames later through a fence and
 * a 16-byte copy of its status: empty blocks are remembered, get no slot
 * and are never generated again. */
#include "world_int.h"
#include "governor.h"
#include "extract.h"
#include "gpu.h"
#include "core.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Staging slot strides: whole vertices / indices, every offset a multiple
 * of GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT. */
void plan_strides(struct world *w)
{
	GLint align = 16;
	glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
	if (align < 16)
		align = 16;
	/* a canary after every staging slot (world_check_pool) */
	w->vstride = (GLintptr)w->vcap * VERTEX_BYTES + STAGE_GUARD;
	w->istride = (GLintptr)w->tcap * 12 + STAGE_GUARD;
	w->sstride = ST_BYTES;
	w->vstride = (w->vstride + align - 1) / align * align;
	w->istride = (w->istride + align - 1) / align * align;
	w->sstride = (w->sstride + align - 1) / align * align;
	/* vertex and element offsets must be whole vertices / indices */
	w->vstride = (w->vstride + VERTEX_BYTES - 1) / VERTEX_BYTES * VERTEX_BYTES;
	w->istride = (w->istride + 11) / 12 * 12;
	while (w->istride % align)
		w->istride += 12;
	while (w->vstride % align)
		w->vstride += VERTEX_BYTES;
}

/* The pipeline that extracts every block: one block's grid, the world's
 * terrain, its own buffers sized for one block (world_block_mesh). */
static int create_pipeline(struct world *w, const struct params *p, char *err, size_t errlen)
{
	struct grid g;
	memset(&g, 0, sizeof(g));
	g.nx = g.ny = g.nz = w->n;
	g.cell = p->block_size / (float)w->n;
	g.margin_extra = AO_MARGIN;
	struct params q = *p;
	q.closed = false;
	q.max_triangles = p->block_tris; /* its own buffers serve world_block_mesh */
	q.max_vertices = p->block_tris;
	w->terrain = terrain_create(w->ed);
	w->pl = pipeline_create(&g, &q, terrain_field(w->terrain), err, errlen);
	return w->pl ? 0 : -1;
}

struct world *world_create(const struct params *p, struct edits *ed, char *err, size_t errlen)
{
	struct world *w = calloc(1, sizeof(*w));
	if (!w) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	/* drawing the world churns the driver's memory: keep it in the heap
	 * from frame to frame (heap.c) */
	heap_policy();
	w->ed = ed;
	w->n = p->block_cells;
	w->slots = p->block_pool;
	w->tcap = (uint32_t)p->block_tris;
	w->vcap = w->tcap / 4 * 3; /* a surface has about half as many vertices as triangles */
	plan_strides(w);

	w->cap = 4096;
	w->blocks = malloc(sizeof(*w->blocks) * w->cap);
	w->slot_block = malloc(sizeof(int) * (size_t)w->slots);
	if (!w->blocks || !w->slot_block) {
		snprintf(err, errlen, "out of memory");
		world_destroy(w);
		return NULL;
	}
	for (uint32_t i = 0; i < w->cap; i++)
		w->blocks[i].key[3] = -1;
	for (int i = 0; i < w->slots; i++)
		w->slot_block[i] = -1;
	if (create_pipeline(w, p, err, errlen) < 0 || pool_create(w, err, errlen) < 0 || probes_create(w) < 0) {
		world_destroy(w);
		return NULL;
	}
	log_debug("world: %d slots; %d staging slots x (%u vertices, %u triangles) = %lld KB; block arena "
		  "in chunks of %lld KB, its meshes at most %lld MB",
		  w->slots, WORLD_STAGES, w->vcap, w->tcap, (long long)((w->vstride + w->istride) * WORLD_STAGES >> 10),
		  (long long)(w->chunk_bytes >> 10), (long long)(w->arena_max >> 20));
	return w;
}

void world_keep_terms(struct world *w, const struct params *configured)
{
	pipeline_keep_terms(w->pl, configured);
}

void world_destroy(struct world *w)
{
	if (!w)
		return;
	probes_destroy(w);
	log_debug("world: at most %llu triangles drawn in a frame; block arena %lld KB in %d chunks (%lld KB of "
		  "meshes; %llu chunks added, %llu packed); block table %u of %u entries (%zu bytes each), %llu forgotten",
		  (unsigned long long)w->st.drawn_tris_max, (long long)(w->arena_cap >> 10), w->nchunks,
		  (long long)(w->arena_used >> 10), (unsigned long long)w->st.arena_grown,
		  (unsigned long long)w->st.arena_packed, w->count, w->cap, sizeof(struct block),
		  (unsigned long long)w->st.forgotten);
	pipeline_destroy(w->pl);
	terrain_destroy(w->terrain);
	pool_destroy(w);
	for (int i = 0; i < FRAMES_IN_FLIGHT; i++)
		if (w->frame_fence[i])
			glDeleteSync(w->frame_fence[i]);
	for (int i = 0; i < READBACKS; i++) {
		if (w->rb[i].fence)
			glDeleteSync(w->rb[i].fence);
		if (w->rb[i].buf)
			glDeleteBuffers(1, &w->rb[i].buf);
	}
	free(w->blocks);
	free(w->slot_block);
	free(w->want);
	free(w->want_sort);
	free(w);
}

static uint32_t table_age;

void world_test_table_age(uint32_t frames)
{
	table_age = frames;
}

int world_update(struct world *w, const struct params *p, const struct camera *c, double now, bool deterministic)
{
	w->frame++;
	/* terrain edits (curves / heightmap files changed, or set through the
	 * API): only the blocks under the changed region are generated again */
	char err[512];
	if (edits_load(w->ed, p, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return -1;
	}
	float xz[4];
	if (edits_take_changes(w->ed, xz))
		world_invalidate(w, p, xz);
	collect_results(w, false);
	/* the table remembers every block ever wanted (empty ones so as not to
	 * generate them again): bounded by forgetting those long unwanted */
	if (prune_blocks(w, table_age ? table_age : BLOCK_MEMORY_FRAMES) < 0 || plan_blocks(w, p, c) < 0)
		return -1;
	/* the pre-pass and the generation, staged over frames (world_gen.c) */
	if (generate_wanted(w, p, now, deterministic) < 0)
		return -1;
	heap_reserve();
	return 0;
}

int world_fill(struct world *w, const struct params *p, const struct camera *c, double now)
{
	for (int guard = 0; guard < 100000; guard++) {
		uint64_t before = w->st.generated;
		if (world_update(w, p, c, now, true) < 0)
			return -1;
		if (w->st.generated == before)
			return 0;
	}
	return 0;
}

/* Waits until the frame FRAMES_IN_FLIGHT before this one is rasterized.
 * Nothing else bounds what the driver holds: llvmpipe bins a frame's
 * triangles on this thread and queues the scene for its rasterizer
 * threads, and without a page flip or a read-back to wait for, a thread
 * that bins faster than they rasterize queues up to 64 scenes (each up to
 * 36 MB) — the world's live growth (docs/RELIABILITY.md, "Memory"). */
static int frame_throttle(struct world *w)
{
	GLsync *f = &w->frame_fence[w->draws % FRAMES_IN_FLIGHT];
	if (!*f)
		return 0;
	GLenum st = glClientWaitSync(*f, GL_SYNC_FLUSH_COMMANDS_BIT, 10ull * 1000 * 1000 * 1000);
	glDeleteSync(*f);
	*f = 0;
	if (st != GL_ALREADY_SIGNALED && st != GL_CONDITION_SATISFIED) {
		log_error("world: the frame %d frames back did not finish in 10 s (wait status 0x%x)", FRAMES_IN_FLIGHT, st);
		return -1;
	}
	return 0;
}

int world_draw(struct world *w, struct renderer *r, const struct camera *c, const struct params *p, double now)
{
	if (frame_throttle(w) < 0)
		return -1;
	if (renderer_begin(r, c, p) < 0)
		return -1;
	int drawn = 0;
	uint64_t tris = 0;
	/* want[] is sorted nearest first: front to back */
	for (int i = 0; i < w->nwant; i++) {
		struct block *blk = &w->blocks[w->want[i]];
		if ((blk->state != B_READY && blk->state != B_PENDING) || blk->slot < 0 || !blk->visible)
			continue;
		float fade = 1.0f, sink = 0.0f;
		int lod = blk->key[3];
		if (lod < p->lod_levels - 1) {
			/* finer levels rise out of the rock after generation and
			 * sink back near the end of their range; the coarser level
			 * lies beneath (lod_bias of its cells inside), so a block
			 * sunk by more than that is hidden behind it */
			if (p->fade_time > 0)
				fade = fminf(1.0f, (float)(now - blk->born) / p->fade_time);
			float range = lod_range(p, lod);
			float edge = (range - blk->dist) / (0.2f * range);
			fade = fminf(fade, fmaxf(0.0f, fminf(1.0f, edge)));
			if (fade <= 0.0f)
				continue;
			float coarse_cell = block_world_size(p, lod + 1) / (float)w->n;
			sink = (1.0f - fade) * (p->lod_bias + 1.5f) * coarse_cell;
		}
		GLuint vbo, ibo;
		GLintptr voff, ioff;
		pool_mesh_at(w, blk->slot, &vbo, &voff, &ibo, &ioff);
		renderer_draw_mesh(r, vbo, ibo, w->status, w->sstride * blk->slot, sink, blk->dist);
		drawn++;
		tris += w->mem[blk->slot].stage >= 0 ? w->tcap : w->mem[blk->slot].tris;
	}
	w->st.drawn = drawn;
	w->st.drawn_tris = tris;
	if (tris > w->st.drawn_tris_max)
		w->st.drawn_tris_max = tris;
	float rect[4] = { c->eye[0] - p->view_distance, c->eye[2] - p->view_distance, c->eye[0] + p->view_distance,
			  c->eye[2] + p->view_distance };
	renderer_water(r, c, p, rect);
	renderer_lakes(r, c, p, rect);
	int rc = renderer_end(r);
	w->frame_fence[w->draws % FRAMES_IN_FLIGHT] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
	if (!w->frame_fence[w->draws % FRAMES_IN_FLIGHT])
		rc = gpu_check("frame fence") < 0 ? -1 : rc;
	w->draws++;
	return rc;
}

int world_invalidate(struct world *w, const struct params *p, const float xz[4])
{
	int marked = 0;
	w->gen_block = -1; /* a block under way may have read the field before the edit: drop it */
	for (uint32_t i = 0; i < w->cap; i++) {
		struct block *blk = &w->blocks[i];
		if (blk->key[3] < 0 || blk->state == B_FREE)
			continue;
		/* what the block's generation reads: its cells, the density margin
		 * (normals, short AO rays) and the long AO rays */
		float lo[3], hi[3];
		block_aabb(p, blk->key, lo, hi);
		float cell = block_world_size(p, blk->key[3]) / (float)w->n;
		float pad = (float)(1 + AO_MARGIN + 1) * cell;
		if (p->ao_rays > 0)
			pad += (float)p->ao_long_steps * p->ao_long_step;
		if (hi[0] + pad < xz[0] || lo[0] - pad > xz[2] || hi[2] + pad < xz[1] || lo[2] - pad > xz[3])
			continue;
		blk->probe = PROBE_UNKNOWN; /* the pre-pass's verdict too */
		if (blk->state == B_EMPTY) {
			blk->state = B_FREE; /* may not be empty any more */
		} else if (blk->slot >= 0) {
			blk->stale = true;
		} else {
			blk->state = B_FREE;
		}
		marked++;
	}
	w->st.invalidated += (uint64_t)marked;
	return marked;
}

void world_set_far_octaves_drop(struct world *w, int drop)
{
	w->far_drop = drop > 0 ? drop : 0;
}

int world_hold_quality(struct world *w, struct renderer *r, const struct governor_quality *q, const struct params *p,
		       struct params *eff, char *err, size_t errlen)
{
	governor_apply(q, p, eff);
	world_set_far_octaves_drop(w, q->far_octaves_drop);
	renderer_set_smoothing(r, q->smoothing > 0.5f);
	renderer_set_detail(r, governor_detail_scales(q));
	return renderer_set_scale(r, q->render_scale, err, errlen);
}

void world_get_stats(const struct world *w, struct world_stats *st)
{
	*st = w->st;
	st->ready = st->pending = st->empty_known = 0;
	for (uint32_t i = 0; i < w->cap; i++) {
		if (w->blocks[i].key[3] < 0)
			continue;
		st->ready += w->blocks[i].state == B_READY;
		st->pending += w->blocks[i].state == B_PENDING;
		st->empty_known += w->blocks[i].state == B_EMPTY;
	}
	st->wanted = w->nwant;
	st->blocks_known = w->count;
	st->table_cap = w->cap;
	st->arena_bytes = (long long)w->arena_cap;
	st->arena_chunk = (long long)w->chunk_bytes;
	st->arena_chunks = w->nchunks;
	st->compiles = pipeline_compiles(w->pl);
	st->arena_used = (long long)w->arena_used;
	st->arena_max = (long long)w->arena_max;
}

int world_block_mesh(struct world *w, const struct params *p, int lod, const int idx[3], struct mesh *m)
{
	struct grid g;
	int k[4] = { idx[0], idx[1], idx[2], lod };
	if (finish_staged(w, 0.0) < 0) /* a block under way uses the pipeline */
		return -1;
	block_grid(w, p, k, &g);
	pipeline_set_grid(w->pl, &g, 0.0f);
	pipeline_set_target(w->pl, NULL);
	w->cur_lod = lod;
	if (block_extract(w, p) < 0)
		return -1;
	return pipeline_read_mesh(w->pl, m);
}

/* ---- mesh export (--export-mesh) -------------------------------------------
 * Self-contained: reads the pool as world_draw sees it. */

/* Blocks with a mesh in the pool: generated (ready, or still pending its
 * empty check) and holding a slot. */
static bool export_block(const struct block *b)
{
	return b->key[3] >= 0 && (b->state == B_READY || b->state == B_PENDING) && b->slot >= 0;
}

/* The triangles and vertices block b wrote into its slot. */
static int export_counts(const struct world *w, const struct block *b, uint32_t *tris, uint32_t *verts)
{
	uint32_t v[2];
	if (gpu_read_buffer(w->status, w->sstride * b->slot + ST_TRIS_WRITTEN * 4, sizeof(v), v) < 0)
		return -1;
	_Static_assert(ST_VERTS_WRITTEN == ST_TRIS_WRITTEN + 1, "written counters are adjacent");
	*tris = v[0] < w->tcap ? v[0] : w->tcap;
	*verts = v[1] < w->vcap ? v[1] : w->vcap;
	return 0;
}

/* Block b's mesh appended to m at vertex nv, triangle nt. */
static int export_append(const struct world *w, const struct block *b, struct mesh *m, uint32_t nv, uint32_t nt,
			 uint32_t verts, uint32_t tris, uint32_t *vb)
{
	GLuint vbo, ibo;
	GLintptr voff, ioff;
	pool_mesh_at(w, b->slot, &vbo, &voff, &ibo, &ioff);
	if ((verts && gpu_read_buffer(vbo, voff, (GLsizeiptr)verts * VERTEX_BYTES, vb) < 0) ||
	    (tris && gpu_read_buffer(ibo, ioff, (GLsizeiptr)tris * 12, m->idx + 3 * (size_t)nt) < 0))
		return -1;
	for (uint32_t i = 0; i < verts; i++)
		vertex_unpack(vb + 4 * (size_t)i, m->pos + 3 * (size_t)(nv + i), m->nrm + 3 * (size_t)(nv + i), NULL, NULL);
	for (size_t k = 3 * (size_t)nt; k < 3 * (size_t)(nt + tris); k++) {
		if (m->idx[k] >= verts)
			return -1;
		m->idx[k] += nv; /* block-local -> the exported mesh's */
	}
	return 0;
}

int world_read_mesh(struct world *w, struct mesh *m)
{
	memset(m, 0, sizeof(*m));
	uint64_t nv = 0, nt = 0;
	uint32_t tris = 0, verts = 0;
	for (uint32_t i = 0; i < w->cap; i++) {
		if (!export_block(&w->blocks[i]))
			continue;
		if (export_counts(w, &w->blocks[i], &tris, &verts) < 0)
			return -1;
		nv += verts;
		nt += tris;
	}
	if (nv > UINT32_MAX || nt > UINT32_MAX / 3 || mesh_alloc(m, (uint32_t)nv, (uint32_t)nt) < 0)
		return -1;
	uint32_t *vb = malloc((size_t)VERTEX_BYTES * (w->vcap ? w->vcap : 1));
	int rc = vb ? 0 : -1;
	uint32_t at_v = 0, at_t = 0;
	for (uint32_t i = 0; i < w->cap && rc == 0; i++) {
		const struct block *b = &w->blocks[i];
		if (!export_block(b))
			continue;
		rc = export_counts(w, b, &tris, &verts);
		if (rc == 0 && (at_v + (uint64_t)verts > nv || at_t + (uint64_t)tris > nt))
			rc = -1; /* changed under us: cannot happen without a frame in between */
		if (rc == 0)
			rc = export_append(w, b, m, at_v, at_t, verts, tris, vb);
		at_v += verts;
		at_t += tris;
	}
	free(vb);
	if (rc < 0)
		mesh_free(m);
	return rc;
}
