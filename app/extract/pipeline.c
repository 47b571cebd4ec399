/* isoterra — host side of the GPU terrain pipeline.
 *
 *   density.comp      density at (n+3)^3 corners (one-sample margin)
 *   mc_classify.comp  per owner cell: triangle count + owned-vertex mask
 *                     -> HistoPyramid level 0 (bytes) and level 1 (sums)
 *   hp_reduce.comp    level k = sums of four level k-1 nodes, to the top
 *   mc_setup.comp     totals -> clamp to capacity -> indirect commands
 *   mc_vertices.comp  one invocation per shared vertex (indirect dispatch)
 *   mc_indices.comp   one invocation per triangle (indirect dispatch)
 *   -> glDrawElementsIndirect by the renderer.
 * Comparison methods: mc_atomic.comp (atomic append, unshared vertices)
 * and mc_nocompact.comp (15 vertices per cell), both closed by
 * mc_finish.comp and drawn with glDrawArraysIndirect. */
#include "pipeline.h"
#include "util.h"
#include "gpu.h"
#include "abi.h"
#include "clock.h"
#include "log.h"
#include "mc.h"
#include "noise.h"
#include "edits.h" /* curves + heightmap (issue 6) */

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAX_LEVELS 16
#define GUARD_BYTES 1024u   /* canary after every output buffer */
#define GUARD_WORD 0xa5c3e1f7u

#define DENSITY_VARIANTS 12
#include <time.h>

/* Density programs specialized on the code-path parameters (fractal family,
 * noise source, shape, ...), compiled on first use and kept. */
struct density_variant {
	char key[512];
	GLuint prog;
};

struct pipeline {
	struct grid g;
	struct density_variant variants[DENSITY_VARIANTS];
	int next_variant;
	GLuint p_density, p_classify, p_reduce, p_downsweep, p_setup, p_vertices, p_indices;
	GLuint p_atomic, p_nocompact, p_finish;
	GLuint b_dens, b_l0, b_hp, b_tables, b_verts, b_idx, b_status;
	struct noise_set *ns;
	struct noise_gl ng;
	bool noise_ready;
	uint32_t owners, words;
	int top;
	uint32_t n[MAX_LEVELS], pad[MAX_LEVELS], off[MAX_LEVELS];
	uint32_t hp_nodes;             /* prefix sums start here */
	uint32_t tri_cap, vert_cap;    /* HP (indexed) capacities */
	uint64_t verts_alloc;          /* vertices the vertex buffer holds */
	int max_groups;
	int max_ssbo;
	int last_mode;
	bool profile;                  /* glFinish + time every pass (benchmarks) */
	float density_bias;            /* subtracted from the density (LOD) */
	bool has_target;
	struct pipeline_target target;
	double pass_ms[PASS_COUNT];
};

void grid_from_params(struct grid *g, const struct params *p)
{
	memset(g, 0, sizeof(*g));
	g->nx = g->nz = p->grid;
	g->ny = (int)lroundf((float)p->grid * p->vol_height);
	if (g->ny < 2)
		g->ny = 2;
	g->cell = p->vol_size / (float)p->grid;
	g->origin[0] = p->vol_x - 0.5f * p->vol_size;
	g->origin[1] = p->vol_y - 0.5f * g->cell * (float)g->ny;
	g->origin[2] = p->vol_z - 0.5f * p->vol_size;
}

/* With profiling on, waits for the GPU and charges the time since the last
 * mark to pass `which`. */
static void mark(struct pipeline *pl, int which, double *t)
{
	if (!pl->profile)
		return;
	glFinish();
	double n = clock_ms();
	pl->pass_ms[which] += n - *t;
	*t = n;
}

void pipeline_profile(struct pipeline *pl, bool on, double ms[PASS_COUNT])
{
	if (ms)
		memcpy(ms, pl->pass_ms, sizeof(pl->pass_ms));
	memset(pl->pass_ms, 0, sizeof(pl->pass_ms));
	pl->profile = on;
}

static uint32_t div_up(uint64_t a, uint64_t b) { return (uint32_t)((a + b - 1) / b); }

static void dispatch_1d(const struct pipeline *pl, uint64_t items)
{
	uint32_t groups = div_up(items, 64);
	if (!groups)
		return;
	uint32_t gx = groups < (uint32_t)pl->max_groups ? groups : (uint32_t)pl->max_groups;
	glDispatchCompute(gx, div_up(groups, gx), 1);
}

