/* isoterra — uniform locations per program, looked up once.  The passes
 * set the same uniforms on the same programs for every block of every
 * frame (the grid's, the pyramid's, the 90-odd shader parameters): by name
 * that was 69 309 glGetUniformLocation calls in the world's first frame at
 * 320x180, about 840 in each frame after it (docs/PERFORMANCE.md).  A location stays valid until the program is
 * linked again, so the loader (shader.c) and the live editor's relink
 * (shader_watch.c) forget a program's entry whenever they (re)link one; a
 * deleted program's name comes back only through the loader. */
#include "gpu.h"
#include "gpu_int.h"
#include "core.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define UC_PROGRAMS 64 /* programs remembered; the least recently used goes */
#define UC_NAMED 48    /* names per program besides the parameters */

struct uc_entry {
	GLuint prog;
	uint64_t used;
	GLint *param;      /* per param_table entry: its u_<name>, UC_UNKNOWN before the first look */
	const char *name[UC_NAMED];
	GLint loc[UC_NAMED];
	int nnamed;
};
#define UC_UNKNOWN (-2)

static struct uc_entry uc[UC_PROGRAMS];
static uint64_t uc_clock;
static struct uc_entry *uc_last; /* a pass sets several uniforms of one program in a row */

static void entry_free(struct uc_entry *e)
{
	free(e->param);
	memset(e, 0, sizeof(*e));
}

void uniform_cache_forget(GLuint prog)
{
	uc_last = NULL;
	for (int i = 0; i < UC_PROGRAMS; i++)
		if (uc[i].prog == prog && prog)
			entry_free(&uc[i]);
}

/* prog's entry, made on first use (NULL when out of memory: no caching). */
static struct uc_entry *entry(GLuint prog)
{
	struct uc_entry *victim = &uc[0];
	uc_clock++;
	if (uc_last && uc_last->prog == prog) {
		uc_last->used = uc_clock;
		return uc_last;
	}
	for (int i = 0; i < UC_PROGRAMS; i++) {
		if (uc[i].prog == prog) {
			uc[i].used = uc_clock;
			return uc_last = &uc[i];
		}
		if (!uc[i].prog || (victim->prog && uc[i].used < victim->used))
			victim = &uc[i];
	}
	entry_free(victim);
	uc_last = NULL;
	victim->param = malloc(param_count * sizeof(GLint));
	if (!victim->param)
		return NULL;
	for (size_t i = 0; i < param_count; i++)
		victim->param[i] = UC_UNKNOWN;
	victim->prog = prog;
	victim->used = uc_clock;
	return uc_last = victim;
}

GLint gpu_uniform(GLuint prog, const char *name)
{
	struct uc_entry *e = entry(prog);
	if (!e)
		return glGetUniformLocation(prog, name);
	/* by pointer first: a call site passes the same literal every time */
	for (int i = 0; i < e->nnamed; i++)
		if (e->name[i] == name)
			return e->loc[i];
	for (int i = 0; i < e->nnamed; i++)
		if (!strcmp(e->name[i], name))
			return e->loc[i];
	GLint loc = glGetUniformLocation(prog, name);
	/* names are the callers' string literals: kept by pointer */
	if (e->nnamed < UC_NAMED) {
		e->name[e->nnamed] = name;
		e->loc[e->nnamed++] = loc;
	}
	return loc;
}

void gpu_set_param_uniforms(GLuint prog, const struct params *p)
{
	struct uc_entry *e = entry(prog);
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (!(pi->flags & P_SHADER))
			continue;
		GLint loc = e ? e->param[i] : UC_UNKNOWN;
		if (loc == UC_UNKNOWN) {
			char name[80];
			snprintf(name, sizeof(name), "u_%s", pi->name);
			loc = glGetUniformLocation(prog, name);
			if (e)
				e->param[i] = loc;
		}
		if (loc < 0)
			continue;
		if (pi->type == PT_FLOAT)
			glProgramUniform1f(prog, loc, (float)params_get_number(p, pi));
		else
			glProgramUniform1i(prog, loc, (int)params_get_number(p, pi));
	}
}
