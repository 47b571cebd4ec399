/* isoterra — the streaming world: blocks of block_cells^3 cells at several
 * levels of detail, generated on the GPU into a fixed pool of buffer slots,
 * nearest first, under a per-frame budget; empty blocks are remembered and
 * never regenerated; visible blocks are drawn front to back. */
#ifndef ISOTERRA_WORLD_H
#define ISOTERRA_WORLD_H

#include <stdbool.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "params.h"
#include "render.h"

struct world;
struct edits;

struct world_stats {
	uint64_t generated;       /* blocks run through the pipeline */
	uint64_t empty_found;     /* of those, found to have no triangles */
	uint64_t empty_skipped;   /* requests skipped because known empty */
	uint64_t evicted;         /* slots taken back from a farther block */
	uint64_t overflowed;      /* blocks over the largest slot capacity (BLOCK_TRIS_MAX) */
	uint64_t stages_grown;    /* times the staging slots grew for a finer field's blocks */
	uint64_t invalidated;     /* blocks marked for regeneration by terrain edits */
	/* the coarse pre-pass (world_gen.c): blocks it bounded, and those it
	 * proved all air or all rock (never generated, known empty) */
	uint64_t prepass_probed;
	uint64_t prepass_empty;
	uint64_t arena_grown;     /* chunks added to the block arena (the first aside) */
	uint64_t arena_packed;    /* times one of its chunks was packed to make room */
	uint64_t forgotten;       /* blocks dropped from the table, not wanted for long */
	uint32_t blocks_known, table_cap; /* the block table: entries, capacity */
	long long arena_bytes;    /* the block arena's capacity (bytes, its chunks together) */
	long long arena_chunk;    /* of it, the size of a chunk (at least: one may be larger) */
	int arena_chunks;         /* its chunks */
	unsigned compiles;        /* programs the blocks' pipeline compiled (pipeline_compiles) */
	long long arena_used;     /* of it, the meshes of the blocks in it */
	long long arena_max;      /* what it may grow to: block_pool worst-case blocks */
	uint64_t drawn_tris;      /* triangles the last frame drew (a staged block counts its capacity) */
	uint64_t drawn_tris_max;  /* the most any frame drew */
	int ready, pending, empty_known, drawn, wanted;
};

/* A world carving the edit state ed (app/edit/edits.h; borrowed: it must
 * outlive the world).  NULL with err. */
struct world *world_create(const struct params *p, struct edits *ed, char *err, size_t errlen);
void world_destroy(struct world *w);
/* Plans and generates blocks for this camera.  deterministic: generate up
 * to gen_per_frame blocks and wait for their results (offline rendering,
 * tests); otherwise stop at gen_budget_ms.  now: seconds (fades).  0/-1. */
int world_update(struct world *w, const struct params *p, const struct camera *c, double now, bool deterministic);
/* The parameters as configured, before a governor turned AO rays or sun
 * shadow steps down: the terms they switch on keep their code in the
 * blocks' vertex pass even at a count of 0 (pipeline_keep_terms), so the
 * governor's steps compile nothing mid-flight. */
void world_keep_terms(struct world *w, const struct params *configured);
/* Generates until every wanted block is ready (or the pool is full). */
int world_fill(struct world *w, const struct params *p, const struct camera *c, double now);
/* Draws the visible blocks front to back with the renderer's program. */
int world_draw(struct world *w, struct renderer *r, const struct camera *c, const struct params *p, double now);
void world_get_stats(const struct world *w, struct world_stats *st);
/* The frame-time governor's far-LOD trick: the coarsest level's blocks made
 * from now on leave out their `drop` finest octaves (at least one stays);
 * the finer levels lie over them, so no seam shows. */
void world_set_far_octaves_drop(struct world *w, int drop);
/* A quality of the governor's ladder held by world w drawn by r: the
 * parameters the frame runs with into eff (governor_apply), the far
 * octaves left out, the edge smoothing and the render scale.  0, or -1
 * with err (the upscale pass could not be made). */
struct governor_quality;
int world_hold_quality(struct world *w, struct renderer *r, const struct governor_quality *q, const struct params *p,
		       struct params *eff, char *err, size_t errlen);

/* Terrain edits (curves, heightmap; app/edit/edits.h): marks every known block
 * whose density samples (the block, its sample margin and the reach of its
 * ambient-occlusion rays) overlap the world XZ box (xmin, zmin, xmax, zmax)
 * for regeneration.  A drawable block keeps its mesh until the new one
 * replaces it in the same slot; a block known to be empty is forgotten (an
 * embankment may fill it).  world_update() calls it itself with the region
 * edits_take_changes() reports, so an edit re-generates only the affected
 * blocks.  Returns the number of blocks marked. */