static void set_common(const struct pipeline *pl, GLuint prog, const struct params *p)
{
	glProgramUniform3i(prog, glGetUniformLocation(prog, "u_cells"), pl->g.nx, pl->g.ny, pl->g.nz);
	glProgramUniform3f(prog, glGetUniformLocation(prog, "u_origin"), pl->g.origin[0], pl->g.origin[1], pl->g.origin[2]);
	glProgramUniform1f(prog, glGetUniformLocation(prog, "u_cell"), pl->g.cell);
	glProgramUniform3i(prog, glGetUniformLocation(prog, "u_base"), pl->g.base[0], pl->g.base[1], pl->g.base[2]);
	glProgramUniform1i(prog, glGetUniformLocation(prog, "u_margin"), grid_margin(&pl->g));
	GLint loc = glGetUniformLocation(prog, "u_hp_off");
	if (loc >= 0)
		glProgramUniform1uiv(prog, loc, MAX_LEVELS, pl->off);
	loc = glGetUniformLocation(prog, "u_hp_top");
	if (loc >= 0)
		glProgramUniform1i(prog, loc, pl->top);
	loc = glGetUniformLocation(prog, "u_pre_base");
	if (loc >= 0)
		glProgramUniform1ui(prog, loc, pl->hp_nodes);
	loc = glGetUniformLocation(prog, "u_max_groups");
	if (loc >= 0)
		glProgramUniform1ui(prog, loc, (GLuint)pl->max_groups);
	if (p)
		gpu_set_param_uniforms(prog, p);
}

void pipeline_set_target(struct pipeline *pl, const struct pipeline_target *t)
{
	pl->has_target = t != NULL;
	if (t)
		pl->target = *t;
}

void pipeline_set_grid(struct pipeline *pl, const struct grid *g, float density_bias)
{
	/* same dimensions and margin: the buffers fit */
	if (g->nx == pl->g.nx && g->ny == pl->g.ny && g->nz == pl->g.nz && g->margin_extra == pl->g.margin_extra)
		pl->g = *g;
	pl->density_bias = density_bias;
}

static void set_caps(GLuint prog, uint32_t tri_cap, uint32_t vert_cap)
{
	glProgramUniform1ui(prog, glGetUniformLocation(prog, "u_tri_cap"), tri_cap);
	glProgramUniform1ui(prog, glGetUniformLocation(prog, "u_vert_cap"), vert_cap);
}

static GLuint make_buffer(GLsizeiptr size, const void *data, GLenum usage)
{
	GLuint b = 0;
	glGenBuffers(1, &b);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
	glBufferData(GL_SHADER_STORAGE_BUFFER, size > 0 ? size : 4, data, usage);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	return b;
}

/* Level sizes: n[1] = words, n[k] = ceil(n[k-1]/4) until 1; every level but
 * the top padded to a multiple of four so a parent reads four children. */
static void plan_levels(uint32_t words, int *top, uint32_t *n, uint32_t *pad, uint32_t *off, uint32_t *total)
{
	memset(n, 0, sizeof(uint32_t) * MAX_LEVELS);
	memset(pad, 0, sizeof(uint32_t) * MAX_LEVELS);
	memset(off, 0, sizeof(uint32_t) * MAX_LEVELS);
	int k = 1;
	n[1] = words ? words : 1;
	while (n[k] > 1) {
		n[k + 1] = div_up(n[k], 4);
		k++;
	}
	*top = k;
	uint32_t o = 0;
	for (int i = 1; i <= k; i++) {
		pad[i] = i < k ? 4 * n[i + 1] : 1;
		off[i] = o;
		o += pad[i];
	}
	*total = o;
}

