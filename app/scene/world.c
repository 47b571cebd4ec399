/* isoterra — the streaming world (GPU Gems 3 ch.1 §2).
 *
 * Blocks are block_cells^3 cells; a level-L block covers block_size * 2^L
 * world units.  Every level is planned out to lod_distance of its own
 * blocks (the coarsest to view_distance) inside the frustum and the band of
 * heights where the surface can be.  Coarse blocks are generated with a
 * small density bias (eroded by lod_bias of their cells), so where a finer
 * block exists it lies outside the coarse surface and wins the depth test:
 * no cracks between levels, and the coarse level still fills the screen
 * while finer blocks stream in.  A finer block dissolves in over fade_time
 * after it is generated and dissolves out over the last 20% of its level's
 * range (ordered dither), so levels change without popping.
 *
 * Blocks are generated nearest first into a fixed pool of slots (one vertex
 * buffer, one element buffer and one status/indirect buffer, each cut into
 * block_pool slots); when the pool is full the farthest block that is not
 * wanted, or is farther than the one asked for, gives its slot up.  Whether
 * a block turned out empty is learnt a few frames later through a fence and
 * a 16-byte copy of its status: empty blocks are remembered, get no slot
 * and are never generated again. */
#include "world.h"
#include "edits.h"
#include "gpu.h"
#include "abi.h"
#include "clock.h"
#include "log.h"
#include "pipeline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum bstate { B_FREE = 0, B_PENDING, B_READY, B_EMPTY };

struct block {
	int key[4];          /* x, y, z, lod */
	enum bstate state;
	int slot;
	double born;         /* time it became drawable (fade in) */
	float dist;          /* distance to the camera this frame */
	uint32_t frame;      /* last frame it was wanted */
	bool visible;        /* in the view frustum (else only prefetched) */
	int readback;        /* index in the readback ring, or -1 */
	bool stale;          /* terrain edited under it: regenerate in place */
	int generations;     /* times generated (tests) */
};

struct readback {
	GLuint buf;
	GLsync fence;
	int block;           /* block index, -1 = free */
};

#define READBACKS 64
/* a generated block's counters, copied out of its status block for the
 * fence-guarded read-back: triangles/vertices needed ... overflow flag */
#define RB_FIRST ST_TRIS_NEEDED
#define RB_WORDS (ST_OVERFLOW - ST_TRIS_NEEDED + 1)
#define RB_BYTES (RB_WORDS * 4)
#define AO_MARGIN 6      /* extra density samples around a block: short AO rays */

struct world {
	struct pipeline *pl;
	int n;               /* cells per block edge */
	GLuint vbo, ibo, status;
	GLintptr vstride, istride, sstride;
	uint32_t vcap, tcap;
	int slots;
	int *slot_block;     /* slot -> block index, -1 free */
	struct block *blocks;
	uint32_t cap, count; /* hash table of blocks (open addressing) */
	struct readback rb[READBACKS];
	uint32_t frame;
	double credit_ms;    /* generation budget left (negative: owed) */
	struct world_stats st;
	/* this frame's wanted blocks, nearest first */
	int *want;
	int nwant, want_cap;
};

static uint32_t hash_key(const int k[4])
{
	uint32_t h = (uint32_t)k[0] * 73856093u ^ (uint32_t)k[1] * 19349663u ^ (uint32_t)k[2] * 83492791u ^
		     (uint32_t)k[3] * 2654435761u;
	return h ^ (h >> 15);
}

static int rehash(struct world *w);

/* Index of the block with key k, creating it (B_FREE) if asked. */
static int find_block(struct world *w, const int k[4], bool create)
{
	if (create && (w->count + 1) * 4 > w->cap * 3 && rehash(w) < 0)
		return -1;
	uint32_t mask = w->cap - 1;
	for (uint32_t i = hash_key(k) & mask;; i = (i + 1) & mask) {
		struct block *b = &w->blocks[i];
		if (b->key[3] < 0) {
			if (!create)
				return -1;
			memcpy(b->key, k, sizeof(b->key));
			b->state = B_FREE;
			b->slot = -1;
			b->readback = -1;
			b->stale = false;
			b->generations = 0;
			w->count++;
			return (int)i;
		}
		if (!memcmp(b->key, k, sizeof(b->key)))
			return (int)i;
	}
}

