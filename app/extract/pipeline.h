/* isoterra — the extraction engine: a density field -> Marching Cubes
 * classification -> HistoPyramid compaction -> vertex and index generation
 * -> indirect draw, all on the GPU (docs/PIPELINE.md).  As in HPMC
 * (Dyken's HistoPyramid Marching Cubes), the engine takes a field provider
 * (field.h: the GLSL program that defines the field + a callback that binds
 * its resources) and knows nothing about what the field is.  No CPU
 * read-back in the frame loop; the *_read functions are for tests, export
 * and end-of-run reports.
 *
 * Five calls (a current GL ES 3.1 context throughout):
 *
 *   struct pipeline *pl = pipeline_create(&grid, p, field, err, errlen);   1. with a field
 *   pipeline_set_grid(pl, &grid2, bias);   2. optional: another grid of the same size
 *   pipeline_set_target(pl, &slot);           and/or someone else's output buffers
 *   pipeline_run(pl, p, err, errlen);      3. density + extraction (every frame)
 *   pipeline_draw_info(pl, &draw);         4. what the renderer draws, indirectly
 *   pipeline_destroy(pl);                  5.
 *
 * The terrain is one field provider (app/terrain/terrain.h). */
#ifndef ISOTERRA_PIPELINE_H
#define ISOTERRA_PIPELINE_H

#include <stdbool.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "params.h"
#include "core.h"
#include "field.h"

/* The grid the parameters describe (--grid N cells over the vol_* cube). */
void grid_from_params(struct grid *g, const struct params *p);

struct extract_stats {
	uint64_t triangles_needed, vertices_needed;   /* what the field asked for */
	uint32_t triangles, vertices;                 /* what was written (clamped) */
	uint32_t triangle_capacity, vertex_capacity;
	bool overflow;
};

struct pipeline;

/* Creates buffers and programs for grid g over the field f (borrowed: it
 * must outlive the pipeline; NULL is refused with a message).  Capacities:
 * p->max_triangles / p->max_vertices (0 = automatic).  Returns NULL with
 * err. */
struct pipeline *pipeline_create(const struct grid *g, const struct params *p, const struct field *f, char *err,
				 size_t errlen);
void pipeline_destroy(struct pipeline *pl);

/* Per-pass timing for benchmarks: with profiling on, every pass ends with
 * glFinish and its wall time is added up; pipeline_profile returns the sums
 * since the last call (ms may be NULL) and resets them. */
enum { PASS_DENSITY, PASS_CLASSIFY, PASS_REDUCE, PASS_VERTICES, PASS_INDICES, PASS_COUNT };
void pipeline_profile(struct pipeline *pl, bool on, double ms[PASS_COUNT]);
/* Programs the pipeline has compiled since it was made: its own passes
 * and every specialized variant of the field's program (a variant found
 * in the cache compiles nothing).  Tests and benchmarks: a knob that
 * moves a value within "on" must not add to it. */
unsigned pipeline_compiles(const struct pipeline *pl);
/* Terms a governor turns down to nothing and up again while the run goes
 * on (AO rays, sun shadow steps): those on in the configured parameters
 * are kept, their code in the vertex pass at a count of 0, which runs
 * none of it (shaders/ao.glsl and sun.glsl return full visibility, as the
 * pass without them writes), so the step switches no program.  A variant
 * made mid-flight is a hitch: on llvmpipe with empty caches, 281 ms for
 * the pass without AO. */
void pipeline_keep_terms(struct pipeline *pl, const struct params *configured);
/* The density pass's program of the last pipeline_density/pipeline_run
 * (tests: which uniforms a variant still reads). */
GLuint pipeline_density_program(const struct pipeline *pl);

/* Output into a slot of someone else's buffers (the world's block pool)
 * instead of the pipeline's own: vertices at vbo_offset (vert_cap of them),
 * indices at ibo_offset (tri_cap triangles), the ST_BYTES status block (abi.h) with
 * the draw command at status_offset; offsets must honour
 * GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT.  The draw command gets
 * first_index / base_vertex so one element buffer serves every slot.  NULL
 * restores the pipeline's own buffers.  HistoPyramid compaction only. */
struct pipeline_target {
	GLuint vbo, ibo, status;
	GLintptr vbo_offset, ibo_offset, status_offset;
	uint32_t vert_cap, tri_cap;
	uint32_t first_index, base_vertex;
};
void pipeline_set_target(struct pipeline *pl, const struct pipeline_target *t);
/* Points the pipeline at another grid of the same size (a world block). */
void pipeline_set_grid(struct pipeline *pl, const struct grid *g, float density_bias);

/* Runs the density pass only (benchmarks, tests).  0, or -1 with err (left
 * empty when the cause, a GL error, was already logged by gpu_check). */
int pipeline_density(struct pipeline *pl, const struct params *p, char *err, size_t errlen);
/* Runs density + extraction with the compaction method in p->compaction
 * (HistoPyramid always with a target).  0, or -1 with err as above. */