static int upload_tables(struct pipeline *pl)
{
	struct mc_tables tables;
	mc_tables_build(&tables);
	const struct mc_tables *t = &tables;
	/* std430: uint[256], int[256*15], ivec4[12], ivec4[8] */
	int32_t buf[256 + 256 * 15 + 12 * 4 + 8 * 4];
	int32_t *w = buf;
	for (int i = 0; i < 256; i++)
		*w++ = t->tri_count[i];
	for (int i = 0; i < 256; i++)
		for (int j = 0; j < 15; j++)
			*w++ = t->tri[i][j];
	for (int e = 0; e < 12; e++)
		for (int j = 0; j < 4; j++)
			*w++ = t->edge_owner[e][j];
	for (int c = 0; c < 8; c++) {
		for (int j = 0; j < 3; j++)
			*w++ = t->corner[c][j];
		*w++ = 0;
	}
	pl->b_tables = make_buffer(sizeof(buf), buf, GL_STATIC_DRAW);
	return 0;
}

static GLuint program(const char *file, char *err, size_t errlen)
{
	return gpu_compute_program(file, NULL, err, errlen);
}

static void write_guard(GLintptr at)
{
	uint32_t g[GUARD_BYTES / 4];
	for (size_t i = 0; i < GUARD_BYTES / 4; i++)
		g[i] = GUARD_WORD;
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, at, GUARD_BYTES, g);
}

/* A program specialized on the code-path parameters (and, for the vertex
 * pass, on whether it computes ambient occlusion); compiled on first use. */
static GLuint variant_program(struct pipeline *pl, const char *file, const struct params *p, bool ao, char *err,
			      size_t errlen)
{
	char key[512];
	int n = snprintf(key, sizeof(key), "// %s\n%s", file, ao ? "#define WITH_AO 1\n" : "");
	if (n < 0 || params_glsl_specialization(p, key + n, sizeof(key) - (size_t)n) < 0) {
		snprintf(err, errlen, "shader specialization key too long");
		return 0;
	}
	for (int i = 0; i < DENSITY_VARIANTS; i++)
		if (pl->variants[i].prog && !strcmp(pl->variants[i].key, key))
			return pl->variants[i].prog;
	GLuint prog = gpu_compute_program(file, key, err, errlen);
	if (!prog)
		return 0;
	struct density_variant *v = &pl->variants[pl->next_variant];
	pl->next_variant = (pl->next_variant + 1) % DENSITY_VARIANTS;
	if (v->prog)
		glDeleteProgram(v->prog);
	snprintf(v->key, sizeof(v->key), "%s", key);
	v->prog = prog;
	return prog;
}

static GLuint density_program(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	return variant_program(pl, "density.comp", p, false, err, errlen);
}

static int ensure_vertex_room(struct pipeline *pl, uint64_t verts, char *err, size_t errlen)
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