static int rehash(struct world *w)
{
	uint32_t ncap = w->cap * 2;
	struct block *old = w->blocks;
	uint32_t ocap = w->cap;
	struct block *nb = malloc(sizeof(*nb) * ncap);
	if (!nb)
		return -1;
	for (uint32_t i = 0; i < ncap; i++)
		nb[i].key[3] = -1;
	w->blocks = nb;
	w->cap = ncap;
	w->count = 0;
	for (int i = 0; i < w->slots; i++)
		w->slot_block[i] = -1;
	for (uint32_t i = 0; i < ocap; i++) {
		if (old[i].key[3] < 0)
			continue;
		int j = find_block(w, old[i].key, true);
		w->blocks[j] = old[i];
		if (old[i].slot >= 0)
			w->slot_block[old[i].slot] = j;
		if (old[i].readback >= 0)
			w->rb[old[i].readback].block = j;
	}
	free(old);
	return 0;
}

struct world *world_create(const struct params *p, char *err, size_t errlen)
{
	struct world *w = calloc(1, sizeof(*w));
	if (!w) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	w->n = p->block_cells;
	w->slots = p->block_pool;
	w->tcap = (uint32_t)p->block_tris;
	w->vcap = w->tcap / 4 * 3; /* a surface has about half as many vertices as triangles */
	GLint align = 16;
	glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
	if (align < 16)
		align = 16;
	w->vstride = (GLintptr)w->vcap * VERTEX_BYTES;
	w->istride = (GLintptr)w->tcap * 12;
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

	struct grid g;
	memset(&g, 0, sizeof(g));
	g.nx = g.ny = g.nz = w->n;
	g.cell = p->block_size / (float)w->n;
	g.margin_extra = AO_MARGIN;
	struct params q = *p;
	q.closed = false;
	q.max_triangles = p->block_tris; /* its own buffers serve world_block_mesh */
	q.max_vertices = p->block_tris;
	w->pl = pipeline_create(&g, &q, err, errlen);
	if (!w->pl) {
		world_destroy(w);
		return NULL;
	}
	glGenBuffers(1, &w->vbo);
	glGenBuffers(1, &w->ibo);
	glGenBuffers(1, &w->status);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->vbo);
	glBufferData(GL_SHADER_STORAGE_BUFFER, w->vstride * w->slots, NULL, GL_DYNAMIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->ibo);
	glBufferData(GL_SHADER_STORAGE_BUFFER, w->istride * w->slots, NULL, GL_DYNAMIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->status);
	glBufferData(GL_SHADER_STORAGE_BUFFER, w->sstride * w->slots, NULL, GL_DYNAMIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	for (int i = 0; i < READBACKS; i++) {
		glGenBuffers(1, &w->rb[i].buf);
		glBindBuffer(GL_COPY_WRITE_BUFFER, w->rb[i].buf);
		glBufferData(GL_COPY_WRITE_BUFFER, RB_BYTES, NULL, GL_STREAM_READ);
		w->rb[i].block = -1;
	}
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
	if (gpu_check("block pool") < 0) {
		snprintf(err, errlen, "cannot allocate the block pool (%d slots of %u triangles: %lld MB); lower --block-pool",
			 w->slots, w->tcap, (long long)((w->vstride + w->istride) * w->slots >> 20));
		world_destroy(w);
		return NULL;
	}
	log_debug("world: %d slots x (%u vertices, %u triangles) = %lld MB", w->slots, w->vcap, w->tcap,
		  (long long)((w->vstride + w->istride + w->sstride) * w->slots >> 20));
	return w;
}

