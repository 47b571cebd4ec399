/* isoterra — the extraction engine's host side: buffers, capacities,
 * programs and the passes.
 *
 *   field program     density at every corner + margin (FIELD_PASS_DENSITY;
 *                     the field's file, main() in common.glsl)
 *   mc_classify.comp  per owner cell: triangle count + owned-vertex mask
 *                     -> HistoPyramid level 0 (bytes) and level 2 (sums
 *                     of 16; level 1 is not stored: shaders/hp.glsl)
 *   hp_reduce.comp    level k = sums of four level k-1 nodes, the large levels
 *   hp_top.comp       the small levels up to the top, and their prefix sums
 *   hp_downsweep.comp the large levels' prefix sums, down to level 2
 *                     (histopyramid.c hp_build)
 *   mc_setup.comp     totals -> clamp to capacity -> indirect commands
 *   mc_vertices.comp  one invocation per shared vertex (indirect dispatch;
 *                     with ambient occlusion the field's program,
 *                     FIELD_PASS_VERTICES)
 *   mc_indices.comp   one invocation per triangle (indirect dispatch)
 *   -> glDrawElementsIndirect by the renderer.
 * Comparison methods: mc_atomic.comp (atomic append, unshared vertices)
 * and mc_nocompact.comp (15 vertices per cell), both closed by
 * mc_finish.comp and drawn with glDrawArraysIndirect.  The programs:
 * programs.c. */
#include "extract_int.h"
#include "core.h"
#include "gpu.h"
#include "mc.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

unsigned pipeline_compiles(const struct pipeline *pl)
{
	return pl->compiles;
}

GLuint pipeline_density_program(const struct pipeline *pl)
{
	return pl->p_density;
}

static void set_common(const struct pipeline *pl, GLuint prog, const struct params *p)
{
	glProgramUniform3i(prog, gpu_uniform(prog, "u_cells"), pl->g.nx, pl->g.ny, pl->g.nz);
	glProgramUniform3f(prog, gpu_uniform(prog, "u_origin"), pl->g.origin[0], pl->g.origin[1], pl->g.origin[2]);
	glProgramUniform1f(prog, gpu_uniform(prog, "u_cell"), pl->g.cell);
	glProgramUniform3i(prog, gpu_uniform(prog, "u_base"), pl->g.base[0], pl->g.base[1], pl->g.base[2]);
	glProgramUniform1i(prog, gpu_uniform(prog, "u_margin"), grid_margin(&pl->g));
	hp_set_uniforms(prog, &pl->hp);
	GLint loc = gpu_uniform(prog, "u_max_groups");
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
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_tri_cap"), tri_cap);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_vert_cap"), vert_cap);
}

/* The field's resources and uniforms for prog.  0, or -1 with err. */
static int bind_field(struct pipeline *pl, GLuint prog, const struct params *p, char *err, size_t errlen)
{
	return pl->field->bind(pl->field->ctx, prog, p, err, errlen) == 0 ? 0 : -1;
}