struct pipeline *pipeline_create(const struct grid *g, const struct params *p, char *err, size_t errlen)
{
	struct pipeline *pl = calloc(1, sizeof(*pl));
	if (!pl) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	pl->g = *g;
	pl->last_mode = -1;
	glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &pl->max_groups);
	glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &pl->max_ssbo);
	if (pl->max_groups <= 0)
		pl->max_groups = 65535;
	if (pl->max_ssbo <= 0)
		pl->max_ssbo = 1 << 27;

	uint64_t owners = (uint64_t)(g->nx + 1) * (g->ny + 1) * (g->nz + 1);
	uint64_t dens = (uint64_t)grid_dens_count(g);
	if (dens * 4 > (uint64_t)pl->max_ssbo || owners > 0x3fffffffu) {
		snprintf(err, errlen, "grid %dx%dx%d needs a %llu MB density buffer, over the GL limit (%d MB)", g->nx, g->ny,
			 g->nz, (unsigned long long)(dens * 4 >> 20), pl->max_ssbo >> 20);
		free(pl);
		return NULL;
	}
	pl->owners = (uint32_t)owners;
	pl->words = div_up(owners, 4);
	uint32_t hp_nodes;
	plan_levels(pl->words, &pl->top, pl->n, pl->pad, pl->off, &hp_nodes);
	pl->hp_nodes = hp_nodes;

	/* capacities: automatic = 16 triangles per cell of the largest face,
	 * never more than the field could ask for (5 per cell) */
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
	if (vcap > 3 * owners)
		vcap = 3 * owners;
	if (tcap * 12 > (uint64_t)pl->max_ssbo)
		tcap = (uint64_t)pl->max_ssbo / 12;
	if (vcap * VERTEX_BYTES > (uint64_t)pl->max_ssbo)
		vcap = (uint64_t)pl->max_ssbo / VERTEX_BYTES;
	pl->tri_cap = (uint32_t)(tcap ? tcap : 1);
	pl->vert_cap = (uint32_t)(vcap ? vcap : 1);

	pl->ns = malloc(sizeof(*pl->ns));
	if (!pl->ns) {
		snprintf(err, errlen, "out of memory");
		free(pl);
		return NULL;
	}
	if (!(pl->p_density = density_program(pl, p, err, errlen)) ||
	    !(pl->p_classify = program("mc_classify.comp", err, errlen)) ||
	    !(pl->p_reduce = program("hp_reduce.comp", err, errlen)) ||
	    !(pl->p_downsweep = program("hp_downsweep.comp", err, errlen)) ||
	    !(pl->p_setup = program("mc_setup.comp", err, errlen)) ||
	    !(pl->p_vertices = variant_program(pl, "mc_vertices.comp", p, p->ao_rays > 0, err, errlen)) ||
	    !(pl->p_indices = program("mc_indices.comp", err, errlen))) {
		pipeline_destroy(pl);
		return NULL;
	}
	pl->b_dens = make_buffer((GLsizeiptr)(dens * 4), NULL, GL_DYNAMIC_COPY);
	pl->b_l0 = make_buffer((GLsizeiptr)pl->words * 4, NULL, GL_DYNAMIC_COPY);
	pl->b_hp = make_buffer((GLsizeiptr)hp_nodes * 16, NULL, GL_DYNAMIC_COPY); /* pyramid + prefix sums */
	pl->b_idx = make_buffer((GLsizeiptr)pl->tri_cap * 12 + GUARD_BYTES, NULL, GL_DYNAMIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_idx);
	write_guard((GLintptr)pl->tri_cap * 12);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	uint32_t zero[ST_WORDS] = { 0 };
	pl->b_status = make_buffer(sizeof(zero), zero, GL_DYNAMIC_DRAW);
	glGenBuffers(1, &pl->b_verts);
	upload_tables(pl);
	if (gpu_check("pipeline buffers") < 0 || ensure_vertex_room(pl, pl->vert_cap, err, errlen) < 0) {
		if (!err[0])
			snprintf(err, errlen, "cannot allocate the pipeline's GPU buffers (grid %d)", g->nx);
		pipeline_destroy(pl);
		return NULL;
	}
	log_debug("pipeline: grid %dx%dx%d, %u owner cells, %d pyramid levels, capacity %u triangles / %u vertices",
		  g->nx, g->ny, g->nz, pl->owners, pl->top, pl->tri_cap, pl->vert_cap);
	return pl;
}

void pipeline_destroy(struct pipeline *pl)
{
	if (!pl)
		return;
	for (int i = 0; i < DENSITY_VARIANTS; i++)
		if (pl->variants[i].prog)
			glDeleteProgram(pl->variants[i].prog);
	GLuint progs[] = { pl->p_classify, pl->p_reduce, pl->p_downsweep, pl->p_setup,
			   pl->p_indices, pl->p_atomic, pl->p_nocompact, pl->p_finish };
	for (size_t i = 0; i < ARRAY_SIZE(progs); i++)
		if (progs[i])
			glDeleteProgram(progs[i]);
	GLuint bufs[] = { pl->b_dens, pl->b_l0, pl->b_hp, pl->b_tables, pl->b_verts, pl->b_idx, pl->b_status };
	for (size_t i = 0; i < ARRAY_SIZE(bufs); i++)
		if (bufs[i])
			glDeleteBuffers(1, &bufs[i]);
	if (pl->noise_ready)
		noise_gl_destroy(&pl->ng);
	edits_gl_release(); /* curves + heightmap (issue 6); re-uploaded on the next bind */
	free(pl->ns);
	free(pl);
}

static void bind_all(const struct pipeline *pl)
{
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_DENSITY, pl->b_dens);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_HP_BASE, pl->b_l0);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_HP_LEVELS, pl->b_hp);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_MC_TABLES, pl->b_tables);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_VERTICES, pl->b_verts);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, pl->b_idx);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_STATUS, pl->b_status);
}