void world_destroy(struct world *w)
{
	if (!w)
		return;
	pipeline_destroy(w->pl);
	if (w->vbo)
		glDeleteBuffers(1, &w->vbo);
	if (w->ibo)
		glDeleteBuffers(1, &w->ibo);
	if (w->status)
		glDeleteBuffers(1, &w->status);
	for (int i = 0; i < READBACKS; i++) {
		if (w->rb[i].fence)
			glDeleteSync(w->rb[i].fence);
		if (w->rb[i].buf)
			glDeleteBuffers(1, &w->rb[i].buf);
	}
	free(w->blocks);
	free(w->slot_block);
	free(w->want);
	free(w);
}

static float block_world_size(const struct params *p, int lod)
{
	return p->block_size * (float)(1 << lod);
}

static void block_aabb(const struct params *p, const int k[4], float lo[3], float hi[3])
{
	float s = block_world_size(p, k[3]);
	for (int a = 0; a < 3; a++) {
		lo[a] = (float)k[a] * s;
		hi[a] = lo[a] + s;
	}
}

/* Frustum planes (Gribb & Hartmann) from a column-major view-projection. */
static void frustum(const float m[16], float pl[6][4])
{
	for (int i = 0; i < 3; i++)
		for (int s = 0; s < 2; s++) {
			float *q = pl[i * 2 + s];
			float sign = s ? -1.0f : 1.0f;
			for (int j = 0; j < 4; j++)
				q[j] = m[j * 4 + 3] + sign * m[j * 4 + i];
		}
}

static bool aabb_visible(float pl[6][4], const float lo[3], const float hi[3])
{
	for (int i = 0; i < 6; i++) {
		float px = pl[i][0] >= 0 ? hi[0] : lo[0];
		float py = pl[i][1] >= 0 ? hi[1] : lo[1];
		float pz = pl[i][2] >= 0 ? hi[2] : lo[2];
		if (pl[i][0] * px + pl[i][1] * py + pl[i][2] * pz + pl[i][3] < 0)
			return false;
	}
	return true;
}

static float aabb_distance(const float eye[3], const float lo[3], const float hi[3])
{
	float d2 = 0;
	for (int a = 0; a < 3; a++) {
		float v = eye[a] < lo[a] ? lo[a] - eye[a] : eye[a] > hi[a] ? eye[a] - hi[a] : 0.0f;
		d2 += v * v;
	}
	return sqrtf(d2);
}

/* Range of a level: lod_distance of its blocks, the coarsest to view_distance. */
static float lod_range(const struct params *p, int lod)
{
	if (lod == p->lod_levels - 1)
		return p->view_distance;
	float r = p->lod_distance * block_world_size(p, lod);
	return r < p->view_distance ? r : p->view_distance;
}

/* Heights where the surface can be (ground shape): the noise adds at most
 * about 1.6 x noise_amp, the warp moves it by warp_amp. */
static void height_band(const struct params *p, const float eye[3], float range, float *ylo, float *yhi)
{
	if (p->shape != SHAPE_GROUND) { /* planet, caves: anywhere */
		*ylo = eye[1] - range;
		*yhi = eye[1] + range;
		return;
	}
	float reach = 1.6f * p->noise_amp / (p->ground_slope > 0.05f ? p->ground_slope : 0.05f) + p->warp_amp;
	*ylo = -reach;
	*yhi = reach;
	if (p->floor_strength > 0 && p->floor_y - 1.0f > *ylo)
		*ylo = p->floor_y - 1.0f;
	/* terrain edits: the heightmap's own range; curves put the surface at
	 * their heights (cut and fill) */
	if (p->field == FIELD_HEIGHTMAP) {
		float extra = p->heightmap_detail + 1.6f * p->heightmap_noise * p->noise_amp + p->warp_amp + 1.0f;
		*ylo = fminf(*ylo, p->heightmap_base - extra);
		*yhi = fmaxf(*yhi, p->heightmap_base + p->heightmap_height + extra);
	}
	const struct curve_quads *q = &edits_get()->quads;
	for (int i = 0; i < q->nctrl; i++) {
		*ylo = fminf(*ylo, q->ctrl[i][1] - 1.0f);
		*yhi = fmaxf(*yhi, q->ctrl[i][1] + 1.0f);
	}
}

static int cmp_want(const void *a, const void *b, void *ctx);

