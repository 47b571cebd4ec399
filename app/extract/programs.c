/* isoterra — the extraction engine's programs: its own passes, the
 * field's passes specialized on the parameters (a variant per #define
 * set, the most recently used kept), and every program of a run issued
 * together at creation (extract_int.h). */
#include "extract_int.h"
#include "core.h"
#include "gpu.h"

#include <stdio.h>
#include <string.h>

/* One of the engine's own passes (not specialized). */
GLuint extract_program(struct pipeline *pl, const char *file, char *err, size_t errlen)
{
	GLuint prog = gpu_compute_program(file, NULL, err, errlen);
	pl->compiles += prog != 0;
	return prog;
}

/* The cache key of program `file` with `defines`: for a field program
 * also the parameters' specialization (params_glsl_specialization: the
 * enum terms' values, the TERM_<NAME> switches) and the field's own
 * defines.  0, or -1 with err. */
static int variant_key(struct pipeline *pl, const char *file, const char *defines, const struct params *p, bool field,
		       char *key, size_t len, char *err, size_t errlen)
{
	int n = snprintf(key, len, "// %s\n%s", file, defines);
	size_t used = n < 0 ? len : (size_t)n;
	if (field && used < len) {
		n = params_glsl_specialization(p, key + used, len - used);
		used = n < 0 ? len : used + (size_t)n;
	}
	if (field && pl->field->defines && used < len) {
		err[0] = 0;
		n = pl->field->defines(pl->field->ctx, p, key + used, len - used, err, errlen);
		if (n < 0 && err[0])
			return -1;
		used = n < 0 ? len : used + (size_t)n;
	}
	if (used >= len) {
		snprintf(err, errlen, "shader specialization key of %s too long", file);
		return -1;
	}
	return 0;
}

/* Program `file` with `defines` (field: specialized as variant_key says);
 * compiled on first use, the PROGRAM_VARIANTS most recently used kept
 * (least recently used evicted), so a knob that switches a term on or off
 * compiles once and switching back finds the program again. */
GLuint extract_variant_program(struct pipeline *pl, const char *file, const char *defines, const struct params *p,
			      bool field, char *err, size_t errlen)
{
	char key[VARIANT_KEY_MAX];
	if (variant_key(pl, file, defines, p, field, key, sizeof(key), err, errlen) < 0)
		return 0;
	pl->variant_clock++;
	struct program_variant *victim = NULL;
	for (int i = 0; i < PROGRAM_VARIANTS; i++) {
		struct program_variant *v = &pl->variants[i];
		if (v->prog && !strcmp(v->key, key)) {
			v->used = pl->variant_clock;
			return v->prog;
		}
		if (!victim || (victim->prog && (!v->prog || v->used < victim->used)))
			victim = v;
	}
	double t0 = clock_ms();
	GLuint prog = gpu_compute_program(file, key, err, errlen);
	if (!prog)
		return 0;
	pl->compiles++;
	log_debug("pipeline: a new variant of %s, linked in %.1f ms (the driver may compile more at its first "
		  "dispatch)%s",
		  file, clock_ms() - t0, victim->prog ? "; the least recently used one evicted" : "");
	if (victim->prog)
		glDeleteProgram(victim->prog);
	snprintf(victim->key, sizeof(victim->key), "%s", key);
	victim->prog = prog;
	victim->used = pl->variant_clock;
	return prog;
}

bool extract_field_cuts(const struct pipeline *pl, const struct params *p)
{
	return pl->field->cuts && pl->field->cuts(pl->field->ctx, p, &pl->g);
}

/* The density pass's variant: with the far samples' cut where the field
 * allows it (field.h `cuts`). */
static const char *density_defines(const struct pipeline *pl, const struct params *p)
{
	return extract_field_cuts(pl, p) ? "#define FIELD_PASS_DENSITY 1\n#define DENSITY_CUT 1\n"
					 : "#define FIELD_PASS_DENSITY 1\n";
}

#define REFINE_DEFINES "#define FIELD_PASS_DENSITY 1\n#define DENSITY_REFINE 1\n"

/* The density pass: the field's program. */
GLuint extract_density_program(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	return extract_variant_program(pl, pl->field->program, density_defines(pl, p), p, true, err, errlen);
}

/* The cut samples near the surface computed whole (common.glsl). */
GLuint extract_refine_program(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	return extract_variant_program(pl, pl->field->program, REFINE_DEFINES, p, true, err, errlen);
}

/* The vertex pass's terms: AO rays, sun shadows. */
static bool ao_on(const struct params *p)
{
	return p->ao_rays > 0;
}

static bool sun_on(const struct params *p)
{
	return p->shadows > 0.0f && p->shadow_steps > 0;
}

void pipeline_keep_terms(struct pipeline *pl, const struct params *configured)
{
	pl->keep_ao = ao_on(configured);
	pl->keep_sun = sun_on(configured);
}

