/* isoterra — the streaming world's generation: blocks extracted into the
 * slots of the pool (the pipeline writing into someone else's buffers) and
 * their results learnt a few frames on, through a fence and a 16-byte copy
 * of the block's status, without stalling the frame.
 *
 * Cheaper blocks (GPU Gems 3 ch.1's tricks, made safe):
 *  - a coarse pre-pass (pipeline_bound, shaders/block_bound.glsl) bounds
 *    the field over each wanted block whose verdict is unknown, a batch at
 *    a time, read back through a fence frames later; blocks it proves all
 *    air or all rock become empty without a slot or a full pass, only the
 *    others are generated;
 *  - coarse levels leave out the octaves whose bound is below the erosion
 *    they add over the finer level (block_octaves), so a coarse surface
 *    still lies under the finer one and no seam opens;
 *  - a live block's generation runs in four stages (pipeline_run_stage:
 *    density of half the slabs, the other half, classification +
 *    HistoPyramid, output), each charged to the frame's budget, so no
 *    frame carries a whole block. */
#include "world_int.h"
#include "terrain.h"
#include "core.h"
#include "gpu.h"

#include <math.h>
#include <string.h>

static void free_slot(struct world *w, int b)
{
	struct block *blk = &w->blocks[b];
	if (blk->slot >= 0) {
		w->slot_block[blk->slot] = -1;
		pool_release(w, blk->slot);
	}
	blk->slot = -1;
}

int take_slot(struct world *w, float d)
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

void collect_results(struct world *w, bool wait)
{
	for (int i = 0; i < READBACKS; i++) {
		struct readback *r = &w->rb[i];
		if (r->block < 0)
			continue;
		uint32_t v[RB_WORDS] = { 0 };
		int got = gpu_fence_read(&r->fence, r->buf, RB_BYTES, v, wait);
		if (got == 0)
			continue;
		bool m = got > 0;
		struct block *blk = &w->blocks[r->block];
		blk->readback = -1;
		r->block = -1;
		/* over capacity: the clamped mesh is drawn until the block is
		 * generated again into staging slots grown to what it needed
		 * (pool_grow); only a block over BLOCK_TRIS_MAX stays clamped */
		bool grow = false;
		if (v[ST_OVERFLOW - RB_FIRST]) {
			uint32_t need = v[ST_TRIS_NEEDED - RB_FIRST], nv = v[ST_VERTS_NEEDED - RB_FIRST];
			if (nv / 3 * 4 > need)
				need = nv / 3 * 4 + 4;
			grow = m && w->tcap < BLOCK_TRIS_MAX;
			if (grow && need > w->grow_tris)
				w->grow_tris = need;
			if (!grow)
				w->st.overflowed++;
		}
		if (m && v[ST_TRIS_NEEDED - RB_FIRST] == 0 && blk->stale) {
			/* edited since: the empty result is stale, ask again */
			blk->state = B_FREE;
			blk->stale = false;
			free_slot(w, (int)(blk - w->blocks));
		} else if (m && v[ST_TRIS_NEEDED - RB_FIRST] == 0) {
			blk->state = B_EMPTY;
			free_slot(w, (int)(blk - w->blocks));
			w->st.empty_found++;
		} else if (!m || pool_settle(w, blk->slot, v[ST_TRIS_WRITTEN - RB_FIRST], v[ST_VERTS_WRITTEN - RB_FIRST]) < 0) {
			log_error("world: a block's mesh could not be kept: it will be generated again");
			blk->state = B_FREE;
			free_slot(w, (int)(blk - w->blocks));
		} else {
			blk->state = B_READY;
			blk->stale = blk->stale || grow;
		}
	}
}

int free_readback(struct world *w)
{
	for (int i = 0; i < READBACKS; i++)
		if (w->rb[i].block < 0)
			return i;
	return -1;
}

void block_grid(const struct world *w, const struct params *p, const int k[4], struct grid *g)
{
	memset(g, 0, sizeof(*g));
	g->nx = g->ny = g->nz = w->n;
	g->cell = block_world_size(p, k[3]) / (float)w->n;
	g->margin_extra = AO_MARGIN;
	for (int a = 0; a < 3; a++)
		g->base[a] = k[a] * w->n;
}

/* ---- octaves per level -------------------------------------------------- */