static struct world *sort_ctx;
static int cmp_want_dist(const void *a, const void *b)
{
	return cmp_want(a, b, sort_ctx);
}

static int cmp_want(const void *a, const void *b, void *ctx)
{
	const struct world *w = ctx;
	const struct block *x = &w->blocks[*(const int *)a], *y = &w->blocks[*(const int *)b];
	if (x->dist != y->dist)
		return x->dist < y->dist ? -1 : 1;
	if (x->key[3] != y->key[3])
		return x->key[3] < y->key[3] ? -1 : 1; /* finer first at equal distance */
	return memcmp(x->key, y->key, sizeof(x->key));
}

static int push_want(struct world *w, int b)
{
	if (w->nwant == w->want_cap) {
		int nc = w->want_cap ? w->want_cap * 2 : 1024;
		int *nw = realloc(w->want, sizeof(int) * (size_t)nc);
		if (!nw)
			return -1;
		w->want = nw;
		w->want_cap = nc;
	}
	w->want[w->nwant++] = b;
	return 0;
}

/* The blocks this camera wants, nearest first. */
static int plan(struct world *w, const struct params *p, const struct camera *c)
{
	/* Blocks are wanted in a frustum widened by `prefetch` (the view turns
	 * while blocks stream in), drawn only when in the real one. */
	float pl[6][4], wide[6][4], proj[16], vp[16];
	frustum(c->viewproj, pl);
	memcpy(proj, c->proj, sizeof(proj));
	proj[0] /= p->prefetch;
	proj[5] /= p->prefetch;
	mat4_mul(vp, proj, c->view);
	frustum(vp, wide);
	w->nwant = 0;
	for (int lod = 0; lod < p->lod_levels; lod++) {
		float s = block_world_size(p, lod), range = lod_range(p, lod);
		float ylo, yhi;
		height_band(p, c->eye, range, &ylo, &yhi);
		int lo[3], hi[3];
		for (int a = 0; a < 3; a++) {
			float l = c->eye[a] - range, h = c->eye[a] + range;
			if (a == 1) {
				l = fmaxf(l, ylo);
				h = fminf(h, yhi);
			}
			lo[a] = (int)floorf(l / s);
			hi[a] = (int)floorf(h / s);
		}
		for (int z = lo[2]; z <= hi[2]; z++)
			for (int y = lo[1]; y <= hi[1]; y++)
				for (int x = lo[0]; x <= hi[0]; x++) {
					int k[4] = { x, y, z, lod };
					float blo[3], bhi[3];
					block_aabb(p, k, blo, bhi);
					float d = aabb_distance(c->eye, blo, bhi);
					if (d > range || !aabb_visible(wide, blo, bhi))
						continue;
					int b = find_block(w, k, true);
					if (b < 0)
						return -1;
					/* pointers may move with a rehash: use indices */
					w->blocks[b].dist = d;
					w->blocks[b].frame = w->frame;
					w->blocks[b].visible = aabb_visible(pl, blo, bhi);
					if (w->blocks[b].state == B_EMPTY) {
						w->st.empty_skipped++;
						continue;
					}
					if (push_want(w, b) < 0)
						return -1;
				}
	}
	sort_ctx = w;
	qsort(w->want, (size_t)w->nwant, sizeof(int), cmp_want_dist);
	return 0;
}

static void free_slot(struct world *w, int b)
{
	struct block *blk = &w->blocks[b];
	if (blk->slot >= 0)
		w->slot_block[blk->slot] = -1;
	blk->slot = -1;
}

/* A slot for a block at distance d: a free one, or the farthest block's
 * that is not wanted this frame or is farther than d. */
static int take_slot(struct world *w, float d)
{
	int best = -1;
	float best_d = -1;
	for (int s = 0; s < w->slots; s++) {
		int b = w->slot_block[s];
		if (b < 0)
			return s;
		const struct block *blk = &w->blocks[b];
		if (blk->readback >= 0)
			continue; /* result still in flight */
		float bd = blk->frame == w->frame ? blk->dist : 1e30f;
		if (bd > d && bd > best_d) {
			best_d = bd;
			best = s;
		}
	}
	if (best >= 0) {
		int b = w->slot_block[best];
		w->blocks[b].state = B_FREE;
		free_slot(w, b);
		w->st.evicted++;
	}
	return best;
}