struct pipeline *pipeline_create(const struct grid *g, const struct params *p, const struct field *f, char *err,
				 size_t errlen)
{
	if (!f || !f->program || !f->bind) {
		snprintf(err, errlen, "no density field to extract (out of memory?)");
		return NULL;
	}
	struct pipeline *pl = calloc(1, sizeof(*pl));
	if (!pl) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	pl->g = *g;
	pl->field = f;
	pl->last_mode = -1;
	glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &pl->max_groups);
	glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &pl->max_ssbo);
	if (pl->max_groups <= 0)
		pl->max_groups = 65535;
	if (pl->max_ssbo <= 0)
		pl->max_ssbo = 1 << 27;

	uint64_t owners = (uint64_t)(g->nx + 1) * (g->ny + 1) * (g->nz + 1);
	uint64_t dens = (uint64_t)grid_dens_count(g);
	int m2 = 1 + 2 * grid_margin(g);
	uint64_t slab_groups = div_up(div_up((uint64_t)(g->nx + m2) * (g->ny + m2), SIGN_SLAB_ALIGN) * (SIGN_SLAB_ALIGN / 32), WG_SIZE);
	if (dens * 4 > (uint64_t)pl->max_ssbo || owners > 0x3fffffffu || slab_groups > (uint64_t)pl->max_groups) {
		snprintf(err, errlen, "grid %dx%dx%d needs a %llu MB density buffer, over the GL limit (%d MB)", g->nx, g->ny,
			 g->nz, (unsigned long long)(dens * 4 >> 20), pl->max_ssbo >> 20);
		free(pl);
		return NULL;
	}
	pl->owners = (uint32_t)owners;
	pl->sign_words = extract_sign_words(g);
	/* the refine list's sample entries: a 64th of the samples, at least
	 * 64 (the default field in a 128^3 cube lists 2 333 of 2 248 091; a word
	 * entry each for the rest, abi.h RF_*: test_density's small grids
	 * take that path) */
	pl->refine_cap = (uint32_t)(dens / 64 > 64 ? dens / 64 : 64);
	pl->words = div_up(owners, 4);
	extract_plan_capacities(pl, p);
	hp_plan(&pl->hp, pl->words, pl->tri_cap > pl->vert_cap ? pl->tri_cap : pl->vert_cap);
	if ((uint64_t)pl->hp.nodes * 8 > (uint64_t)pl->max_ssbo) {
		snprintf(err, errlen, "grid %dx%dx%d needs a %llu MB HistoPyramid buffer, over the GL limit (%d MB)", g->nx,
			 g->ny, g->nz, (unsigned long long)((uint64_t)pl->hp.nodes * 8 >> 20), pl->max_ssbo >> 20);
		free(pl);
		return NULL;
	}
	if (extract_create_programs(pl, p, err, errlen) < 0 || extract_create_buffers(pl, err, errlen) < 0) {
		pipeline_destroy(pl);
		return NULL;
	}
	log_debug("pipeline: grid %dx%dx%d, %u owner cells, %d pyramid levels, capacity %u triangles / %u vertices",
		  g->nx, g->ny, g->nz, pl->owners, pl->hp.top, pl->tri_cap, pl->vert_cap);
	return pl;
}

void pipeline_destroy(struct pipeline *pl)
{
	if (!pl)
		return;
	for (int i = 0; i < PROGRAM_VARIANTS; i++)
		if (pl->variants[i].prog)
			glDeleteProgram(pl->variants[i].prog);
	GLuint progs[] = { pl->p_debris, pl->p_debris_flood, pl->p_classify, pl->p_hp.reduce, pl->p_hp.downsweep, pl->p_hp.top, pl->p_setup,
			   pl->p_indices, pl->p_atomic, pl->p_nocompact, pl->p_finish, pl->p_refine_mark };
	for (size_t i = 0; i < ARRAY_SIZE(progs); i++)
		if (progs[i])
			glDeleteProgram(progs[i]);
	GLuint bufs[] = { pl->b_dens, pl->b_signs, pl->b_signs_raw, pl->b_hp, pl->b_cut, pl->b_refine, pl->b_debris, pl->b_tables, pl->b_verts,
			  pl->b_idx, pl->b_status, pl->b_watch };
	if (pl->watch_fence)
		glDeleteSync(pl->watch_fence);
	for (size_t i = 0; i < ARRAY_SIZE(bufs); i++)
		if (bufs[i])
			glDeleteBuffers(1, &bufs[i]);
	free(pl);
}

/* Storage buffers are bound per pass, right before its dispatch: a binding
 * point is a role (abi.h), four of them, that the passes share. */
static void bind(GLuint point, GLuint buf)
{
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, point, buf);
}

/* The outputs: the target slot's ranges (the streaming world's pool) or the
 * pipeline's own buffers. */
static void bind_vertices(const struct pipeline *pl)
{
	const struct pipeline_target *tg = &pl->target;
	if (pl->has_target)
		glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_VERTICES, tg->vbo, tg->vbo_offset,
				  (GLsizeiptr)tg->vert_cap * VERTEX_BYTES);
	else
		bind(BIND_VERTICES, pl->b_verts);
}

static void bind_indices(const struct pipeline *pl)
{
	const struct pipeline_target *tg = &pl->target;
	if (pl->has_target)
		glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_INDICES, tg->ibo, tg->ibo_offset, (GLsizeiptr)tg->tri_cap * 12);
	else
		bind(BIND_INDICES, pl->b_idx);
}

/* The status block (returned, with its offset). */
static GLuint bind_status(const struct pipeline *pl, GLintptr *off)
{
	const struct pipeline_target *tg = &pl->target;
	if (pl->has_target) {
		glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_STATUS, tg->status, tg->status_offset, ST_BYTES);
		*off = tg->status_offset;
		return tg->status;
	}
	bind(BIND_STATUS, pl->b_status);
	*off = 0;
	return pl->b_status;
}

