/* isoterra — the host side of the terrain's density bound
 * (shaders/density_bound.glsl): which states it covers, and the bound of a
 * run of octaves (density_bound.h). */
#include "density_bound.h"
#include "edit.h"

#include <math.h>

/* |perlin| <= 1.1 and |texture basis| <= 0.864 (values in [-1, 1] times
 * NOISE_TEX_GAIN, trilinear); shaders/density_bound.glsl, NOISE_BOUND_MAX */
#define PERLIN_MAX 1.1f
#define TEXTURE_MAX 0.864f
#define NOISE_MEAN_ABS 0.2205f

bool density_bound_supported(const struct params *p, const struct edits *ed)
{
	if (p->field != FIELD_TERRAIN || p->noise != NOISE_ALU || p->scroll_speed != 0.0f)
		return false;
	if (p->fractal != FRACTAL_GEISS && p->fractal != FRACTAL_FBM && p->fractal != FRACTAL_TURBULENCE)
		return false;
	if (ed && (ed->quads.nquads > 0 || ed->hm.w > 0 || ed->control.w > 0))
		return false;
	return true;
}

float density_octaves_bound(const struct params *p, int from, int to)
{
	if (p->fractal != FRACTAL_GEISS && p->fractal != FRACTAL_FBM && p->fractal != FRACTAL_TURBULENCE)
		return -1.0f;
	float vmax = p->noise == NOISE_ALU ? PERLIN_MAX : TEXTURE_MAX;
	if (p->fractal == FRACTAL_TURBULENCE)
		vmax -= NOISE_MEAN_ABS; /* |n| - E|n| */
	float step = p->fractal == FRACTAL_FBM ? powf(p->lacunarity, -p->hurst) : p->gain;
	float w = 1.0f, sum = 0.0f;
	for (int i = 0; i < to; i++) {
		if (i >= from)
			sum += w;
		w *= step;
	}
	return fabsf(p->noise_amp) * sum * vmax;
}