int pipeline_density(struct pipeline *pl, const struct params *p)
{
	if (!pl->noise_ready || pl->ng.seed != p->seed) {
		char err[256];
		if (pl->noise_ready)
			noise_gl_destroy(&pl->ng);
		noise_set_init(pl->ns, p->seed);
		if (noise_gl_init(&pl->ng, pl->ns, err, sizeof(err)) < 0) {
			log_error("%s", err);
			pl->noise_ready = false;
			return -1;
		}
		pl->noise_ready = true;
	}
	char err[512];
	pl->p_density = density_program(pl, p, err, sizeof(err));
	if (!pl->p_density) {
		log_error("%s", err);
		return -1;
	}
	double t = clock_ms();
	bind_all(pl);
	noise_gl_bind(&pl->ng);
	set_common(pl, pl->p_density, p);
	if (edits_gl_bind(pl->p_density, p) < 0) /* curves + heightmap (issue 6) */
		return -1;
	glUseProgram(pl->p_density);
	glProgramUniform1f(pl->p_density, glGetUniformLocation(pl->p_density, "u_density_bias"), pl->density_bias);
	int m2 = 1 + 2 * grid_margin(&pl->g);
	glDispatchCompute(div_up((uint64_t)pl->g.nx + m2, 4), div_up((uint64_t)pl->g.ny + m2, 4),
			  div_up((uint64_t)pl->g.nz + m2, 4));
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	mark(pl, PASS_DENSITY, &t);
	return gpu_check("density pass");
}

static int run_hp(struct pipeline *pl, const struct params *p)
{
	double t = clock_ms();
	set_common(pl, pl->p_classify, p);
	glProgramUniform1ui(pl->p_classify, glGetUniformLocation(pl->p_classify, "u_words"), pl->words);
	glProgramUniform1ui(pl->p_classify, glGetUniformLocation(pl->p_classify, "u_words_padded"), pl->pad[1]);
	glUseProgram(pl->p_classify);
	dispatch_1d(pl, pl->pad[1]);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	mark(pl, PASS_CLASSIFY, &t);

	set_common(pl, pl->p_reduce, NULL);
	GLint l_level = glGetUniformLocation(pl->p_reduce, "u_level");
	GLint l_count = glGetUniformLocation(pl->p_reduce, "u_count");
	GLint l_pad = glGetUniformLocation(pl->p_reduce, "u_padded");
	glUseProgram(pl->p_reduce);
	for (int k = 2; k <= pl->top; k++) {
		glProgramUniform1i(pl->p_reduce, l_level, k);
		glProgramUniform1ui(pl->p_reduce, l_count, pl->n[k]);
		glProgramUniform1ui(pl->p_reduce, l_pad, pl->pad[k]);
		dispatch_1d(pl, pl->pad[k]);
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	}

	/* prefix sums, top down: the top node's prefix is 0 */
	set_common(pl, pl->p_downsweep, NULL);
	glUseProgram(pl->p_downsweep);
	{
		uint32_t zero[2] = { 0, 0 };
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_hp);
		glBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)(pl->hp_nodes + pl->off[pl->top]) * 8, 8, zero);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
		GLint l_lev = glGetUniformLocation(pl->p_downsweep, "u_level");
		GLint l_cnt = glGetUniformLocation(pl->p_downsweep, "u_count");
		for (int k = pl->top - 1; k >= 1; k--) {
			glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
			glProgramUniform1i(pl->p_downsweep, l_lev, k);
			glProgramUniform1ui(pl->p_downsweep, l_cnt, pl->n[k]);
			dispatch_1d(pl, pl->n[k]);
		}
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	}

	GLuint status = pl->b_status;
	GLintptr status_off = 0;
	set_common(pl, pl->p_setup, p);
	if (pl->has_target) {
		const struct pipeline_target *tg = &pl->target;
		glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_VERTICES, tg->vbo, tg->vbo_offset, (GLsizeiptr)tg->vert_cap * VERTEX_BYTES);
		glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, tg->ibo, tg->ibo_offset, (GLsizeiptr)tg->tri_cap * 12);
		glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_STATUS, tg->status, tg->status_offset, ST_BYTES);
		set_caps(pl->p_setup, tg->tri_cap, tg->vert_cap);
		glProgramUniform1ui(pl->p_setup, glGetUniformLocation(pl->p_setup, "u_first_index"), tg->first_index);
		glProgramUniform1ui(pl->p_setup, glGetUniformLocation(pl->p_setup, "u_base_vertex"), tg->base_vertex);
		status = tg->status;
		status_off = tg->status_offset;
	} else {
		set_caps(pl->p_setup, pl->tri_cap, pl->vert_cap);
		glProgramUniform1ui(pl->p_setup, glGetUniformLocation(pl->p_setup, "u_first_index"), 0);
		glProgramUniform1ui(pl->p_setup, glGetUniformLocation(pl->p_setup, "u_base_vertex"), 0);
	}
	glUseProgram(pl->p_setup);
	glDispatchCompute(1, 1, 1);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
	mark(pl, PASS_REDUCE, &t);

	char err[512];
	pl->p_vertices = variant_program(pl, "mc_vertices.comp", p, p->ao_rays > 0, err, sizeof(err));
	if (!pl->p_vertices) {
		log_error("%s", err);
		return -1;
	}
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, status);
	set_common(pl, pl->p_vertices, p);
	if (edits_gl_bind(pl->p_vertices, p) < 0) /* normals and AO read density() */
		return -1;
	glUseProgram(pl->p_vertices);
	glDispatchComputeIndirect(status_off + ST_DISPATCH_VERTS * 4);
	mark(pl, PASS_VERTICES, &t);
	set_common(pl, pl->p_indices, p);
	glUseProgram(pl->p_indices);
	glDispatchComputeIndirect(status_off + ST_DISPATCH_TRIS * 4);
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
	mark(pl, PASS_INDICES, &t);
	return 0;
}

