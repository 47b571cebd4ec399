/* isoterra — the streaming world's generation: blocks extracted into the
 * slots of the pool (the pipeline writing into someone else's buffers) and
 * their results learnt a few frames on, through a fence and a 16-byte copy
 * of the block's status, without stalling the frame. */
#include "world_int.h"
#include "log.h"
#include "gpu.h"

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
		} else if (!m || pool_settle(w, blk->slot, v[ST_TRIS_WRITTEN - RB_FIRST], v[ST_VERTS_WRITTEN - RB_FIRST]) < 0) {
			log_error("world: a block's mesh could not be kept: it will be generated again");
			blk->state = B_FREE;
			free_slot(w, (int)(blk - w->blocks));
		} else {
			blk->state = B_READY;
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

int block_extract(struct world *w, const struct params *p)
{
	struct params q = *p;
	if (w->far_drop > 0 && w->cur_lod == p->lod_levels - 1 && p->lod_levels > 1)
		q.octaves = p->octaves - w->far_drop > 1 ? p->octaves - w->far_drop : 1;
	q.closed = false;               /* blocks are open: neighbours continue them */
	q.compaction = COMPACTION_HP;   /* indexed, shared vertices (as every slot) */
	char err[512];
	if (pipeline_run(w->pl, &q, err, sizeof(err)) < 0) {
		if (err[0])
			log_error("%s", err);
		return -1;
	}
	return 0;
}

int generate_block(struct world *w, const struct params *p, int b, int slot, double now)
{
	struct block *blk = &w->blocks[b];
	struct grid g;
	block_grid(w, p, blk->key, &g);
	float bias = blk->key[3] > 0 ? p->lod_bias * g.cell : 0.0f;
	pipeline_set_grid(w->pl, &g, bias);
	int stage = pool_free_stage(w);
	if (stage < 0) {
		log_error("world: no staging slot free for a block");
		return -1;
	}
	struct pipeline_target t;
	pool_target(w, slot, stage, &t);
	pipeline_set_target(w->pl, &t);
	w->cur_lod = blk->key[3];
	if (block_extract(w, p) < 0)
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
