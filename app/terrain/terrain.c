/* isoterra — the terrain field provider: binds the noise (textures
 * TEX_NOISE0..2, uniform block UBIND_NOISE) and the edits (curve SSBOs,
 * heightmap texture) for shaders/density.comp and sets their uniforms;
 * specializes the program on what the edit state holds (HAS_CURVES), and
 * gives the edit state the ground that 2D curves follow (a CPU search of
 * the density's top surface). */
#include "terrain.h"
#include "noise.h"
#include "gpu.h"
#include "core.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

struct terrain {
	struct field field;
	struct edits *ed;   /* borrowed */
	struct noise_set ns;
	struct noise_gl ng;
	bool noise_ready;
	struct noise_set cpu_ns; /* the ground search's (CPU) noise */
	int cpu_seed;
	bool cpu_ready;
};

/* The ground search: from GROUND_TOP down in steps of GROUND_STEP to the
 * first rock, then bisection. */
#define GROUND_TOP 256.0f
#define GROUND_STEP 0.5f

/* edits_ground_fn: the top surface of the unedited field under (x, z) --
 * the heightmap's height (with its fractal detail) for field=heightmap,
 * else the highest air-to-rock crossing of density_ref between
 * -GROUND_TOP and GROUND_TOP. */
static bool terrain_ground(void *ctx, const struct params *p, const struct edits *ed, float x, float z, float *y)
{
	struct terrain *t = ctx;
	if (!t->cpu_ready || t->cpu_seed != p->seed) {
		noise_set_init(&t->cpu_ns, p->seed);
		t->cpu_seed = p->seed;
		t->cpu_ready = true;
	}
	if (p->field == FIELD_HEIGHTMAP) {
		*y = heightmap_ref_height(ed, p, &t->cpu_ns, x, z, true);
		return ed->hm.w > 0;
	}
	float hi = GROUND_TOP;
	if (density_ref(p, &t->cpu_ns, NULL, x, hi, z) >= p->iso)
		return false; /* rock at the top: no surface to find */
	for (float lo = hi - GROUND_STEP; lo >= -GROUND_TOP; hi = lo, lo -= GROUND_STEP) {
		if (density_ref(p, &t->cpu_ns, NULL, x, lo, z) < p->iso)
			continue;
		for (int i = 0; i < 24; i++) { /* air at hi, rock at lo */
			float mid = 0.5f * (lo + hi);
			if (density_ref(p, &t->cpu_ns, NULL, x, mid, z) >= p->iso)
				lo = mid;
			else
				hi = mid;
		}
		*y = 0.5f * (lo + hi);
		return true;
	}
	return false;
}

/* The noise for this seed: uploaded on first use and when the seed changes. */
static int noise_for(struct terrain *t, int seed, char *err, size_t errlen)
{
	if (t->noise_ready && t->ng.seed == seed)
		return 0;
	if (t->noise_ready)
		noise_gl_destroy(&t->ng);
	t->noise_ready = false;
	noise_set_init(&t->ns, seed);
	if (noise_gl_init(&t->ng, &t->ns, err, errlen) < 0)
		return -1;
	t->noise_ready = true;
	return 0;
}

/* The sum of the first n octaves' weights (fbm (f_i/f_0)^-H, geiss and
 * turbulence gain^i), from octave `from` on. */
static double octave_weights(const struct params *p, int from)
{
	double w = 1.0, tail = 0.0;
	double step = p->fractal == FRACTAL_FBM ? pow(p->lacunarity, -p->hurst) : p->gain;
	for (int i = 0; i < p->octaves; i++, w *= step)
		if (i >= from)
			tail += w;
	return tail;
}

/* How far into the rock ambient occlusion's factors are 0 (ao.glsl). */
static double ao_reach(const struct params *p)
{
	double rock = 0.0;
	if (p->ao_short_k > 0.0f)
		rock = fmax(rock, 1.0 / p->ao_short_k);
	if (p->ao_long_k > 0.0f)
		rock = fmax(rock, 1.0 / p->ao_long_k);
	return rock;
}

