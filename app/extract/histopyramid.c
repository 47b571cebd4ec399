/* isoterra — the HistoPyramid's host side (Dyken & Ziegler, in a 1D,
 * 4-to-1 form; docs/PIPELINE.md): the level plan, the reduction up to the
 * totals (hp_reduce.comp) and the down-sweep of the prefix sums
 * (hp_downsweep.comp), the small levels of both in one work group
 * (hp_top.comp).  The extraction (pipeline.c) builds its pyramid over
 * the classified cells with hp_build(); hp_selftest() builds one over given
 * level-0 bytes with the very same calls. */
#include "extract_int.h"
#include "gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void hp_plan(struct hp_levels *h, uint32_t words, uint32_t keys)
{
	memset(h, 0, sizeof(*h));
	int k = 1;
	h->n[1] = words ? words : 1;
	while (h->n[k] > 1 || k < 2) { /* level 2 at least: it holds the totals when it is the top */
		h->n[k + 1] = div_up(h->n[k], 4);
		k++;
	}
	h->top = k;
	/* level 0: four words (two nodes) a level-2 node, the last one's
	 * words past the grid zero; level 1 is not stored (shaders/hp.glsl) */
	h->l0 = 2 * h->n[2];
	uint32_t o = h->l0;
	for (int i = 2; i <= k; i++) {
		h->pad[i] = i < k ? 4 * h->n[i + 1] : 1;
		h->off[i] = o;
		o += h->pad[i];
	}
	/* the prefix sums of levels 2..top */
	h->pre_base = o - h->off[2];
	/* then a hint per WG_SIZE keys (the last one's next: one more) */
	h->hint = o + (o - h->off[2]);
	h->hint_n = div_up(keys, WG_SIZE) + 1;
	h->nodes = h->hint + h->hint_n;
}

void hp_set_uniforms(GLuint prog, const struct hp_levels *h)
{
	/* a program without one of them gets location -1, which GL ignores */
	glProgramUniform1uiv(prog, gpu_uniform(prog, "u_hp_off"), HP_MAX_LEVELS, h->off);
	glProgramUniform1i(prog, gpu_uniform(prog, "u_hp_top"), h->top);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_pre_base"), h->pre_base);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_hp_n2"), h->n[2]);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_hint_base"), h->hint);
	glProgramUniform1ui(prog, gpu_uniform(prog, "u_hint_n"), h->hint_n);
}

void hp_dispatch_1d(uint64_t items, int max_groups)
{
	uint32_t groups = div_up(items, WG_SIZE);
	if (!groups)
		return;
	uint32_t gx = groups < (uint32_t)max_groups ? groups : (uint32_t)max_groups;
	glDispatchCompute(gx, div_up(groups, gx), 1);
}

void hp_build(const struct hp_levels *h, int from, const struct hp_programs *pr, int max_groups)
{
	/* the large levels a dispatch each, from the first that fits one work
	 * group on in hp_top.comp (at most six levels there) */
	int first = from;
	while (first <= h->top && (h->n[first] > HP_TOP_NODES || h->top - first > 5))
		first++;
	int down_last = first - 1 > 2 ? first - 1 : 2;
	hp_set_uniforms(pr->reduce, h);
	GLint l_level = gpu_uniform(pr->reduce, "u_level");
	GLint l_count = gpu_uniform(pr->reduce, "u_count");
	GLint l_pad = gpu_uniform(pr->reduce, "u_padded");
	glUseProgram(pr->reduce);
	for (int k = from; k < first; k++) {
		glProgramUniform1i(pr->reduce, l_level, k);
		glProgramUniform1ui(pr->reduce, l_count, h->n[k]);
		glProgramUniform1ui(pr->reduce, l_pad, h->pad[k]);
		hp_dispatch_1d(h->pad[k], max_groups);
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	}

	/* the small levels up, the top's prefix (0) and down to down_last */
	hp_set_uniforms(pr->top, h);
	glProgramUniform1i(pr->top, gpu_uniform(pr->top, "u_first"), first);
	glProgramUniform1i(pr->top, gpu_uniform(pr->top, "u_down_last"), down_last);
	glProgramUniform1uiv(pr->top, gpu_uniform(pr->top, "u_hp_n"), HP_MAX_LEVELS, h->n);
	glProgramUniform1uiv(pr->top, gpu_uniform(pr->top, "u_hp_pad"), HP_MAX_LEVELS, h->pad);
	glUseProgram(pr->top);
	glDispatchCompute(1, 1, 1);

	/* prefix sums of the large levels, down to level 2 (a cell's prefix
	 * adds the words before its own in its level-2 node: shaders/hp.glsl) */
	hp_set_uniforms(pr->downsweep, h);
	glUseProgram(pr->downsweep);
	GLint l_lev = gpu_uniform(pr->downsweep, "u_level");
	GLint l_cnt = gpu_uniform(pr->downsweep, "u_count");
	for (int k = down_last - 1; k >= 2; k--) { /* an invocation a parent */
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
		glProgramUniform1i(pr->downsweep, l_lev, k);
		glProgramUniform1ui(pr->downsweep, l_cnt, h->n[k + 1]);
		hp_dispatch_1d(h->n[k + 1], max_groups);
	}
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

/* ---- the self-test hook ------------------------------------------------------ */

struct hp_test {
	struct hp_levels h;
	int max_groups;
	uint32_t words;
	GLuint prog;               /* hp_test.comp */
	struct hp_programs pr;
	GLuint b_hp, b_out;
};

static void hp_test_free(struct hp_test *t)
{
	glUseProgram(0);
	GLuint bufs[2] = { t->b_hp, t->b_out };
	for (int i = 0; i < 2; i++)
		if (bufs[i])
			glDeleteBuffers(1, &bufs[i]);
	GLuint progs[4] = { t->prog, t->pr.reduce, t->pr.downsweep, t->pr.top };
	for (int i = 0; i < 4; i++)
		if (progs[i])
			glDeleteProgram(progs[i]);
}

/* Programs, the level-0 words from the bytes, the pyramid and the output
 * buffer (outn keys or prefixes of 8 bytes). */
static int hp_test_setup(struct hp_test *t, const uint8_t *bytes, uint32_t n, uint32_t outn, uint32_t hint_keys,
			 char *err, size_t errlen)
{
	glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &t->max_groups);
	if (t->max_groups <= 0)
		t->max_groups = 65535;
	t->words = div_up(n, 4);
	hp_plan(&t->h, t->words, hint_keys ? hint_keys : outn);
	if (!(t->prog = gpu_compute_program("hp_test.comp", NULL, err, errlen)) ||
	    !(t->pr.reduce = gpu_compute_program("hp_reduce.comp", NULL, err, errlen)) ||
	    !(t->pr.downsweep = gpu_compute_program("hp_downsweep.comp", NULL, err, errlen)) ||
	    !(t->pr.top = gpu_compute_program("hp_top.comp", NULL, err, errlen)))
		return -1;
	/* level 0 as the pipeline leaves it: zero past the last word, to the
	 * end of its last level-2 node's four */
	uint32_t *words = calloc((size_t)t->h.l0 * 2, 4);
	if (!words) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (uint32_t i = 0; i < n; i++)
		words[i / 4] |= (uint32_t)bytes[i] << (8 * (i % 4));
	/* level 0 at the start of the pyramid's buffer */
	t->b_hp = extract_buffer((GLsizeiptr)t->h.nodes * 8, NULL, GL_DYNAMIC_COPY);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, t->b_hp);
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)t->h.l0 * 8, words);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	free(words);
	t->b_out = extract_buffer((GLsizeiptr)(outn ? outn : 1) * 8, NULL, GL_DYNAMIC_COPY);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_HP, t->b_hp);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, t->b_out);
	return 0;
}

