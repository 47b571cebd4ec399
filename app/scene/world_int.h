/* isoterra — inside the streaming world: its state and what its files
 * share (world.c: the pool, the frame, the hooks; world_plan.c: the block
 * table and the blocks a camera wants; world_gen.c: generating blocks into
 * slots and learning their results).  Nothing outside app/scene/world*.c
 * includes this. */
#ifndef ISOTERRA_WORLD_INT_H
#define ISOTERRA_WORLD_INT_H

#include <stdbool.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "world.h"
#include "gpu.h"
#include "edit.h"
#include "extract.h"
#include "terrain.h"

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
	/* ---- cheaper blocks (world_gen.c): the coarse pre-pass's verdict ---- */
	uint8_t probe;       /* PROBE_*: unknown, asked (in flight), may have a surface */
};

/* The coarse pre-pass (world_gen.c): a block is generated only once a
 * pre-pass has said it may hold a surface; blocks it proves all air or all
 * rock become B_EMPTY without ever being generated. */
enum { PROBE_UNKNOWN = 0, PROBE_ASKED, PROBE_SURFACE };
#define PROBE_BATCH 128 /* candidate blocks per pre-pass dispatch */
#define PROBE_RING 4    /* pre-pass batches in flight */
#define PROBE_LIVE 8    /* candidate blocks a live frame sends */
struct probe_batch {
	GLuint in, out;      /* candidate boxes (2 vec4 each), verdicts (uint each) */
	GLsync fence;
	int n;               /* 0: free */
	int key[PROBE_BATCH][4]; /* the blocks' keys (indices move with a rehash) */
};

struct readback {
	GLuint buf;
	GLsync fence;
	int block;           /* block index, -1 = free */
};

#define READBACKS 64
/* staging slots: a block is generated into one (worst-case capacity) and
 * moved into the arena, at its real size, once its counts are read back
 * (world_pool.c) */
#define WORLD_STAGES 8
#define STAGE_GUARD 256u       /* canary bytes after a staging slot's capacity */
#define STAGE_GUARD_WORD 0x5eb1a7e5u
/* a generated block's counters, copied out of its status block for the
 * fence-guarded read-back: triangles/vertices needed ... overflow flag */
#define RB_FIRST ST_TRIS_NEEDED
#define RB_WORDS (ST_OVERFLOW - ST_TRIS_NEEDED + 1)
#define RB_BYTES (RB_WORDS * 4)
/* Frames the driver may hold at once: drawing a frame first waits until
 * the one FRAMES_IN_FLIGHT before it is done (llvmpipe queues up to 64
 * binned scenes of up to 36 MB each; docs/RELIABILITY.md, "Memory") */
#define FRAMES_IN_FLIGHT 2
#define AO_MARGIN 6      /* extra density samples around a block: short AO rays */

/* A slot's mesh: in staging slot `stage` (>= 0) until its counts are known,
 * then `bytes` of arena chunk `chunk` at `off` (its vertices, then its
 * indices). */
struct slot_mem {
	GLintptr off, bytes;
	uint32_t tris, verts;
	int stage, chunk;
};

/* One buffer of the block arena: meshes at their real sizes, first fit. */
struct arena_chunk {
	GLuint buf;
	GLintptr cap, used;
};

/* a wanted block with its sort keys (nearest first) */
struct want_key {
	float dist;
	int key[4];
	int block;
};

/* the largest block capacity, triangles (block_tris's range, params.def) */
#define BLOCK_TRIS_MAX 200000

struct world {
	struct edits *ed;          /* borrowed: the terrain edits */
	struct terrain *terrain;   /* the field the blocks are extracted from */
	struct pipeline *pl;
	int far_drop;        /* octaves left out of the coarsest level's new blocks (the governor) */
	int cur_lod;         /* the level of the block being extracted */
	int n;               /* cells per block edge */
	GLuint vbo, ibo, status;   /* staging vertices, indices (WORLD_STAGES); status per slot */
	GLintptr vstride, istride, sstride;
	uint32_t vcap, tcap;
	uint32_t grow_tris;  /* a block needed this many triangles (or its vertices
	                      * as many): the staging slots grow to it when free */
	int slots;
	int *slot_block;     /* slot -> block index, -1 free */
	struct slot_mem *mem;      /* slot -> where its mesh is */
	struct slot_mem *ord;      /* slots entries: the live meshes sorted by place (world_pool.c) */
	int stage_slot[WORLD_STAGES]; /* staging slot -> slot, -1 free */
	struct arena_chunk *chunks; /* the block arena: the meshes at their real sizes */
	int nchunks, chunks_cap;
	GLintptr chunk_bytes;      /* a new chunk's size (at least what a block needs) */
	GLintptr arena_cap, arena_max, arena_used; /* the chunks' bytes; what the meshes may take; hold */
	struct block *blocks;
	uint32_t cap, count; /* hash table of blocks (open addressing) */
	struct readback rb[READBACKS];
	GLsync frame_fence[FRAMES_IN_FLIGHT]; /* after each of the last frames drawn */
	uint32_t draws;      /* frames drawn (world_draw) */
	uint32_t frame;
	double credit_ms;    /* generation budget left (negative: owed) */
	struct world_stats st;
	/* this frame's wanted blocks, nearest first */
	int *want;
	struct want_key *want_sort; /* want_cap of them: sorting want[] */
	int nwant, want_cap;
	/* ---- cheaper blocks (world_gen.c): the coarse pre-pass and a block's
	 * generation spread over frames ---- */
	bool probe_on;       /* the field has a bound (density_bound_supported) */
	struct probe_batch probes[PROBE_RING];
	int gen_block;       /* the block whose stages are under way, -1 none */
	int gen_key[4];      /* its key (indices move with a rehash) */
	int gen_stage;       /* its next stage (enum pipeline_stage) */
	bool gen_urgent;     /* it fills a hole on screen (a visible coarsest block) */
	struct params gen_q; /* the parameters its stages run with */
};