/* Octaves of level lod without the governor's drop.  Level L is eroded by
 * lod_bias of its cells (level 0 not at all), so it may leave out octaves
 * of the finer level's whose bound (density_octaves_bound) fits in the
 * erosion it adds over that level, lod_bias (cell_L - cell_{L-1}): the
 * coarse density then stays at most the finer one's everywhere, the coarse
 * surface under the finer, and the level borders stay closed. */
static int lod_octaves(const struct world *w, const struct params *p, int lod)
{
	int n = p->octaves;
	for (int l = 1; l <= lod; l++) {
		float cell = block_world_size(p, l) / (float)w->n;
		float room = p->lod_bias * (cell - (l > 1 ? 0.5f * cell : 0.0f));
		int m = n;
		while (m > 1) {
			float b = density_octaves_bound(p, m - 1, n);
			if (b < 0.0f || b > room)
				break;
			m--;
		}
		n = m;
	}
	return n;
}

int block_octaves(const struct world *w, const struct params *p, int lod)
{
	int n = lod_octaves(w, p, lod);
	if (w->far_drop > 0 && lod == p->lod_levels - 1 && p->lod_levels > 1)
		n = n - w->far_drop > 1 ? n - w->far_drop : 1;
	return n;
}

/* The parameters block level lod is extracted with. */
static void block_params(const struct world *w, const struct params *p, int lod, struct params *q)
{
	*q = *p;
	q->octaves = block_octaves(w, p, lod);
	q->closed = false;               /* blocks are open: neighbours continue them */
	q->compaction = COMPACTION_HP;   /* indexed, shared vertices (as every slot) */
}

int block_extract(struct world *w, const struct params *p)
{
	struct params q;
	block_params(w, p, w->cur_lod, &q);
	char err[512];
	if (pipeline_run(w->pl, &q, err, sizeof(err)) < 0) {
		if (err[0])
			log_error("%s", err);
		return -1;
	}
	return 0;
}

/* Points the pipeline at block b's grid (and its erosion). */
static void block_begin(struct world *w, const struct params *p, int b)
{
	struct block *blk = &w->blocks[b];
	struct grid g;
	block_grid(w, p, blk->key, &g);
	float bias = blk->key[3] > 0 ? p->lod_bias * g.cell : 0.0f;
	pipeline_set_grid(w->pl, &g, bias);
	w->cur_lod = blk->key[3];
}

/* The pipeline's output into slot, through a free staging slot (the
 * caller made sure there is one). */
static int block_target(struct world *w, int slot)
{
	int stage = pool_free_stage(w);
	if (stage < 0) {
		log_error("world: no staging slot free for a block");
		return -1;
	}
	struct pipeline_target t;
	pool_target(w, slot, stage, &t);
	pipeline_set_target(w->pl, &t);
	return 0;
}

/* Block b written into slot: its bookkeeping and the request for its
 * result. */
static int block_done(struct world *w, int b, int slot, double now)
{
	struct block *blk = &w->blocks[b];
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
		/* no room to ask: learn its counts now, keep it even if empty */
		uint32_t v[2];
		_Static_assert(ST_VERTS_WRITTEN == ST_TRIS_WRITTEN + 1, "written counters are adjacent");
		if (gpu_read_buffer(w->status, w->sstride * slot + ST_TRIS_WRITTEN * 4, sizeof(v), v) < 0 ||
		    pool_settle(w, slot, v[0], v[1]) < 0)
			return -1;
		blk->state = B_READY;
	}
	return gpu_check("block generation");
}

int generate_block(struct world *w, const struct params *p, int b, int slot, double now)
{
	block_begin(w, p, b);
	if (block_target(w, slot) < 0 || block_extract(w, p) < 0)
		return -1;
	return block_done(w, b, slot, now);
}

/* ---- the coarse pre-pass ------------------------------------------------ */

int probes_create(struct world *w)
{
	w->gen_block = -1;
	for (int i = 0; i < PROBE_RING; i++) {
		struct probe_batch *pb = &w->probes[i];
		glGenBuffers(1, &pb->in);
		glGenBuffers(1, &pb->out);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, pb->in);
		glBufferData(GL_SHADER_STORAGE_BUFFER, PROBE_BATCH * 32, NULL, GL_DYNAMIC_DRAW);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, pb->out);
		glBufferData(GL_SHADER_STORAGE_BUFFER, PROBE_BATCH * 4, NULL, GL_STREAM_READ);
		pb->n = 0;
	}
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	return gpu_check("pre-pass buffers");
}