int world_invalidate(struct world *w, const struct params *p, const float xz[4]);
/* Test hook: how many times block (lod, idx) was generated, its state
 * (0 unknown/free, 1 pending, 2 ready, 3 empty) in *state; -1 if unknown. */
int world_block_generations(const struct world *w, int lod, const int idx[3], int *state);

/* Test hook: 0 when the block memory is consistent — every staging slot's
 * canary intact (nothing wrote past a slot's capacity), every mesh in the
 * arena inside it and apart from the others, the bytes in use their sum —
 * else the number of faults found (each logged); -1 on read failure. */
int world_check_pool(struct world *w);
/* Test hook: the arena of worlds created from now on starts at bytes
 * (0: the default), so that tests see it grow. */
void world_test_arena_start(long long bytes);
/* Test hook: blocks not wanted for this many frames are forgotten (0: the
 * default, BLOCK_MEMORY_FRAMES). */
void world_test_table_age(uint32_t frames);
/* Test hook: packs the arena's meshes at its start (what a growth does,
 * into a new buffer of the same size); the number of meshes that moved, or
 * -1. */
int world_test_compact(struct world *w);

/* Test hooks: generate one block (lod, index) into a scratch slot and read
 * its mesh back (positions/normals; indices local). 0/-1. */
int world_block_mesh(struct world *w, const struct params *p, int lod, const int idx[3], struct mesh *m);

/* Test hooks of the coarse pre-pass: its verdicts for n blocks (x, y, z,
 * lod), 0 may hold a surface, 1 all air, 2 all rock; whether it runs for
 * p (the field has a bound); the octaves level lod's blocks are made with.
 * 0/-1. */
int world_prepass(struct world *w, const struct params *p, const int (*keys)[4], int n, int *verdict);
int world_block_octaves(const struct world *w, const struct params *p, int lod);

/* The surface the world shows, as one mesh (--export-mesh): every block the
 * pool holds a mesh for (generated, not known to be empty), each at its own
 * level of detail, positions in world space (as generated), normals, and
 * indices rebased from each block's slot to the mesh.  Where a finer block
 * lies over a coarser one both are in the mesh, as both are drawn (the
 * coarser eroded by lod_bias of its cells, so slightly inside): with
 * lod_levels = 1 the mesh is the exact, single surface.  0, or -1 (read-back
 * failure, out of memory; m is then empty). */
int world_read_mesh(struct world *w, struct mesh *m);

/* ---- autopilot ----------------------------------------------------------- */
struct noise_set;
struct autopilot {
	double t;                 /* simulated time, seconds */
	float pos[3], dir[3];     /* position, unit heading */
	float yaw, pitch;         /* heading angles, radians */
	float min_clearance_seen; /* most negative margin to rock seen (tests) */
	bool manual;              /* steered by autopilot_steer (camera=manual) */
	float in_move[3];         /* held input: forward, right, up (-1..1) */
	float in_turn[2];         /* held input: yaw right, pitch up (-1..1) */
	float goal[3];            /* heading steered to (unit) */
	float escape[3];          /* heading out of a dead end (unit) */
	double escape_until;      /* held until this time */
	float anchor[3];          /* where it was at anchor_t (progress check) */
	double anchor_t;
	unsigned tick;            /* steps since the last plan */
	bool blocked;             /* the last step could not go straight ahead */
	float view_down;          /* the view's tilt below the heading (tan), smoothed:
	                           * over open ground it frames the land ahead */
	float framing;            /* 1: the composed start (the default), 0: the cruise's
	                           * tilt from the start (the governor's first step) */
	const struct params *p;
	struct noise_set *ns;
	const struct edits *ed;   /* the terrain edits it avoids (NULL: none) */
};
/* ed: the edit state the world carves (borrowed, read as it changes), or
 * NULL.  0, or -1 when out of memory. */
int autopilot_init(struct autopilot *a, const struct params *p, const struct edits *ed);
void autopilot_free(struct autopilot *a);
/* Advances the fixed-step simulation to time t (deterministic). */
void autopilot_advance(struct autopilot *a, double t);
/* Manual flight from now on: holds this input (forward, right, up; yaw,
 * pitch; each -1..1) until the next call.  Still never enters rock. */
void autopilot_steer(struct autopilot *a, const float move[3], const float turn[2]);
/* Back to the autopilot after manual flight (the gamepad's start button):
 * it flies on from where it is, along its heading. */
void autopilot_resume(struct autopilot *a);
/* Camera looking along the heading, down by view_down (up is the
 * planet's radius in planet mode). */
void autopilot_camera(const struct autopilot *a, struct camera *c, float fov, float aspect, float far);

#endif