/* ---- world_plan.c -------------------------------------------------------- */

/* Index of the block with key k (x, y, z, lod), creating it (B_FREE) if
 * asked; -1 when absent or out of memory.  Indices move with a rehash. */
int find_block(struct world *w, const int k[4], bool create);
float block_world_size(const struct params *p, int lod);
void block_aabb(const struct params *p, const int k[4], float lo[3], float hi[3]);
/* Range of a level: lod_distance of its blocks, the coarsest to view_distance. */
float lod_range(const struct params *p, int lod);
/* Once the table is over half full: the blocks that hold no slot, no
 * result in flight and were not wanted in the last `age` frames are
 * forgotten (an empty one would be generated again if wanted), the table
 * doubled only while the rest would fill more than half of it.  Indices
 * move: call it before plan_blocks.  0/-1. */
int prune_blocks(struct world *w, uint32_t age);
/* Frames a block nobody wants stays known (docs/RELIABILITY.md, "Memory") */
#define BLOCK_MEMORY_FRAMES 1000
/* The blocks this camera wants into want[], nearest first.  0/-1. */
int plan_blocks(struct world *w, const struct params *p, const struct camera *c);

/* ---- world_pool.c ------------------------------------------------------------ */

/* The status blocks, staging slots, arena and read-back ring.  0, or -1 with err. */
int pool_create(struct world *w, char *err, size_t errlen);
void pool_destroy(struct world *w);
/* A free staging slot, or -1. */
int pool_free_stage(const struct world *w);
/* Slot's block is generated (again) into staging slot stage: its old mesh
 * is given up, t is the pipeline's target. */
void pool_target(struct world *w, int slot, int stage, struct pipeline_target *t);
/* Slot's block wrote tris triangles and verts vertices: moved from its
 * staging slot into the arena (grown if needed), its draw command pointed
 * there.  0/-1. */
int pool_settle(struct world *w, int slot, uint32_t tris, uint32_t verts);
/* The staging slots' capacity grown to w->grow_tris triangles (and 3/4
 * as many vertices) and a quarter more, when no block is staged: 1 grown,
 * 0 not now (a block staged, or nothing to grow), -1 on a GL error. */
int pool_grow(struct world *w);
/* Staging slot strides for w->tcap / w->vcap (world.c). */
void plan_strides(struct world *w);
/* Gives up slot's mesh (staging slot and arena range). */
void pool_release(struct world *w, int slot);
/* The buffers and byte offsets of slot's vertices and indices. */
void pool_mesh_at(const struct world *w, int slot, GLuint *vbo, GLintptr *voff, GLuint *ibo, GLintptr *ioff);

/* ---- world_gen.c ----------------------------------------------------------- */

void block_grid(const struct world *w, const struct params *p, const int k[4], struct grid *g);
/* Runs the pipeline on the grid and target set (an open block, indexed);
 * 0, or -1 (logged). */
int block_extract(struct world *w, const struct params *p);
/* A slot for a block at distance d: a free one, or the farthest block's
 * that is not wanted this frame or is farther than d; -1 if none. */
int take_slot(struct world *w, float d);
/* Collects finished results (waiting for them with wait): empty blocks
 * give their slot back. */
void collect_results(struct world *w, bool wait);
/* A free entry of the readback ring, or -1. */
int free_readback(struct world *w);
/* Generates block b into slot and asks for its result.  0/-1. */
int generate_block(struct world *w, const struct params *p, int b, int slot, double now);
/* Octaves of level lod's blocks: those below the level's erosion left out
 * (world_gen.c, lod_octaves), and the governor's far_drop at the coarsest. */
int block_octaves(const struct world *w, const struct params *p, int lod);
/* The pre-pass's buffers (world_create) and their release.  0/-1. */
int probes_create(struct world *w);
void probes_destroy(struct world *w);
/* Reads the verdicts of finished pre-pass batches (waiting with wait). */
void collect_probes(struct world *w, bool wait);
/* This frame's generation (world_update): pre-pass the wanted blocks whose
 * verdict is unknown, and generate those that may hold a surface, coverage
 * first, under the budget, a live block's stages spread over frames.  0/-1. */
int generate_wanted(struct world *w, const struct params *p, double now, bool deterministic);
/* Runs the stages left of a block under way (before another run of the
 * pipeline).  0/-1. */
int finish_staged(struct world *w, double now);

#endif