static int run_append(struct pipeline *pl, const struct params *p, bool nocompact)
{
	char err[512];
	uint64_t ncells = (uint64_t)pl->g.nx * pl->g.ny * pl->g.nz;
	GLuint *prog = nocompact ? &pl->p_nocompact : &pl->p_atomic;
	if (!*prog && !(*prog = program(nocompact ? "mc_nocompact.comp" : "mc_atomic.comp", err, sizeof(err)))) {
		log_error("%s", err);
		return -1;
	}
	if (!pl->p_finish && !(pl->p_finish = program("mc_finish.comp", err, sizeof(err)))) {
		log_error("%s", err);
		return -1;
	}
	uint64_t need = nocompact ? 15 * ncells : 3 * (uint64_t)pl->tri_cap;
	if (ensure_vertex_room(pl, need, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return -1;
	}
	bind_all(pl);
	uint32_t zero = 0;
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_status);
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, ST_APPEND_COUNTER * 4, 4, &zero);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	uint32_t tcap = nocompact ? (uint32_t)(5 * ncells) : pl->tri_cap;
	set_common(pl, *prog, p);
	set_caps(*prog, tcap, 3 * tcap);
	glUseProgram(*prog);
	dispatch_1d(pl, ncells);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	set_common(pl, pl->p_finish, p);
	set_caps(pl->p_finish, tcap, 3 * tcap);
	glProgramUniform1i(pl->p_finish, glGetUniformLocation(pl->p_finish, "u_nocompact"), nocompact);
	glUseProgram(pl->p_finish);
	glDispatchCompute(1, 1, 1);
	return 0;
}

int pipeline_run(struct pipeline *pl, const struct params *p)
{
	if (pipeline_density(pl, p) < 0)
		return -1;
	int rc;
	switch (pl->has_target ? COMPACTION_HP : p->compaction) {
	case COMPACTION_ATOMIC: rc = run_append(pl, p, false); break;
	case COMPACTION_NONE: rc = run_append(pl, p, true); break;
	default: rc = run_hp(pl, p); break;
	}
	pl->last_mode = p->compaction;
	glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
			GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
	glUseProgram(0);
	if (rc < 0)
		return -1;
	return gpu_check("extraction passes");
}

void pipeline_draw_info(const struct pipeline *pl, struct pipeline_draw *d)
{
	d->vbo = pl->b_verts;
	d->indexed = pl->last_mode == COMPACTION_HP || pl->last_mode < 0;
	d->ibo = d->indexed ? pl->b_idx : 0;
	d->indirect = pl->b_status;
	d->indirect_offset = (d->indexed ? ST_DRAW_ELEMENTS : ST_DRAW_ARRAYS) * 4;
}

/* ---- read-back ------------------------------------------------------------ */