/* Collects finished results: empty blocks give their slot back. */
static void collect(struct world *w, bool wait)
{
	for (int i = 0; i < READBACKS; i++) {
		struct readback *r = &w->rb[i];
		if (r->block < 0)
			continue;
		GLenum st = glClientWaitSync(r->fence, wait ? GL_SYNC_FLUSH_COMMANDS_BIT : 0,
					     wait ? 10ull * 1000 * 1000 * 1000 : 0);
		if (st != GL_ALREADY_SIGNALED && st != GL_CONDITION_SATISFIED)
			continue;
		glDeleteSync(r->fence);
		r->fence = 0;
		uint32_t v[RB_WORDS] = { 0 };
		glBindBuffer(GL_COPY_READ_BUFFER, r->buf);
		void *m = glMapBufferRange(GL_COPY_READ_BUFFER, 0, RB_BYTES, GL_MAP_READ_BIT);
		if (m) {
			memcpy(v, m, RB_BYTES);
			glUnmapBuffer(GL_COPY_READ_BUFFER);
		}
		glBindBuffer(GL_COPY_READ_BUFFER, 0);
		struct block *blk = &w->blocks[r->block];
		blk->readback = -1;
		r->block = -1;
		if (v[ST_OVERFLOW - RB_FIRST])
			w->st.overflowed++;
		if (m && v[ST_TRIS_NEEDED - RB_FIRST] == 0 && blk->stale) {
			/* edited since: the empty result is stale, ask again */
			blk->state = B_FREE;
			blk->stale = false;
			free_slot(w, (int)(blk - w->blocks));
		} else if (m && v[ST_TRIS_NEEDED - RB_FIRST] == 0) {
			blk->state = B_EMPTY;
			free_slot(w, (int)(blk - w->blocks));
			w->st.empty_found++;
		} else {
			blk->state = B_READY;
		}
	}
}

static int free_readback(struct world *w)
{
	for (int i = 0; i < READBACKS; i++)
		if (w->rb[i].block < 0)
			return i;
	return -1;
}

static void block_grid(const struct world *w, const struct params *p, const int k[4], struct grid *g)
{
	memset(g, 0, sizeof(*g));
	g->nx = g->ny = g->nz = w->n;
	g->cell = block_world_size(p, k[3]) / (float)w->n;
	g->margin_extra = AO_MARGIN;
	for (int a = 0; a < 3; a++)
		g->base[a] = k[a] * w->n;
}

static int generate(struct world *w, const struct params *p, int b, int slot, double now)
{
	struct block *blk = &w->blocks[b];
	struct grid g;
	block_grid(w, p, blk->key, &g);
	float bias = blk->key[3] > 0 ? p->lod_bias * g.cell : 0.0f;
	pipeline_set_grid(w->pl, &g, bias);
	struct pipeline_target t = {
		.vbo = w->vbo, .ibo = w->ibo, .status = w->status,
		.vbo_offset = w->vstride * slot, .ibo_offset = w->istride * slot, .status_offset = w->sstride * slot,
		.vert_cap = w->vcap, .tri_cap = w->tcap,
		.first_index = (uint32_t)(w->istride * slot / 4), .base_vertex = (uint32_t)(w->vstride * slot / VERTEX_BYTES),
	};
	pipeline_set_target(w->pl, &t);
	struct params q = *p;
	q.closed = false;
	if (pipeline_run(w->pl, &q) < 0)
		return -1;
	bool in_place = blk->stale && blk->slot == slot;
	blk->slot = slot;
	w->slot_block[slot] = b;
	blk->state = B_PENDING;
	if (!in_place)
		blk->born = now; /* a regenerated block does not fade in again */
	blk->stale = false;
	blk->generations++;
	w->st.generated++;
	int r = free_readback(w);
	if (r >= 0) {
		glBindBuffer(GL_COPY_READ_BUFFER, w->status);
		glBindBuffer(GL_COPY_WRITE_BUFFER, w->rb[r].buf);
		glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, w->sstride * slot + RB_FIRST * 4, 0, RB_BYTES);
		glBindBuffer(GL_COPY_READ_BUFFER, 0);
		glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
		w->rb[r].fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
		w->rb[r].block = b;
		blk->readback = r;
	} else {
		blk->state = B_READY; /* no room to ask: keep it, it may be empty */
	}
	return gpu_check("block generation");
}

