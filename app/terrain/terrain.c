/* isoterra — the terrain field provider: binds the noise (textures
 * TEX_NOISE0..2, uniform block UBIND_NOISE) and the edits (curve SSBOs,
 * heightmap texture) for shaders/density.comp and sets their uniforms;
 * specializes the program on what the edit state holds (HAS_CURVES). */
#include "terrain.h"
#include "noise.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

struct terrain {
	struct field field;
	struct edits *ed;   /* borrowed */
	struct noise_set ns;
	struct noise_gl ng;
	bool noise_ready;
};

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

static int terrain_bind(void *ctx, GLuint prog, const struct params *p, char *err, size_t errlen)
{
	struct terrain *t = ctx;
	if (noise_for(t, p->seed, err, errlen) < 0)
		return -1;
	noise_gl_bind(&t->ng);
	return edits_gl_bind(t->ed, prog, p, err, errlen);
}

/* The edit state's switches: HAS_CURVES 0 compiles the carve out
 * (shaders/carve.glsl), HAS_TUNNELS 0 its tunnels' walk.  The state is brought in line with p first (the
 * curves file loaded or dropped), so the program chosen matches what bind
 * uploads.  The heightmap needs no switch: its code is compiled only for
 * field=heightmap (a specialized enum), which requires a map. */
static int terrain_defines(void *ctx, const struct params *p, char *buf, size_t len, char *err, size_t errlen)
{
	struct terrain *t = ctx;
	if (edits_load(t->ed, p, err, errlen) < 0)
		return -1;
	bool curves = t->ed->quads.nquads > 0 && t->ed->hash.pivot;
	int n = snprintf(buf, len, "#define HAS_CURVES %d\n#define HAS_TUNNELS %d\n", curves,
			 curves && edits_has_tunnels(t->ed));
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
	t->field.ctx = t;
	return t;
}

void terrain_destroy(struct terrain *t)
{
	if (!t)
		return;
	if (t->noise_ready)
		noise_gl_destroy(&t->ng);
	free(t);
}

const struct field *terrain_field(const struct terrain *t)
{
	return t ? &t->field : NULL;
}