/* The density pass may leave out the finest octaves of far samples
 * (field.h `cuts`; shaders/fractal.glsl cut_far) for the fractal sums
 * whose octaves add terms of known bounds, without curves (their carve
 * is not weighed there) and for the terrain field only; and where it
 * pays: a sample is cut before octave CUT_LAST_OCTAVE + 1 (abi.h) at the
 * latest, when it is farther from the iso level than the octaves left can
 * move it (and, in rock, than ambient occlusion reaches).  When five of
 * that margin and the reach exceed the grid's height, too few samples are
 * that far for the test and the refine passes to pay (measured on
 * llvmpipe: the default field at 128^3, 43 units high against a margin of
 * 8.1, gained nothing from the cut, 47.5 against 47.2 ms; the benchmark
 * field, 32 high against 2.2, 8 % faster still; with a bound of 1.5 the
 * default field's margin was 11 and the cut 4 % slower). */
static bool terrain_cuts(void *ctx, const struct params *p, const struct grid *g)
{
	struct terrain *t = ctx;
	bool sum = p->fractal == FRACTAL_FBM || p->fractal == FRACTAL_GEISS || p->fractal == FRACTAL_TURBULENCE;
	bool curves = t->ed->quads.nquads > 0 && t->ed->hash.pivot;
	if (!p->density_cut || p->field != FIELD_TERRAIN || !sum || p->octaves < 2 || p->noise_amp == 0.0f || curves)
		return false;
	double margin = CUT_NOISE_BOUND * fabs(p->noise_amp) * octave_weights(p, CUT_LAST_OCTAVE);
	return 5.0 * margin + ao_reach(p) <= (double)g->ny * g->cell;
}

static void set_fractal_uniforms(GLuint prog, const struct params *p)
{
	glProgramUniform1f(prog, gpu_uniform(prog, "u_fractal_hstep"), powf(p->lacunarity, -p->hurst));
	glProgramUniform1f(prog, gpu_uniform(prog, "u_cut_tail"), (float)(octave_weights(p, 0) * 1.001 + 1e-6));
	glProgramUniform1f(prog, gpu_uniform(prog, "u_cut_rock"), (float)ao_reach(p));
}

static int terrain_bind(void *ctx, GLuint prog, const struct params *p, char *err, size_t errlen)
{
	struct terrain *t = ctx;
	if (noise_for(t, p->seed, err, errlen) < 0)
		return -1;
	noise_gl_bind(&t->ng);
	set_fractal_uniforms(prog, p);
	return edits_gl_bind(t->ed, prog, p, err, errlen);
}

/* The edit state's switches: HAS_CURVES 0 compiles the carve out
 * (shaders/carve.glsl), HAS_TUNNELS 0 its tunnels' walk, HAS_CONTROL_MAP
 * 1 reads the control map file instead of painting it with noise.  The state is brought in line with p first (the
 * curves file loaded or dropped), so the program chosen matches what bind
 * uploads.  The heightmap needs no switch: its code is compiled only for
 * field=heightmap (a specialized enum), which requires a map. */
static int terrain_defines(void *ctx, const struct params *p, char *buf, size_t len, char *err, size_t errlen)
{
	struct terrain *t = ctx;
	if (edits_load(t->ed, p, err, errlen) < 0)
		return -1;
	bool curves = t->ed->quads.nquads > 0 && t->ed->hash.pivot;
	int n = snprintf(buf, len, "#define HAS_CURVES %d\n#define HAS_TUNNELS %d\n#define HAS_CONTROL_MAP %d\n", curves,
			 curves && edits_has_tunnels(t->ed), t->ed->control.w > 0);
	return n < 0 || (size_t)n >= len ? -1 : n;
}

struct terrain *terrain_create(struct edits *ed)
{
	if (!ed)
		return NULL;
	struct terrain *t = calloc(1, sizeof(*t));
	if (!t)
		return NULL;
	t->ed = ed;
	t->field.program = "density.comp";
	t->field.bind = terrain_bind;
	t->field.defines = terrain_defines;
	t->field.cuts = terrain_cuts;
	t->field.ctx = t;
	edits_set_ground(ed, terrain_ground, t);
	return t;
}

void terrain_destroy(struct terrain *t)
{
	if (!t)
		return;
	if (t->noise_ready)
		noise_gl_destroy(&t->ng);
	if (t->ed->ground_ctx == t)
		edits_set_ground(t->ed, NULL, NULL);
	free(t);
}

const struct field *terrain_field(const struct terrain *t)
{
	return t ? &t->field : NULL;
}