/* The vertex pass's variant (extract_vertex_program). */
static const char *vertex_defines(const struct pipeline *pl, const struct params *p, const char **file, bool *field)
{
	bool ao = ao_on(p) || pl->keep_ao, sun = sun_on(p) || pl->keep_sun;
	*field = ao || sun;
	*file = *field ? pl->field->program : "mc_vertices.comp";
	if (!*field)
		return "";
	/* a grid with an extra margin is a block of a larger world, whose long
	 * AO rays and sun rays evaluate the field outside it (shaders/ao.glsl,
	 * shaders/sun.glsl); a lone volume's end at its sides */
	static const char *const defs[2][2][2] = {
		{ { "", "#define FIELD_PASS_VERTICES 1\n#define WITH_SUN 1\n" },
		  { "#define FIELD_PASS_VERTICES 1\n#define WITH_AO 1\n",
		    "#define FIELD_PASS_VERTICES 1\n#define WITH_AO 1\n#define WITH_SUN 1\n" } },
		{ { "", "#define FIELD_PASS_VERTICES 1\n#define WITH_SUN 1\n#define AO_FAR_OUTSIDE 1\n" },
		  { "#define FIELD_PASS_VERTICES 1\n#define WITH_AO 1\n#define AO_FAR_OUTSIDE 1\n",
		    "#define FIELD_PASS_VERTICES 1\n#define WITH_AO 1\n#define WITH_SUN 1\n#define AO_FAR_OUTSIDE 1\n" } },
	};
	return defs[pl->g.margin_extra > 0][ao][sun];
}

/* The vertex pass: with ambient occlusion or shadows their rays read the field, so it is
 * the field's program (*reads_field, may be NULL); without, the engine's own (not specialized:
 * it reads no parameter that selects code). */
GLuint extract_vertex_program(struct pipeline *pl, const struct params *p, bool *reads_field, char *err,
			      size_t errlen)
{
	const char *file;
	bool field;
	const char *defines = vertex_defines(pl, p, &file, &field);
	if (reads_field)
		*reads_field = field;
	return extract_variant_program(pl, file, defines, p, field, err, errlen);
}

/* Issues a variant's compile and link ahead (gpu_prefetch_compute). */
static void prefetch_variant(struct pipeline *pl, const char *file, const char *defines, const struct params *p,
			     bool field)
{
	char key[VARIANT_KEY_MAX], err[256];
	if (variant_key(pl, file, defines, p, field, key, sizeof(key), err, sizeof(err)) == 0)
		gpu_prefetch_compute(file, key);
}

/* Every program of a run, issued together first: a driver with parallel
 * compilation builds them side by side (the start's largest part on a GPU
 * with empty caches), then each is taken in order. */
int extract_create_programs(struct pipeline *pl, const struct params *p, char *err, size_t errlen)
{
	static const char *const own[] = { "mc_debris.comp", "mc_debris_flood.comp", "mc_classify.comp", "hp_reduce.comp",
					   "hp_downsweep.comp", "hp_top.comp", "mc_setup.comp", "mc_indices.comp" };
	const char *vfile;
	bool vfield;
	const char *vdefs = vertex_defines(pl, p, &vfile, &vfield);
	prefetch_variant(pl, pl->field->program, density_defines(pl, p), p, true);
	if (extract_field_cuts(pl, p))
		prefetch_variant(pl, pl->field->program, REFINE_DEFINES, p, true);
	prefetch_variant(pl, vfile, vdefs, p, vfield);
	if (pl->g.margin_extra > 0) /* a world's block: the coarse pre-pass (pipeline_bound) */
		prefetch_variant(pl, pl->field->program, "#define FIELD_PASS_BOUND 1\n", p, true);
	for (size_t i = 0; i < ARRAY_SIZE(own); i++)
		gpu_prefetch_compute(own[i], NULL);
	if (!(pl->p_density = extract_density_program(pl, p, err, errlen)) ||
	    !(pl->p_debris = extract_program(pl, "mc_debris.comp", err, errlen)) ||
	    !(pl->p_debris_flood = extract_program(pl, "mc_debris_flood.comp", err, errlen)) ||
	    !(pl->p_classify = extract_program(pl, "mc_classify.comp", err, errlen)) ||
	    !(pl->p_hp.reduce = extract_program(pl, "hp_reduce.comp", err, errlen)) ||
	    !(pl->p_hp.downsweep = extract_program(pl, "hp_downsweep.comp", err, errlen)) ||
	    !(pl->p_hp.top = extract_program(pl, "hp_top.comp", err, errlen)) ||
	    !(pl->p_setup = extract_program(pl, "mc_setup.comp", err, errlen)) ||
	    !(pl->p_vertices = extract_vertex_program(pl, p, NULL, err, errlen)) ||
	    !(pl->p_indices = extract_program(pl, "mc_indices.comp", err, errlen)))
		return -1;
	return 0;
}