static int read_buffer(GLuint buf, GLintptr off, GLsizeiptr size, void *out)
{
	if (size <= 0)
		return 0;
	glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf);
	void *m = glMapBufferRange(GL_SHADER_STORAGE_BUFFER, off, size, GL_MAP_READ_BIT);
	if (!m) {
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
		gpu_check("glMapBufferRange");
		return -1;
	}
	memcpy(out, m, (size_t)size);
	GLboolean ok = glUnmapBuffer(GL_SHADER_STORAGE_BUFFER);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	return ok ? 0 : -1;
}

int pipeline_read_density(struct pipeline *pl, float *out)
{
	return read_buffer(pl->b_dens, 0, (GLsizeiptr)grid_dens_count(&pl->g) * 4, out);
}

int pipeline_check_guards(struct pipeline *pl)
{
	uint32_t g[GUARD_BYTES / 4];
	int bad = 0;
	if (read_buffer(pl->b_idx, (GLintptr)pl->tri_cap * 12, GUARD_BYTES, g) < 0)
		return -1;
	for (size_t i = 0; i < GUARD_BYTES / 4; i++)
		bad += g[i] != GUARD_WORD;
	if (read_buffer(pl->b_verts, (GLintptr)(pl->verts_alloc * VERTEX_BYTES), GUARD_BYTES, g) < 0)
		return -1;
	for (size_t i = 0; i < GUARD_BYTES / 4; i++)
		bad += g[i] != GUARD_WORD;
	return bad ? 1 : 0;
}

int pipeline_read_stats(struct pipeline *pl, struct extract_stats *st)
{
	uint32_t s[ST_WORDS];
	memset(st, 0, sizeof(*st));
	if (read_buffer(pl->b_status, 0, sizeof(s), s) < 0)
		return -1;
	st->triangles_needed = s[ST_TRIS_NEEDED];
	st->vertices_needed = s[ST_VERTS_NEEDED];
	st->triangles = s[ST_TRIS_WRITTEN];
	st->vertices = s[ST_VERTS_WRITTEN];
	st->triangle_capacity = s[ST_TRI_CAP];
	st->vertex_capacity = s[ST_VERT_CAP];
	st->overflow = s[ST_OVERFLOW] != 0;
	return 0;
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
	float *vb = malloc((size_t)VERTEX_BYTES * (nv ? nv : 1));
	if (!vb) {
		mesh_free(m);
		return -1;
	}
	int rc = read_buffer(pl->b_verts, 0, (GLsizeiptr)nv * VERTEX_BYTES, vb);
	if (rc == 0 && indexed)
		rc = read_buffer(pl->b_idx, 0, (GLsizeiptr)nt * 12, m->idx);
	else if (rc == 0)
		for (uint32_t i = 0; i < 3 * nt; i++)
			m->idx[i] = i;
	for (uint32_t i = 0; rc == 0 && i < nv; i++)
		for (int a = 0; a < 3; a++) {
			m->pos[3 * i + a] = vb[8 * i + a];
			m->nrm[3 * i + a] = vb[8 * i + 4 + a];
		}
	free(vb);
	if (rc < 0)
		mesh_free(m);
	return rc;
}

/* ---- HistoPyramid self-test hook ------------------------------------------ */