int world_update(struct world *w, const struct params *p, const struct camera *c, double now, bool deterministic)
{
	w->frame++;
	/* terrain edits (curves / heightmap files changed, or set through the
	 * API): only the blocks under the changed region are generated again */
	char err[512];
	if (edits_load(p, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return -1;
	}
	float xz[4];
	if (edits_take_changes(xz))
		world_invalidate(w, p, xz);
	collect(w, false);
	if (plan(w, p, c) < 0)
		return -1;
	int made = 0;
	bool budgeted = !deterministic && p->gen_budget_ms > 0;
	/* The budget is a credit: each frame adds gen_budget_ms (banked up to
	 * one frame's worth), each block spends what it really took.  A block
	 * that costs more than a frame's budget (a 32^3 block with AO on a
	 * software rasteriser) is then generated every few frames instead of
	 * in every frame, and the frame rate holds. */
	if (budgeted)
		w->credit_ms = fmin(w->credit_ms + p->gen_budget_ms, p->gen_budget_ms);
	/* Order: coverage first, then detail.  The coarsest level alone covers
	 * the whole view (finer blocks lie over it), so its missing blocks come
	 * first, then the next finer level's; visible blocks before prefetched
	 * ones; nearest first within each (want[] is sorted by distance). */
	int n = w->nwant, passes = p->lod_levels * 2;
	for (int k = 0; k < n * passes && made < p->gen_per_frame; k++) {
		int pass = k / n, lod = p->lod_levels - 1 - pass % p->lod_levels;
		bool vis = pass < p->lod_levels;
		int b = w->want[k % n];
		struct block *blk = &w->blocks[b];
		/* a block edited under (stale) is generated again into its own slot */
		bool regen = blk->stale && blk->slot >= 0 && (blk->state == B_READY || blk->state == B_PENDING);
		if ((blk->state != B_FREE && !regen) || blk->key[3] != lod || blk->visible != vis)
			continue;
		if (regen && blk->readback >= 0)
			continue; /* its previous result is still in flight */
		/* a hole on screen (a visible coarsest block missing) is worse
		 * than a slow frame: one such block per frame whatever the credit */
		bool urgent = !regen && vis && lod == p->lod_levels - 1 && made == 0;
		if (budgeted && w->credit_ms <= 0.0 && !urgent)
			break;
		if (free_readback(w) < 0) {
			collect(w, true);
			if (free_readback(w) < 0)
				break;
		}
		int slot = regen ? blk->slot : take_slot(w, blk->dist);
		if (slot < 0)
			break; /* pool full of nearer blocks */
		double tb = clock_ms();
		if (generate(w, p, b, slot, now) < 0)
			return -1;
		made++;
		if (budgeted) {
			glFlush();
			w->credit_ms = fmax(w->credit_ms - (clock_ms() - tb), -4.0 * p->gen_budget_ms);
		}
	}
	if (deterministic)
		collect(w, true);
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

int world_draw(struct world *w, struct renderer *r, const struct camera *c, const struct params *p, double now)
{
	renderer_begin(r, c, p);
	int drawn = 0;
	/* want[] is sorted nearest first: front to back */
	for (int i = 0; i < w->nwant; i++) {
		struct block *blk = &w->blocks[w->want[i]];
		if ((blk->state != B_READY && blk->state != B_PENDING) || blk->slot < 0 || !blk->visible)
			continue;
		float fade = 1.0f;
		int lod = blk->key[3];
		if (lod < p->lod_levels - 1) {
			/* finer levels dissolve in after generation and out near
			 * the end of their range; the coarser level lies beneath */
			if (p->fade_time > 0)
				fade = fminf(1.0f, (float)(now - blk->born) / p->fade_time);
			float range = lod_range(p, lod);
			float edge = (range - blk->dist) / (0.2f * range);
			fade = fminf(fade, fmaxf(0.0f, fminf(1.0f, edge)));
			if (fade <= 0.0f)
				continue;
		}
		renderer_draw_mesh(r, w->vbo, w->ibo, w->status, w->sstride * blk->slot, fade);
		drawn++;
	}
	w->st.drawn = drawn;
	float rect[4] = { c->eye[0] - p->view_distance, c->eye[2] - p->view_distance, c->eye[0] + p->view_distance,
			  c->eye[2] + p->view_distance };
	renderer_water(r, c, p, rect);
	return renderer_end(r);
}

int world_invalidate(struct world *w, const struct params *p, const float xz[4])
{
	int marked = 0;
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

int world_block_generations(const struct world *w, int lod, const int idx[3], int *state)
{
	int k[4] = { idx[0], idx[1], idx[2], lod };
	uint32_t mask = w->cap - 1;
	for (uint32_t i = hash_key(k) & mask;; i = (i + 1) & mask) {
		const struct block *b = &w->blocks[i];
		if (b->key[3] < 0) {
			*state = 0;
			return -1;
		}
		if (!memcmp(b->key, k, sizeof(b->key))) {
			*state = (int)b->state;
			return b->generations;
		}
	}
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
}

int world_block_mesh(struct world *w, const struct params *p, int lod, const int idx[3], struct mesh *m)
{
	struct grid g;
	int k[4] = { idx[0], idx[1], idx[2], lod };
	block_grid(w, p, k, &g);
	pipeline_set_grid(w->pl, &g, 0.0f);
	pipeline_set_target(w->pl, NULL);
	struct params q = *p;
	q.closed = false;
	q.compaction = COMPACTION_HP;
	if (pipeline_run(w->pl, &q) < 0)
		return -1;
	return pipeline_read_mesh(w->pl, m);
}

/* ---- mesh export (--export-mesh) -------------------------------------------
 * Self-contained: reads the pool as world_draw sees it. */

static int export_read(GLuint buf, GLintptr off, GLsizeiptr size, void *out)
{
	if (size <= 0)
		return 0;
	glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
	glBindBuffer(GL_COPY_READ_BUFFER, buf);
	void *m = glMapBufferRange(GL_COPY_READ_BUFFER, off, size, GL_MAP_READ_BIT);
	if (m) {
		memcpy(out, m, (size_t)size);
		glUnmapBuffer(GL_COPY_READ_BUFFER);
	}
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	return m ? 0 : -1;
}

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
	if (export_read(w->status, w->sstride * b->slot + ST_TRIS_WRITTEN * 4, sizeof(v), v) < 0)
		return -1;
	_Static_assert(ST_VERTS_WRITTEN == ST_TRIS_WRITTEN + 1, "written counters are adjacent");
	*tris = v[0] < w->tcap ? v[0] : w->tcap;
	*verts = v[1] < w->vcap ? v[1] : w->vcap;
	return 0;
}

/* Block b's mesh appended to m at vertex nv, triangle nt. */
static int export_append(const struct world *w, const struct block *b, struct mesh *m, uint32_t nv, uint32_t nt,
			 uint32_t verts, uint32_t tris, float *vb)
{
	if (export_read(w->vbo, w->vstride * b->slot, (GLsizeiptr)verts * VERTEX_BYTES, vb) < 0 ||
	    export_read(w->ibo, w->istride * b->slot, (GLsizeiptr)tris * 12, m->idx + 3 * (size_t)nt) < 0)
		return -1;
	for (uint32_t i = 0; i < verts; i++)
		for (int a = 0; a < 3; a++) {
			m->pos[3 * (size_t)(nv + i) + a] = vb[8 * (size_t)i + a];
			m->nrm[3 * (size_t)(nv + i) + a] = vb[8 * (size_t)i + 4 + a];
		}
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
	float *vb = malloc((size_t)VERTEX_BYTES * (w->vcap ? w->vcap : 1));
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
