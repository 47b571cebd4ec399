/* isoterra — the terrain field provider: binds the noise (textures
 * TEX_NOISE0..2, uniform block UBIND_NOISE) and the edits (curve SSBOs,
 * heightmap texture) for shaders/density.comp and sets their uniforms. */
#include "terrain.h"
#include "noise.h"

#include <stdbool.h>
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