int hp_selftest(const uint8_t *bytes, uint32_t n, int comp, uint32_t total[2], uint32_t *key_cell,
		uint32_t *key_rank, uint32_t *prefix, uint32_t *prefix_fast, char *err, size_t errlen)
{
	struct pipeline pl;
	memset(&pl, 0, sizeof(pl));
	glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &pl.max_groups);
	if (pl.max_groups <= 0)
		pl.max_groups = 65535;
	pl.words = div_up(n, 4);
	uint32_t nodes;
	plan_levels(pl.words, &pl.top, pl.n, pl.pad, pl.off, &nodes);
	pl.hp_nodes = nodes;
	GLuint prog = gpu_compute_program("hp_test.comp", NULL, err, errlen);
	GLuint reduce = gpu_compute_program("hp_reduce.comp", NULL, err, errlen);
	GLuint down = gpu_compute_program("hp_downsweep.comp", NULL, err, errlen);
	if (!prog || !reduce || !down)
		return -1;
	uint32_t *words = calloc(pl.words ? pl.words : 1, 4);
	if (!words)
		return -1;
	for (uint32_t i = 0; i < n; i++)
		words[i / 4] |= (uint32_t)bytes[i] << (8 * (i % 4));
	GLuint b_l0 = make_buffer((GLsizeiptr)pl.words * 4, words, GL_STATIC_DRAW);
	free(words);
	GLuint b_hp = make_buffer((GLsizeiptr)nodes * 16, NULL, GL_DYNAMIC_COPY);
	uint32_t outn = n * (comp == 0 ? 5 : 3);
	GLuint b_out = make_buffer((GLsizeiptr)(outn ? outn : 1) * 8, NULL, GL_DYNAMIC_COPY);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_HP_BASE, b_l0);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_HP_LEVELS, b_hp);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_TEST_OUT, b_out);
	GLint l_mode = glGetUniformLocation(prog, "u_mode"), l_n = glGetUniformLocation(prog, "u_n");
	set_common(&pl, prog, NULL);
	glProgramUniform1ui(prog, glGetUniformLocation(prog, "u_words"), pl.words);
	glProgramUniform1i(prog, glGetUniformLocation(prog, "u_comp"), comp);
	glUseProgram(prog);
	glProgramUniform1i(prog, l_mode, 0);
	glProgramUniform1ui(prog, l_n, pl.pad[1]);
	dispatch_1d(&pl, pl.pad[1]);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	set_common(&pl, reduce, NULL);
	glUseProgram(reduce);
	for (int k = 2; k <= pl.top; k++) {
		glProgramUniform1i(reduce, glGetUniformLocation(reduce, "u_level"), k);
		glProgramUniform1ui(reduce, glGetUniformLocation(reduce, "u_count"), pl.n[k]);
		glProgramUniform1ui(reduce, glGetUniformLocation(reduce, "u_padded"), pl.pad[k]);
		dispatch_1d(&pl, pl.pad[k]);
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	}
	set_common(&pl, down, NULL);
	glUseProgram(down);
	uint32_t zero2[2] = { 0, 0 };
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, b_hp);
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)(nodes + pl.off[pl.top]) * 8, 8, zero2);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	for (int k = pl.top - 1; k >= 1; k--) {
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
		glProgramUniform1i(down, glGetUniformLocation(down, "u_level"), k);
		glProgramUniform1ui(down, glGetUniformLocation(down, "u_count"), pl.n[k]);
		dispatch_1d(&pl, pl.n[k]);
	}
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	uint32_t top[2];
	int rc = read_buffer(b_hp, (GLintptr)pl.off[pl.top] * 8, 8, top);
	if (rc == 0) {
		total[0] = top[0];
		total[1] = top[1];
	}
	size_t room = (size_t)n * (comp == 0 ? 5 : 3);
	uint32_t *tmp = malloc(8 * (room ? room : 1));
	glUseProgram(prog);
	if (rc == 0 && tmp && top[comp] <= room) {
		glProgramUniform1i(prog, l_mode, 1);
		glProgramUniform1ui(prog, l_n, top[comp]);
		dispatch_1d(&pl, top[comp]);
		rc = read_buffer(b_out, 0, (GLsizeiptr)top[comp] * 8, tmp);
		for (uint32_t i = 0; rc == 0 && i < top[comp]; i++) {
			key_cell[i] = tmp[2 * i];
			key_rank[i] = tmp[2 * i + 1];
		}
		glProgramUniform1i(prog, l_mode, 2);
		glProgramUniform1ui(prog, l_n, n);
		dispatch_1d(&pl, n);
		if (rc == 0)
			rc = read_buffer(b_out, 0, (GLsizeiptr)n * 8, tmp);
		for (uint32_t i = 0; rc == 0 && i < n; i++) {
			prefix[i] = tmp[2 * i];
			if (prefix_fast)
				prefix_fast[i] = tmp[2 * i + 1];
		}
	} else if (rc == 0) {
		snprintf(err, errlen, "hp_selftest: total %u exceeds %zu (bad level-0 bytes?)", top[comp], room);
		rc = -1;
	}
	free(tmp);
	glUseProgram(0);
	glDeleteBuffers(1, &b_l0);
	glDeleteBuffers(1, &b_hp);
	glDeleteBuffers(1, &b_out);
	glDeleteProgram(prog);
	glDeleteProgram(reduce);
	glDeleteProgram(down);
	if (rc == 0 && gpu_check("hp_selftest") < 0)
		rc = -1;
	return rc;
}