void probes_destroy(struct world *w)
{
	for (int i = 0; i < PROBE_RING; i++) {
		struct probe_batch *pb = &w->probes[i];
		if (pb->fence)
			glDeleteSync(pb->fence);
		if (pb->in)
			glDeleteBuffers(1, &pb->in);
		if (pb->out)
			glDeleteBuffers(1, &pb->out);
	}
}

void collect_probes(struct world *w, bool wait)
{
	for (int i = 0; i < PROBE_RING; i++) {
		struct probe_batch *pb = &w->probes[i];
		if (!pb->n)
			continue;
		uint32_t v[PROBE_BATCH];
		int got = gpu_fence_read(&pb->fence, pb->out, (GLsizeiptr)pb->n * 4, v, wait);
		if (got == 0)
			continue;
		bool m = got > 0;
		for (int k = 0; k < pb->n; k++) {
			int b = find_block(w, pb->key[k], false);
			if (b < 0)
				continue;
			struct block *blk = &w->blocks[b];
			if (blk->probe != PROBE_ASKED)
				continue; /* invalidated since: ask again */
			blk->probe = PROBE_SURFACE;
			if (m && (v[k] == 1 || v[k] == 2) && blk->state == B_FREE) {
				blk->state = B_EMPTY;
				w->st.prepass_empty++;
			}
		}
		pb->n = 0;
	}
}

/* The pre-pass's box of block k: its cells and one more on every side (the
 * owner cells on its faces), its erosion, and the octaves evaluated at the
 * lattice (at most as many as the block can be generated with: the bound
 * covers any count from there to p->octaves). */
static void probe_box(const struct world *w, const struct params *p, const int k[4], float box[8])
{
	float s = block_world_size(p, k[3]), cell = s / (float)w->n;
	int keep = lod_octaves(w, p, k[3]);
	if (k[3] == p->lod_levels - 1 && p->lod_levels > 1)
		keep -= 2; /* the governor's far_drop, at most 2 */
	keep = keep < 1 ? 1 : keep > DENSITY_BOUND_OCTAVES ? DENSITY_BOUND_OCTAVES : keep;
	for (int a = 0; a < 3; a++) {
		box[a] = (float)k[a] * s - cell;
		box[4 + a] = (float)(k[a] + 1) * s + cell;
	}
	box[3] = (float)keep;
	box[7] = k[3] > 0 ? p->lod_bias * cell : 0.0f;
}

/* Sends up to `batches` pre-pass batches of at most `limit` wanted blocks
 * whose verdict is unknown, in generation order (live: not the visible
 * coarsest blocks, which are generated without waiting for it); returns
 * the blocks sent, -1 on error. */
static int probe_wanted(struct world *w, const struct params *p, int batches, int limit, bool live)
{
	int n = w->nwant, passes = p->lod_levels * 2, sent = 0, k = 0;
	for (int i = 0; i < PROBE_RING && batches > 0; i++) {
		struct probe_batch *pb = &w->probes[i];
		if (pb->n)
			continue;
		float box[PROBE_BATCH][8];
		for (; k < n * passes && pb->n < PROBE_BATCH && pb->n < limit; k++) {
			int pass = k / n, lod = p->lod_levels - 1 - pass % p->lod_levels;
			struct block *blk = &w->blocks[w->want[k % n]];
			if (blk->state != B_FREE || blk->probe != PROBE_UNKNOWN || blk->key[3] != lod ||
			    blk->visible != (pass < p->lod_levels))
				continue;
			if (live && blk->visible && lod == p->lod_levels - 1)
				continue;
			probe_box(w, p, blk->key, box[pb->n]);
			memcpy(pb->key[pb->n++], blk->key, sizeof(blk->key));
			blk->probe = PROBE_ASKED;
		}
		if (!pb->n)
			break;
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, pb->in);
		glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)pb->n * 32, box);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
		char err[512];
		if (pipeline_bound(w->pl, p, pb->in, pb->out, (uint32_t)pb->n, err, sizeof(err)) < 0) {
			if (err[0])
				log_error("%s", err);
			return -1;
		}
		pb->fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
		w->st.prepass_probed += (uint64_t)pb->n;
		sent += pb->n;
		batches--;
	}
	return sent;
}