/* The density pass over z slabs z0 .. z1-1 of the density grid (its
 * margin included: 0 .. nz + 2 margin + 1). */
static int density_slabs(struct pipeline *pl, const struct params *p, int z0, int z1, char *err, size_t errlen)
{
	err[0] = 0;
	if (!pl->b_dens && extract_field_buffers(pl, err, errlen) < 0) /* released after the last run */
		return -1;
	pl->p_density = extract_density_program(pl, p, err, errlen);
	if (!pl->p_density)
		return -1;
	double t = clock_ms();
	pl->filtered = false; /* new densities: the filter is due again */
	bind(BIND_DENSITY, pl->b_dens);
	bind(BIND_SIGNS_OUT, pl->b_signs_raw); /* the debris filter reads them */
	if (extract_field_cuts(pl, p)) { /* the far samples' cut bits */
		bind(BIND_CUT, pl->b_cut);
		pl->cut_pending = true;
	}
	set_common(pl, pl->p_density, p);
	if (bind_field(pl, pl->p_density, p, err, errlen) < 0)
		return -1;
	glUseProgram(pl->p_density);
	glProgramUniform1f(pl->p_density, gpu_uniform(pl->p_density, "u_density_bias"), pl->density_bias);
	glProgramUniform1ui(pl->p_density, gpu_uniform(pl->p_density, "u_sign_words"), pl->sign_words);
	glProgramUniform1i(pl->p_density, gpu_uniform(pl->p_density, "u_z0"), z0);
	/* one z slab per row of groups; an invocation per sign word, 32
	 * samples, a slab padded to SIGN_SLAB_ALIGN bits (common.glsl) */
	int m2 = 1 + 2 * grid_margin(&pl->g);
	uint64_t slab_words = div_up((uint64_t)(pl->g.nx + m2) * (pl->g.ny + m2), SIGN_SLAB_ALIGN) * (SIGN_SLAB_ALIGN / 32);
	if (z1 > z0)
		glDispatchCompute((GLuint)div_up(slab_words, WG_SIZE), (GLuint)(z1 - z0), 1);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	mark(pl, PASS_DENSITY, &t);
	return gpu_check("density pass");
}

/* The debris filter (shaders/mc_debris.comp): the density pass's sign
 * bits (b_signs_raw) less one-sample islands and bubbles, into b_signs,
 * which classification and the index pass read; with near, also the near
 * bits for the refine pass (b_cut's second half). */
static int debris_pass(struct pipeline *pl, bool near, char *err, size_t errlen)
{
	GLuint prog = pl->p_debris;
	if (near) { /* a variant: looked up each time (the cache may have let it go) */
		prog = extract_variant_program(pl, "mc_debris.comp", "#define DEBRIS_NEAR 1\n", NULL, false, err, errlen);
		if (!prog)
			return -1;
		bind(BIND_CUT, pl->b_cut);
	}
	set_common(pl, prog, NULL);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_sign_words"), pl->sign_words);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_max_groups"), (GLuint)pl->max_groups);
	/* the candidate list's header: no entry, a dispatch of none */
	static const GLuint header[DL_HEAD] = { 0, 1, 1, 0 };
	glBindBuffer(GL_COPY_WRITE_BUFFER, pl->b_debris);
	glBufferSubData(GL_COPY_WRITE_BUFFER, 0, sizeof(header), header);
	bind(BIND_SIGNS, pl->b_signs_raw);
	bind(BIND_SIGNS_OUT, pl->b_signs);
	bind(BIND_DEBRIS, pl->b_debris);
	glUseProgram(prog);
	int m2 = 1 + 2 * grid_margin(&pl->g);
	uint64_t slab_words = div_up((uint64_t)(pl->g.nx + m2) * (pl->g.ny + m2), SIGN_SLAB_ALIGN) * (SIGN_SLAB_ALIGN / 32);
	glDispatchCompute((GLuint)div_up(slab_words, WG_SIZE), (GLuint)(pl->g.nz + m2), 1);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
	/* the listed candidates' components, from the list's header */
	set_common(pl, pl->p_debris_flood, NULL);
	glProgramUniform1ui(pl->p_debris_flood, gpu_uniform(pl->p_debris_flood, "u_sign_words"), pl->sign_words);
	glUseProgram(pl->p_debris_flood);
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pl->b_debris);
	glDispatchComputeIndirect((GLintptr)(DL_DISPATCH * 4));
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	return 0;
}

