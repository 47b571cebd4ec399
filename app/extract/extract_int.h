/* isoterra — inside the extraction engine: the pipeline's state and what
 * its files share (pipeline.c: buffers, programs, passes; histopyramid.c:
 * the pyramid's levels, reduction and down-sweep; buffers.c).  Nothing
 * outside app/extract/ includes this. */
#ifndef ISOTERRA_EXTRACT_INT_H
#define ISOTERRA_EXTRACT_INT_H

#include <stdbool.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "pipeline.h"

#define GUARD_BYTES 1024u      /* canary after every output buffer */
#define GUARD_WORD 0xa5c3e1f7u
/* Specialized programs kept per pipeline (least recently used evicted):
 * each parameter state needs two (density pass, vertex pass with AO), so
 * 16 keep eight states, the terms a knob flips among them. */
#define PROGRAM_VARIANTS 16
#define VARIANT_KEY_MAX 1024   /* its #defines (the cache key) */

static inline uint32_t div_up(uint64_t a, uint64_t b)
{
	return (uint32_t)((a + b - 1) / b);
}

/* ---- the HistoPyramid (histopyramid.c) ------------------------------------ */

#define HP_MAX_LEVELS 16 /* u_hp_off[16] in shaders/hp.glsl */

/* Level sizes: n[1] = level-0 words, n[k] = ceil(n[k-1] / 4) up to one node
 * at `top` (2 or more); every level from 2 but the top padded to a multiple
 * of four (pad) so a parent reads four children.  One buffer of uvec2 nodes
 * (shaders/hp.glsl): level 0 first (l0 nodes, two words each, four words a
 * level-2 node), level 1 not stored (off[1], pad[1] 0), level k >= 2 at
 * node offset off[k], then the prefix sums of levels 2..top, node i of
 * level k at pre_base + off[k] + i; `nodes` in all. */
struct hp_levels {
	int top;
	uint32_t n[HP_MAX_LEVELS], pad[HP_MAX_LEVELS], off[HP_MAX_LEVELS];
	uint32_t l0, pre_base, nodes;
	uint32_t hint, hint_n; /* the traversal's hints (shaders/hp.glsl): where, how many */
};

/* The levels over `words` level-0 words, with hints for up to `keys`
 * outputs of either component. */
void hp_plan(struct hp_levels *h, uint32_t words, uint32_t keys);
/* u_hp_off, u_hp_top, u_pre_base of a program (those it uses). */
void hp_set_uniforms(GLuint prog, const struct hp_levels *h);
/* glDispatchCompute of 64-wide groups over items, split in 2D past
 * max_groups. */
void hp_dispatch_1d(uint64_t items, int max_groups);
/* A level of at most this many nodes is reduced in hp_top.comp's one work
 * group (its six steps up cover 1024 nodes: 4^5 = 1024). */
#define HP_TOP_NODES 1024
/* The pyramid's programs: hp_reduce.comp, hp_downsweep.comp (a dispatch a
 * level, for the large ones) and hp_top.comp (the small levels at once). */
struct hp_programs {
	GLuint reduce, downsweep, top;
};
/* With level 0 and levels 2 .. from-1 written (bound at BIND_HP; from >=
 * 3): levels from..top by the reduction, then the prefix sum of every node
 * of levels 2..top, top down (down-sweep). */
void hp_build(const struct hp_levels *h, int from, const struct hp_programs *pr, int max_groups);

/* ---- the pipeline (pipeline.c) ---------------------------------------------- */

/* A program specialized on the code-path parameters and the field's
 * defines (key: the #define text); compiled on first use. */
struct program_variant {
	char key[VARIANT_KEY_MAX];
	GLuint prog;
	uint64_t used; /* variant_clock at its last use (LRU) */
};