/* Runs hp_test.comp in mode (0 level 2, 1 traversal, 2 prefix sums) over
 * count items. */
static void hp_test_pass(const struct hp_test *t, int mode, uint32_t count)
{
	glUseProgram(t->prog);
	glProgramUniform1i(t->prog, gpu_uniform(t->prog, "u_mode"), mode);
	glProgramUniform1ui(t->prog, gpu_uniform(t->prog, "u_n"), count);
	hp_dispatch_1d(count, t->max_groups);
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

int hp_selftest(const uint8_t *bytes, uint32_t n, int comp, uint32_t hint_keys, uint32_t total[2], uint32_t *key_cell,
		uint32_t *key_rank, uint32_t *prefix, uint32_t *prefix_fast, char *err, size_t errlen)
{
	struct hp_test t;
	memset(&t, 0, sizeof(t));
	size_t room = (size_t)n * (comp == 0 ? 5 : 3);
	uint32_t *tmp = malloc(8 * (room ? room : 1));
	int rc = tmp ? hp_test_setup(&t, bytes, n, (uint32_t)room, hint_keys, err, errlen) : -1;
	if (!tmp)
		snprintf(err, errlen, "out of memory");
	uint32_t top[2] = { 0, 0 };
	if (rc == 0) {
		hp_set_uniforms(t.prog, &t.h);
		glProgramUniform1ui(t.prog, gpu_uniform(t.prog, "u_words"), t.words);
		glProgramUniform1i(t.prog, gpu_uniform(t.prog, "u_comp"), comp);
		hp_test_pass(&t, 0, t.h.pad[2]); /* level 2 from the words */
		hp_build(&t.h, 3, &t.pr, t.max_groups);
		rc = gpu_read_buffer(t.b_hp, (GLintptr)t.h.off[t.h.top] * 8, 8, top);
	}
	if (rc == 0) {
		total[0] = top[0];
		total[1] = top[1];
		if (top[comp] > room) {
			snprintf(err, errlen, "hp_selftest: total %u exceeds %zu (bad level-0 bytes?)", top[comp], room);
			rc = -1;
		}
	}
	if (rc == 0) {
		hp_test_pass(&t, 1, top[comp]); /* every output key -> (cell, rank) */
		rc = gpu_read_buffer(t.b_out, 0, (GLsizeiptr)top[comp] * 8, tmp);
		for (uint32_t i = 0; rc == 0 && i < top[comp]; i++) {
			key_cell[i] = tmp[2 * i];
			key_rank[i] = tmp[2 * i + 1];
		}
	}
	if (rc == 0) {
		hp_test_pass(&t, 2, n); /* every cell's prefix, both ways */
		rc = gpu_read_buffer(t.b_out, 0, (GLsizeiptr)n * 8, tmp);
		for (uint32_t i = 0; rc == 0 && i < n; i++) {
			prefix[i] = tmp[2 * i];
			if (prefix_fast)
				prefix_fast[i] = tmp[2 * i + 1];
		}
	}
	free(tmp);
	hp_test_free(&t);
	if (rc == 0 && gpu_check("hp_selftest") < 0)
		rc = -1;
	return rc;
}