/* The filtered sign bits (b_signs) for what reads the cells' cases: the
 * plain filter, unless the refine pass's filter already made them from
 * these densities (its program is made at creation: no error to report). */
static void filtered_signs(struct pipeline *pl)
{
	if (!pl->filtered)
		debris_pass(pl, false, NULL, 0);
	pl->filtered = false;
}

/* After the last slab, when a slab was cut: the debris filter, with the
 * samples next to a sign change marked (its near bits); refine_mark.comp
 * lists the cut samples within one step of those (b_refine, abi.h RF_*);
 * the field's refine variant computes them whole from where each was cut
 * (common.glsl, DENSITY_REFINE), dispatched from the list's header: no
 * read-back.  Charged to the density pass. */
static int refine_pass(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	if (!pl->cut_pending)
		return 0;
	pl->cut_pending = false;
	GLuint prog = extract_refine_program(pl, p, err, errlen);
	if (!prog)
		return -1;
	if (!pl->p_refine_mark && !(pl->p_refine_mark = extract_program(pl, "refine_mark.comp", err, errlen)))
		return -1;
	double t = clock_ms();
	if (debris_pass(pl, true, err, errlen) < 0)
		return -1;
	pl->filtered = true;
	static const uint32_t head[RF_HEAD] = { 0, 1, 1, 0, 0, 0, 0, 0 }; /* no groups, no entries */
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_refine);
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof(head), head);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	bind(BIND_CUT, pl->b_cut);
	bind(BIND_REFINE, pl->b_refine);
	set_common(pl, pl->p_refine_mark, NULL);
	glProgramUniform1ui(pl->p_refine_mark, gpu_uniform(pl->p_refine_mark, "u_sign_words"), pl->sign_words);
	glProgramUniform1ui(pl->p_refine_mark, gpu_uniform(pl->p_refine_mark, "u_refine_cap"), pl->refine_cap);
	glProgramUniform1ui(pl->p_refine_mark, gpu_uniform(pl->p_refine_mark, "u_max_groups"), (GLuint)pl->max_groups);
	glUseProgram(pl->p_refine_mark);
	int m2 = 1 + 2 * grid_margin(&pl->g);
	uint64_t slab_words = div_up((uint64_t)(pl->g.nx + m2) * (pl->g.ny + m2), SIGN_SLAB_ALIGN) * (SIGN_SLAB_ALIGN / 32);
	glDispatchCompute((GLuint)div_up(slab_words, WG_SIZE), (GLuint)(pl->g.nz + m2), 1);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
	bind(BIND_DENSITY, pl->b_dens);
	set_common(pl, prog, p);
	if (bind_field(pl, prog, p, err, errlen) < 0)
		return -1;
	glProgramUniform1f(prog, gpu_uniform(prog, "u_density_bias"), pl->density_bias);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_refine_cap"), pl->refine_cap);
	glUseProgram(prog);
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, pl->b_refine);
	glDispatchComputeIndirect(RF_DISPATCH * 4);
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	mark(pl, PASS_DENSITY, &t);
	return gpu_check("density refine passes");
}

int pipeline_density(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	if (density_slabs(pl, p, 0, pl->g.nz + 1 + 2 * grid_margin(&pl->g), err, errlen) < 0)
		return -1;
	return refine_pass(pl, p, err, errlen);
}

/* mc_setup.comp: the totals clamped to the capacities of the output (the
 * target slot or the pipeline's own buffers) -> the indirect commands in
 * its status block (returned with its offset). */
static GLuint setup_pass(struct pipeline *pl, const struct params *p, GLintptr *status_off)
{
	set_common(pl, pl->p_setup, p);
	bind(BIND_HP, pl->b_hp);
	GLuint status = bind_status(pl, status_off);
	if (pl->has_target) {
		const struct pipeline_target *tg = &pl->target;
		set_caps(pl->p_setup, tg->tri_cap, tg->vert_cap);
		glProgramUniform1ui(pl->p_setup, gpu_uniform(pl->p_setup, "u_first_index"), tg->first_index);
		glProgramUniform1ui(pl->p_setup, gpu_uniform(pl->p_setup, "u_base_vertex"), tg->base_vertex);
	} else {
		set_caps(pl->p_setup, pl->tri_cap, pl->vert_cap);
		glProgramUniform1ui(pl->p_setup, gpu_uniform(pl->p_setup, "u_first_index"), 0);
		glProgramUniform1ui(pl->p_setup, gpu_uniform(pl->p_setup, "u_base_vertex"), 0);
	}
	glUseProgram(pl->p_setup);
	glDispatchCompute(1, 1, 1);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
	return status;
}