/* ---- generation, staged over frames ----------------------------------- */

/* The next stage of the block under way; 1 when it ran, 0 when the block
 * was dropped (no slot for its output, or not wanted any more), -1 on
 * error. */
static int run_stage(struct world *w, double now)
{
	int b = w->gen_block = find_block(w, w->gen_key, false);
	if (b < 0)
		return 0;
	struct block *blk = &w->blocks[b];
	bool regen = blk->stale && blk->slot >= 0;
	if (blk->frame != w->frame && !regen) { /* out of view since: drop it */
		w->gen_block = -1;
		return 0;
	}
	int slot = -1;
	if (w->gen_stage == PIPE_OUTPUT) {
		if (free_readback(w) < 0 || pool_free_stage(w) < 0)
			collect_results(w, false);
		if (pool_free_stage(w) < 0)
			collect_results(w, true); /* every staging slot awaits its counts: the oldest are done by now */
		slot = pool_free_stage(w) < 0 ? -1 : regen ? blk->slot : take_slot(w, blk->dist);
		if (slot < 0) { /* pool full of nearer blocks (or no staging slot) */
			w->gen_block = -1;
			return 0;
		}
		if (block_target(w, slot) < 0)
			return -1;
	}
	char err[512];
	if (pipeline_run_stage(w->pl, &w->gen_q, (enum pipeline_stage)w->gen_stage, err, sizeof(err)) < 0) {
		if (err[0])
			log_error("%s", err);
		return -1;
	}
	if (w->gen_stage++ < PIPE_OUTPUT)
		return 1;
	w->gen_block = -1;
	return block_done(w, b, slot, now) < 0 ? -1 : 1;
}

int finish_staged(struct world *w, double now)
{
	while (w->gen_block >= 0)
		if (run_stage(w, now) < 0)
			return -1;
	return 0;
}

/* The next wanted block to generate at or after *k (coverage first: the
 * coarsest level's visible blocks, then the finer levels', then the
 * prefetched ones; nearest first within each), with its regen flag; -1
 * when none. */
static int next_wanted(struct world *w, const struct params *p, bool live, int *k, bool *regen, bool *urgent)
{
	int n = w->nwant, passes = p->lod_levels * 2;
	for (; *k < n * passes; (*k)++) {
		int pass = *k / n, lod = p->lod_levels - 1 - pass % p->lod_levels;
		bool vis = pass < p->lod_levels;
		int b = w->want[*k % n];
		struct block *blk = &w->blocks[b];
		/* a block edited under (stale) is generated again into its own slot */
		*regen = blk->stale && blk->slot >= 0 && (blk->state == B_READY || blk->state == B_PENDING);
		if ((blk->state != B_FREE && !*regen) || blk->key[3] != lod || blk->visible != vis)
			continue;
		if (*regen && blk->readback >= 0)
			continue; /* its previous result is still in flight */
		/* a hole on screen (a visible coarsest block missing) is worse
		 * than a slow frame: live, it does not wait for the pre-pass */
		*urgent = !*regen && vis && lod == p->lod_levels - 1;
		if (!*regen && w->probe_on && blk->probe != PROBE_SURFACE && !(*urgent && live))
			continue; /* the pre-pass has not said yet */
		(*k)++;
		return b;
	}
	return -1;
}