struct pipeline {
	struct grid g;
	const struct field *field;     /* borrowed */
	struct program_variant variants[PROGRAM_VARIANTS];
	uint64_t variant_clock;        /* ticks at every variant lookup */
	unsigned compiles;             /* programs compiled (pipeline_compiles) */
	GLuint p_density, p_debris, p_classify, p_setup, p_vertices, p_indices;
	struct hp_programs p_hp;
	GLuint p_atomic, p_nocompact, p_finish;
	GLuint p_refine_mark;          /* the refine list (made at the first cut) */
	GLuint p_debris_flood;         /* the debris filter's second pass (mc_debris_flood.comp) */
	GLuint b_dens, b_signs, b_hp, b_tables, b_verts, b_idx, b_status;
	GLuint b_watch;        /* the last run's counts, copied for a read behind watch_fence (buffers.c) */
	GLsync watch_fence;
	GLuint b_signs_raw;            /* the density pass's bits; b_signs: less debris */
	uint32_t owners, words;        /* owner cells, level-0 words */
	uint32_t sign_words;           /* each sign buffer's capacity (words) */
	GLuint b_cut;                  /* the far samples' cut bits, then the near bits: 2 sign_words words */
	GLuint b_refine;               /* the refine list (abi.h RF_*): RF_HEAD + refine_cap + sign_words words */
	GLuint b_debris;               /* the debris filter's candidates (abi.h DL_*): DL_HEAD + 2 sign_words words */
	uint32_t refine_cap;           /* its sample entries */
	struct hp_levels hp;
	uint32_t tri_cap, vert_cap;    /* HP (indexed) capacities */
	uint64_t verts_alloc;          /* vertices the vertex buffer holds */
	int max_groups;
	int max_ssbo;
	int last_mode;                 /* compaction of the last run, -1 none */
	bool said_no_ao;               /* append compaction's "no AO" said (once) */
	bool profile;                  /* glFinish + time every pass (benchmarks) */
	float density_bias;            /* subtracted from the density (LOD) */
	bool cut_pending;              /* a density slab cut far samples: the refine pass is due */
	bool filtered;                 /* b_signs holds this run's filtered bits (the refine pass ran the filter) */
	bool has_target;
	bool keep_ao, keep_sun;        /* their code stays in the vertex pass at a count of 0 (pipeline_keep_terms) */
	struct pipeline_target target;
	double pass_ms[PASS_COUNT];
};

/* ---- the programs (programs.c) ----------------------------------------------- */

/* One of the engine's own passes (not specialized); counts the compile. */
GLuint extract_program(struct pipeline *pl, const char *file, char *err, size_t errlen);
/* Program `file` with `defines`, for a field program (field) also
 * specialized on the parameters and the field's own defines; compiled on
 * first use, the PROGRAM_VARIANTS most recently used kept.  0 with err. */
GLuint extract_variant_program(struct pipeline *pl, const char *file, const char *defines, const struct params *p,
			       bool field, char *err, size_t errlen);
/* The density pass (the field's program) and the vertex pass (the field's
 * with ambient occlusion, else mc_vertices.comp) for these parameters. */
GLuint extract_density_program(struct pipeline *pl, const struct params *p, char *err, size_t errlen);
/* Whether the field's density pass cuts far samples for p (field.h
 * `cuts`), and the variant that refines them near the surface. */
bool extract_field_cuts(const struct pipeline *pl, const struct params *p);
GLuint extract_refine_program(struct pipeline *pl, const struct params *p, char *err, size_t errlen);
/* *reads_field (may be NULL): the program is the field's (its AO or sun rays read the field). */
GLuint extract_vertex_program(struct pipeline *pl, const struct params *p, bool *reads_field, char *err,
			      size_t errlen);
/* Every program of a run: all issued first (parallel compilation), then
 * taken in order into pl->p_*.  0, or -1 with err. */
int extract_create_programs(struct pipeline *pl, const struct params *p, char *err, size_t errlen);

/* ---- the buffers (buffers.c) ------------------------------------------------ */

/* Output capacities: automatic = 16 triangles per cell of the largest
 * face, at least 64 Ki, within what the field can ask for and the GL
 * buffer limit (pl->tri_cap, pl->vert_cap). */
void extract_plan_capacities(struct pipeline *pl, const struct params *p);
/* The sign buffer's capacity in words for grid g. */
uint32_t extract_sign_words(const struct grid *g);
/* The densities, sign bits and HistoPyramid (released between runs by
 * pipeline_release_field); then also the outputs, status and tables.
 * 0, or -1 with err. */
int extract_field_buffers(struct pipeline *pl, char *err, size_t errlen);
int extract_create_buffers(struct pipeline *pl, char *err, size_t errlen);
/* The vertex buffer grown to hold verts (with its canary).  0, or -1 with err. */
int extract_vertex_room(struct pipeline *pl, uint64_t verts, char *err, size_t errlen);

/* A shader storage buffer of size bytes (at least 4), data may be NULL. */
GLuint extract_buffer(GLsizeiptr size, const void *data, GLenum usage);

/* ---- read-back (buffers.c) ------------------------------------------------- */

/* size bytes of buf at off into out.  0 or -1. */

#endif