/* The vertex and index passes, sized by the indirect commands in status. */
static int output_passes(struct pipeline *pl, const struct params *p, GLuint status, GLintptr status_off, double *t,
			 char *err, size_t errlen)
{
	bool reads_field;
	pl->p_vertices = extract_vertex_program(pl, p, &reads_field, err, errlen);
	if (!pl->p_vertices)
		return -1;
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, status);
	set_common(pl, pl->p_vertices, p);
	/* the AO and sun rays read the field (its program's, even at a count of 0) */
	if (reads_field && bind_field(pl, pl->p_vertices, p, err, errlen) < 0)
		return -1;
	bind(BIND_DENSITY, pl->b_dens);
	bind_vertices(pl);
	glUseProgram(pl->p_vertices);
	glDispatchComputeIndirect(status_off + ST_DISPATCH_VERTS * 4);
	mark(pl, PASS_VERTICES, t);
	set_common(pl, pl->p_indices, p);
	bind(BIND_SIGNS, pl->b_signs);
	bind_indices(pl);
	glBindBufferBase(GL_UNIFORM_BUFFER, UBIND_MC_TABLES, pl->b_tables);
	glUseProgram(pl->p_indices);
	glDispatchComputeIndirect(status_off + ST_DISPATCH_TRIS * 4);
	glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
	mark(pl, PASS_INDICES, t);
	return 0;
}

/* The debris filter, classification and the HistoPyramid (the pipeline's
 * own buffers only). */
static void pyramid_passes(struct pipeline *pl, const struct params *p)
{
	double t = clock_ms();
	filtered_signs(pl);
	set_common(pl, pl->p_classify, p);
	bind(BIND_SIGNS, pl->b_signs);
	bind(BIND_HP, pl->b_hp);
	glBindBufferBase(GL_UNIFORM_BUFFER, UBIND_MC_TABLES, pl->b_tables);
	glUseProgram(pl->p_classify);
	/* an invocation: four level-0 words and the level-2 node above them
	 * (or a level-2 pad) */
	uint32_t l2 = pl->hp.pad[2];
	glProgramUniform1ui(pl->p_classify, gpu_uniform(pl->p_classify, "u_level2_nodes"), l2);
	hp_dispatch_1d(l2, pl->max_groups);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	mark(pl, PASS_CLASSIFY, &t);
	hp_build(&pl->hp, 3, &pl->p_hp, pl->max_groups);
	mark(pl, PASS_REDUCE, &t);
}

/* The indirect commands, vertices and indices into the output (the target
 * slot or the pipeline's own buffers). */
static int output_stage(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	double t = clock_ms();
	GLintptr status_off;
	GLuint status = setup_pass(pl, p, &status_off);
	mark(pl, PASS_REDUCE, &t);
	return output_passes(pl, p, status, status_off, &t, err, errlen);
}

static int run_hp(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	pyramid_passes(pl, p);
	return output_stage(pl, p, err, errlen);
}

/* The last barrier of a run: the outputs are drawn, read and copied. */
static void end_run(void)
{
	glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT | GL_COMMAND_BARRIER_BIT |
			GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
	glUseProgram(0);
}

int pipeline_run_stage(struct pipeline *pl, const struct params *p, enum pipeline_stage stage, char *err,
		       size_t errlen)
{
	err[0] = 0;
	int zs = pl->g.nz + 1 + 2 * grid_margin(&pl->g), rc = 0;
	if (!pl->b_dens && stage > PIPE_DENSITY_LO) {
		snprintf(err, errlen, "pipeline stage %d without its density: the field's buffers were released", stage);
		return -1;
	}
	switch (stage) {
	case PIPE_DENSITY_LO: return density_slabs(pl, p, 0, zs / 2, err, errlen);
	case PIPE_DENSITY_HI:
		if (density_slabs(pl, p, zs / 2, zs, err, errlen) < 0)
			return -1;
		return refine_pass(pl, p, err, errlen);
	case PIPE_PYRAMID:
		pyramid_passes(pl, p);
		glUseProgram(0);
		return gpu_check("pyramid passes");
	default:
		rc = output_stage(pl, p, err, errlen);
		pl->last_mode = COMPACTION_HP;
		end_run();
		return rc < 0 ? -1 : gpu_check("output passes");
	}
}