int generate_wanted(struct world *w, const struct params *p, double now, bool deterministic)
{
	w->probe_on = density_bound_supported(p, w->ed);
	bool budgeted = !deterministic && p->gen_budget_ms > 0;
	/* The budget is a credit: each frame adds gen_budget_ms (banked up to
	 * one frame's worth), each stage spends what it really took.  A block
	 * that costs more than a frame's budget (a 32^3 block with AO on a
	 * software rasteriser) is then spread over several frames, and the
	 * frame rate holds. */
	if (budgeted)
		w->credit_ms = fmin(w->credit_ms + p->gen_budget_ms, p->gen_budget_ms);
	if (!budgeted && finish_staged(w, now) < 0) /* a live block under way, then offline */
		return -1;
	if (w->gen_block < 0 && pool_grow(w) < 0)
		return -1;
	collect_probes(w, deterministic);
	if (deterministic && w->probe_on) { /* every wanted block's verdict, now */
		int sent;
		while ((sent = probe_wanted(w, p, PROBE_RING, PROBE_BATCH, false)) > 0)
			collect_probes(w, true);
		if (sent < 0)
			return -1;
	}
	int made = 0, steps = 0, k = 0;
	bool exhausted = false;
	for (;;) {
		if (w->gen_block >= 0) { /* the block under way: its next stage */
			/* a hole on screen: up to half a block a frame whatever the credit */
			if (budgeted && w->credit_ms <= 0.0 && !(w->gen_urgent && steps < PIPE_STAGES / 2))
				break;
			double tb = clock_ms();
			int rc = run_stage(w, now);
			if (rc < 0)
				return -1;
			steps++;
			made += rc > 0 && w->gen_block < 0;
			glFlush();
			w->credit_ms = fmax(w->credit_ms - (clock_ms() - tb), -4.0 * p->gen_budget_ms);
			continue;
		}
		if (made >= p->gen_per_frame)
			break;
		/* slots to grow: no new block until the staged ones have settled */
		if (w->grow_tris > w->tcap) {
			int g = pool_grow(w);
			if (g < 0)
				return -1;
			if (g == 0)
				break;
		}
		bool regen = false, urgent = false;
		int b = next_wanted(w, p, budgeted, &k, &regen, &urgent);
		if (b < 0) {
			exhausted = true; /* nothing the pre-pass has cleared is left */
			break;
		}
		struct block *blk = &w->blocks[b];
		/* a visible coarsest block missing: one per frame whatever the credit */
		urgent = urgent && made == 0;
		if (budgeted && w->credit_ms <= 0.0 && !urgent)
			break;
		if (free_readback(w) < 0 || pool_free_stage(w) < 0) {
			collect_results(w, true);
			if (free_readback(w) < 0 || pool_free_stage(w) < 0)
				break;
		}
		if (budgeted) { /* live: staged, from the next turn of the loop */
			block_begin(w, p, b);
			block_params(w, p, blk->key[3], &w->gen_q);
			w->gen_block = b;
			memcpy(w->gen_key, blk->key, sizeof(w->gen_key));
			w->gen_stage = PIPE_DENSITY_LO;
			w->gen_urgent = urgent;
			continue;
		}
		int slot = regen ? blk->slot : take_slot(w, blk->dist);
		if (slot < 0)
			break; /* pool full of nearer blocks */
		if (generate_block(w, p, b, slot, now) < 0)
			return -1;
		made++;
	}
	/* the pre-pass for the next frames: a small batch a frame while the
	 * budget has credit left, or when generation waits for it (its cost is
	 * charged like a stage's: a block's bound costs a few % of its
	 * generation) */
	if (!deterministic && w->probe_on && (!budgeted || w->credit_ms > 0.0 || (exhausted && w->gen_block < 0))) {
		double tb = clock_ms();
		if (probe_wanted(w, p, 1, PROBE_LIVE, budgeted) < 0)
			return -1;
		if (budgeted) {
			glFlush();
			w->credit_ms = fmax(w->credit_ms - (clock_ms() - tb), -4.0 * p->gen_budget_ms);
		}
	}
	if (deterministic)
		collect_results(w, true);
	return 0;
}

/* ---- test hooks ------------------------------------------------------------ */

int world_prepass(struct world *w, const struct params *p, const int (*keys)[4], int n, int *verdict)
{
	collect_probes(w, true); /* the ring free */
	struct probe_batch *pb = &w->probes[0];
	for (int at = 0; at < n; at += PROBE_BATCH) {
		int m = n - at < PROBE_BATCH ? n - at : PROBE_BATCH;
		float box[PROBE_BATCH][8];
		for (int i = 0; i < m; i++)
			probe_box(w, p, keys[at + i], box[i]);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, pb->in);
		glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)m * 32, box);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
		char err[512];
		uint32_t v[PROBE_BATCH];
		if (pipeline_bound(w->pl, p, pb->in, pb->out, (uint32_t)m, err, sizeof(err)) < 0 ||
		    gpu_read_buffer(pb->out, 0, (GLsizeiptr)m * 4, v) < 0) {
			if (err[0])
				log_error("%s", err);
			return -1;
		}
		for (int i = 0; i < m; i++)
			verdict[at + i] = (int)v[i];
	}
	return 0;
}

int world_block_octaves(const struct world *w, const struct params *p, int lod)
{
	return block_octaves(w, p, lod);
}