int pipeline_run(struct pipeline *pl, const struct params *p, char *err, size_t errlen);
/* Lets go of what only a run needs: the densities, sign bits and the
 * HistoPyramid (at the no-flag run's 128x58x128, 10.7 MB).  The mesh, its
 * draw command and counters stay, to draw, read and export; the next run
 * (or its first stage) makes the rest again.  For a scene's last frame:
 * the volume's picture is drawn without them.  Not between a run's
 * stages; pipeline_read_density fails until the next run.  A driver may
 * keep a deleted buffer until its next compute pass binds others (Mesa's
 * state tracker does): on a software rasterizer the draw's parts pass
 * (app/render/parts.c) is that pass. */
void pipeline_release_field(struct pipeline *pl);
/* The same run in four stages (a world block's generation spread over
 * frames, pipeline_run's HistoPyramid path in order): the density of the
 * lower and the upper half of the z slabs, classification + HistoPyramid,
 * and the output (indirect commands, vertices, indices: only this stage
 * writes the target).  The grid, target and parameters must stay the same
 * from the first stage to the last, and no other run may come in between;
 * a frame's drawing may.  0, or -1 with err as above. */
enum pipeline_stage { PIPE_DENSITY_LO, PIPE_DENSITY_HI, PIPE_PYRAMID, PIPE_OUTPUT, PIPE_STAGES };
int pipeline_run_stage(struct pipeline *pl, const struct params *p, enum pipeline_stage stage, char *err,
		       size_t errlen);
/* The streaming world's coarse pre-pass (shaders/block_bound.glsl): for
 * count candidate boxes in buffer in (two vec4 each: low corner + the
 * octaves evaluated, high corner + the density bias), a verdict each into
 * out (uint: 0 may hold a surface, 1 all air, 2 all rock), from the
 * field's conservative bound (density_bound() in its program; the terrain:
 * shaders/density_bound.glsl).  Asynchronous: fence it to read out.  0,
 * or -1 with err. */
int pipeline_bound(struct pipeline *pl, const struct params *p, GLuint in, GLuint out, uint32_t count, char *err,
		   size_t errlen);
/* Draw state for the renderer: vertex buffer (vec4 position, vec4 normal per
 * vertex, 32 bytes), element buffer (uint32, may be 0 when not indexed) and
 * the indirect command buffer (DrawElementsIndirectCommand at offset 0, or
 * DrawArraysIndirectCommand when indexed is false). */
struct pipeline_draw {
	GLuint vbo, ibo, indirect;
	GLintptr indirect_offset;
	bool indexed;
	uint32_t capacity; /* triangles the command can draw at most */
};
void pipeline_draw_info(const struct pipeline *pl, struct pipeline_draw *d);

/* ---- read-back (buffers.c; tests, export, reports; never in the frame
 * loop).  Each waits for the GPU. ------------------------------------------ */
/* grid_dens_count() densities (the grid's corners and margin), x fastest. */
int pipeline_read_density(struct pipeline *pl, float *out);
/* 0 when the canaries after the output buffers are intact, 1 when
 * something wrote past a capacity, -1 on read error. */
int pipeline_check_guards(struct pipeline *pl);
int pipeline_read_stats(struct pipeline *pl, struct extract_stats *st);
/* The same counts without a stall, for a frame loop: pipeline_watch_stats
 * copies the last run's (into the pipeline's own buffers: a target's
 * status block has its owner's read-back, world_gen.c) behind a fence (0,
 * or -1 logged);
 * pipeline_watched_stats gives them once the GPU is past it (1), 0 before
 * (or when nothing is watched), -1 when they could not be read; wait:
 * blocks until then (offline). */
int pipeline_watch_stats(struct pipeline *pl);
int pipeline_watched_stats(struct pipeline *pl, bool wait, struct extract_stats *st);
/* The extracted mesh (indexed; for atomic/none the triangles are unshared). */
int pipeline_read_mesh(struct pipeline *pl, struct mesh *m);
/* HistoPyramid test hook (histopyramid.c): builds the pyramid over n
 * level-0 cell bytes (bits 0..2 triangle count, bits 3..5 vertex mask) with
 * the extraction's own reduction and down-sweep, returns the totals
 * (triangles, vertices), the (cell, rank) of every output key of component
 * comp (0 triangles, 1 vertices) and every cell's prefix sum, read
 * bottom-up (prefix) and from the down-swept prefix sums (prefix_fast, may
 * be NULL).  The traversal's hints cover the first hint_keys keys (0:
 * every one; past them it searches every node, as for a world stage grown
 * past its pipeline's capacity).  key_* must hold 5n (triangles) or 3n
 * (vertices) entries, prefix n.  Needs a current context.  0 or -1 with
 * err. */
int hp_selftest(const uint8_t *bytes, uint32_t n, int comp, uint32_t hint_keys, uint32_t total[2], uint32_t *key_cell,
		uint32_t *key_rank, uint32_t *prefix, uint32_t *prefix_fast, char *err, size_t errlen);

#endif