int pipeline_bound(struct pipeline *pl, const struct params *p, GLuint in, GLuint out, uint32_t count, char *err,
		   size_t errlen)
{
	err[0] = 0;
	if (!count)
		return 0;
	GLuint prog = extract_variant_program(pl, pl->field->program, "#define FIELD_PASS_BOUND 1\n", p, true, err, errlen);
	if (!prog)
		return -1;
	set_common(pl, prog, p);
	if (bind_field(pl, prog, p, err, errlen) < 0)
		return -1;
	glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_AUX_IN, in, 0, (GLsizeiptr)count * 32);
	glBindBufferRange(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, out, 0, (GLsizeiptr)count * 4);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_bound_count"), count);
	glUseProgram(prog);
	glDispatchCompute(count, 1, 1);
	glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
	glUseProgram(0);
	return gpu_check("coarse pre-pass");
}

/* Triangles the draw command can hold: mc_setup.comp and mc_finish.comp
 * clamp to the capacity; with no compaction every cell's five are drawn. */
static uint32_t draw_capacity(const struct pipeline *pl, bool nocompact)
{
	return nocompact ? (uint32_t)(5 * (uint64_t)pl->g.nx * pl->g.ny * pl->g.nz) : pl->tri_cap;
}

static int run_append(struct pipeline *pl, const struct params *p, bool nocompact, char *err, size_t errlen)
{
	uint64_t ncells = (uint64_t)pl->g.nx * pl->g.ny * pl->g.nz;
	GLuint *prog = nocompact ? &pl->p_nocompact : &pl->p_atomic;
	if (!*prog && !(*prog = extract_program(pl, nocompact ? "mc_nocompact.comp" : "mc_atomic.comp", err, errlen)))
		return -1;
	if (!pl->p_finish && !(pl->p_finish = extract_program(pl, "mc_finish.comp", err, errlen)))
		return -1;
	if (p->ao_rays > 0 && !pl->said_no_ao) {
		log_warn("compaction %s computes no ambient occlusion (it has no vertex pass; only hp does): "
			 "--ao-rays %d ignored", nocompact ? "none" : "atomic", p->ao_rays);
		pl->said_no_ao = true;
	}
	uint64_t need = nocompact ? 15 * ncells : 3 * (uint64_t)pl->tri_cap;
	if (extract_vertex_room(pl, need, err, errlen) < 0)
		return -1;
	/* the cells' cases from the debris filter's sign bits, as the
	 * HistoPyramid's classification reads them: the same mesh, the same
	 * filter's work */
	filtered_signs(pl);
	bind(BIND_CASE_SIGNS, pl->b_signs);
	bind(BIND_DENSITY, pl->b_dens);
	bind(BIND_VERTICES, pl->b_verts);
	bind(BIND_STATUS, pl->b_status);
	glBindBufferBase(GL_UNIFORM_BUFFER, UBIND_MC_TABLES, pl->b_tables);
	uint32_t zero = 0;
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, pl->b_status);
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, ST_APPEND_COUNTER * 4, 4, &zero);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	uint32_t tcap = draw_capacity(pl, nocompact);
	set_common(pl, *prog, p);
	set_caps(*prog, tcap, 3 * tcap);
	glUseProgram(*prog);
	hp_dispatch_1d(ncells, pl->max_groups);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	set_common(pl, pl->p_finish, p);
	set_caps(pl->p_finish, tcap, 3 * tcap);
	glProgramUniform1i(pl->p_finish, gpu_uniform(pl->p_finish, "u_nocompact"), nocompact);
	glUseProgram(pl->p_finish);
	glDispatchCompute(1, 1, 1);
	return 0;
}

int pipeline_run(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	if (pipeline_density(pl, p, err, errlen) < 0)
		return -1;
	int rc;
	switch (pl->has_target ? COMPACTION_HP : p->compaction) {
	case COMPACTION_ATOMIC: rc = run_append(pl, p, false, err, errlen); break;
	case COMPACTION_NONE: rc = run_append(pl, p, true, err, errlen); break;
	default: rc = run_hp(pl, p, err, errlen); break;
	}
	pl->last_mode = p->compaction;
	end_run();
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
	d->capacity = draw_capacity(pl, pl->last_mode == COMPACTION_NONE);
}
