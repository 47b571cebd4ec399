/* isoterra — CPU reference of the density function: shaders/density.glsl and
 * shaders/fractal.glsl, term by term, in plain C float (same operations in
 * the same order).  Differences to the GPU come from libm vs GLSL sin/cos/
 * pow/sqrt and FMA contraction only (~1e-6 relative), except for
 * noise=texture, where the GPU's hardware trilinear filter is approximated
 * here by exact fp32 trilinear interpolation (see tests/test_density.c). */
#include "density_ref.h"
#include "edit.h" /* curves and heightmap: carve_ref.c */

#include <math.h>

/* keep in sync with fractal.glsl */
#define NOISE_TEX_GAIN 0.864f
#define NOISE_MEAN_ABS 0.2205f
#define NOISE_MEAN_SQ 0.0734f
static const float worley_mean[4] = { 0.5205f, 0.7167f, 0.8451f, 0.9437f };
static const float octave_shift[3] = { 17.31f, -9.17f, 23.53f };
#define SLOPE_EPS 0.05f
#define PI_F 3.14159265358979f

/* FIELD_*, SHAPE_*, NOISE_*, FRACTAL_*, TERRACE_*: params_enums.h, generated
 * from params.def like the shaders' #defines */

static inline float clampf(float x, float lo, float hi)
{
	return x < lo ? lo : (x > hi ? hi : x);
}

static inline float sat(float x)
{
	return clampf(x, 0.0f, 1.0f);
}

static inline float smooth01(float t)
{
	t = clampf(t, 0.0f, 1.0f);
	return t * t * (3.0f - 2.0f * t);
}

/* ---- fractal.glsl ------------------------------------------------------- */

static void octave_point(const struct params *p, const struct noise_set *ns, const float ws[3], int i, float freq,
			 float out[3])
{
	float x = ws[0] * freq, y = ws[1] * freq, z = ws[2] * freq;
	if (i < p->rotated_octaves && i < 4) {
		const float *r = ns->rot[i];
		float rx = r[0] * x + r[1] * y + r[2] * z;
		float ry = r[3] * x + r[4] * y + r[5] * z;
		float rz = r[6] * x + r[7] * y + r[8] * z;
		x = rx;
		y = ry;
		z = rz;
	}
	float fi = (float)i;
	out[0] = x + fi * octave_shift[0];
	out[1] = y + fi * octave_shift[1];
	out[2] = z + fi * octave_shift[2];
}

static float octave_noise(const struct params *p, const struct noise_set *ns, const float q[3], int i)
{
	if (p->noise == NOISE_TEXTURE)
		return noise_tex_sample(ns, i % 3, q[0], q[1], q[2], (i / 3) & 3) * NOISE_TEX_GAIN;
	return noise_perlin(ns, q[0], q[1], q[2]);
}

/* The running state of the fractal sum (fractal.glsl's FractalSum). */
struct fsum {
	float freq, ga, hw, sum, center, weight, ew, sx, sz;
};

static float octave_at(const struct params *p, const struct noise_set *ns, const float ws[3], int i, float freq)
{
	float q[3];
	octave_point(p, ns, ws, i, freq, q);
	return octave_noise(p, ns, q, i);
}

/* slope_damped: octave i at ws and at the two gradient points, weighted by
 * the slope of the sum so far. */
static void slope_octave(const struct params *p, const struct noise_set *ns, struct fsum *s, const float ws[3], int i)
{
	float e = SLOPE_EPS / fmaxf(p->noise_freq, 1e-6f);
	const float wx[3] = { ws[0] + e, ws[1] + 0.0f, ws[2] + 0.0f };
	const float wz[3] = { ws[0] + 0.0f, ws[1] + 0.0f, ws[2] + e };
	float n = octave_at(p, ns, ws, i, s->freq);
	float nx = octave_at(p, ns, wx, i, s->freq);
	float nz = octave_at(p, ns, wz, i, s->freq);
	float w = 1.0f;
	if (i > 0) {
		float gx = (s->sx - s->sum) * (1.0f / SLOPE_EPS), gz = (s->sz - s->sum) * (1.0f / SLOPE_EPS);
		w = clampf(p->mf_slope * sqrtf(gx * gx + gz * gz), 0.0f, 1.0f);
	}
	float k = w * s->hw;
	s->sum += k * n;
	s->sx += k * nx;
	s->sz += k * nz;
}

/* hybrid multifractal, octave i (basis n) */
static void hybrid_octave(const struct params *p, struct fsum *s, int i, float n)
{
	if (i == 0) {
		s->sum = n + p->mf_offset;
		s->weight = s->sum;
		s->center = p->mf_offset;
		s->ew = p->mf_offset;
		return;
	}
	float sig = (n + p->mf_offset) * s->hw, csig = p->mf_offset * s->hw;
	s->weight = fminf(s->weight, 1.0f);
	s->ew = fminf(s->ew, 1.0f);
	s->sum += s->weight * sig;
	s->center += s->ew * csig;
	s->weight *= sig;
	s->ew *= csig;
}

/* Octave i of every family but slope_damped (fractal.glsl's fractal_octave). */
static void fractal_octave_ref(const struct params *p, const struct noise_set *ns, struct fsum *s, const float ws[3],
			       int i, float es, float wc)
{
	if (p->fractal == FRACTAL_WORLEY) {
		float q[3], F[4];
		octave_point(p, ns, ws, i, s->freq, q);
		noise_worley(ns, q[0], q[1], q[2], i, F);
		float v = p->worley_c1 * F[0] + p->worley_c2 * F[1] + p->worley_c3 * F[2] + p->worley_c4 * F[3];
		s->sum += s->ga * (v - wc);
		return;
	}
	float n = octave_at(p, ns, ws, i, s->freq);
	switch (p->fractal) {
	case FRACTAL_FBM:
		s->sum += s->hw * n;
		break;
	case FRACTAL_TURBULENCE:
		s->sum += s->ga * (fabsf(n) - NOISE_MEAN_ABS);
		break;
	case FRACTAL_RIDGED: {
		float r = p->ridge_offset - fabsf(n);
		r = r * r * s->weight;
		s->sum += s->hw * r;
		s->weight = clampf(r * p->ridge_gain, 0.0f, 1.0f);
		s->center += s->hw * es * s->ew;
		s->ew = fminf(es * s->ew * p->ridge_gain, 1.0f);
		break;
	}
	case FRACTAL_MULTIFRACTAL:
		s->sum *= p->mf_offset + p->mf_contrast * s->hw * n;
		s->center *= p->mf_offset;
		break;
	case FRACTAL_HETERO:
		if (i == 0) {
			s->sum = p->mf_offset + n;
			s->center = p->mf_offset;
		} else {
			s->sum += (n + p->mf_offset) * s->hw * s->sum;
			s->center += p->mf_offset * s->hw * s->center;
		}
		break;
	case FRACTAL_HYBRID:
		hybrid_octave(p, s, i, n);
		break;
	case FRACTAL_ABS_MULTIFRACTAL:
		s->sum *= p->mf_offset + p->mf_contrast * s->hw * fabsf(n);
		s->center *= p->mf_offset + p->mf_contrast * s->hw * NOISE_MEAN_ABS;
		break;
	default: /* FRACTAL_GEISS */
		s->sum += s->ga * n;
		break;
	}
}

static float fractal_ref(const struct params *p, const struct noise_set *ns, const float ws[3])
{
	struct fsum s = { .freq = p->noise_freq, .ga = 1.0f, .hw = 1.0f, .weight = 1.0f, .ew = 1.0f };
	float hstep = powf(p->lacunarity, -p->hurst);
	float es = p->ridge_offset * p->ridge_offset - 2.0f * p->ridge_offset * NOISE_MEAN_ABS + NOISE_MEAN_SQ;
	float wc = p->worley_c1 * worley_mean[0] + p->worley_c2 * worley_mean[1] + p->worley_c3 * worley_mean[2] +
		   p->worley_c4 * worley_mean[3];
	if (p->fractal == FRACTAL_MULTIFRACTAL || p->fractal == FRACTAL_ABS_MULTIFRACTAL) {
		s.sum = 1.0f;
		s.center = 1.0f;
	}
	for (int i = 0; i < p->octaves; i++) {
		if (p->fractal == FRACTAL_SLOPE_DAMPED)
			slope_octave(p, ns, &s, ws, i);
		else
			fractal_octave_ref(p, ns, &s, ws, i, es, wc);
		s.freq *= p->lacunarity;
		s.ga *= p->gain;
		s.hw *= hstep;
	}
	return s.sum - s.center;
}

/* ---- density.glsl ------------------------------------------------------- */

static float test_field(const struct params *p, float x, float y, float z)
{
	float s = p->field_scale;
	float inv = 1.0f / s;
	float qx = x * inv, qy = y * inv, qz = z * inv;
	float v;
	switch (p->field) {
	case FIELD_TORUS: {
		float r = 0.6f - sqrtf(qx * qx + qz * qz);
		v = 0.16f - r * r - qy * qy;
		break;
	}
	case FIELD_BUMPS:
		v = sinf(5.0f * qx) * cosf(5.0f * qz) * 0.2f - qy;
		break;
	case FIELD_RIPPLE:
		v = sinf(10.0f * (qx * qx + qz * qz)) * 0.1f - qy;
		break;
	case FIELD_SPHERE:
		v = 1.0f - sqrtf(qx * qx + qy * qy + qz * qz);
		break;
	default: /* FIELD_CHECKER */
		v = cosf(PI_F * qx) * cosf(PI_F * qy) * cosf(PI_F * qz);
		break;
	}
	return v * s;
}

static void domain_warp(const struct params *p, const struct noise_set *ns, const float ws[3], float w[3])
{
	float x = ws[0] * p->warp_freq, y = ws[1] * p->warp_freq, z = ws[2] * p->warp_freq;
	if (p->noise == NOISE_TEXTURE) {
		for (int c = 0; c < 3; c++)
			w[c] = noise_tex_sample(ns, 1, x, y, z, c) * NOISE_TEX_GAIN;
		return;
	}
	w[0] = noise_perlin(ns, x + 11.3f, y + 47.9f, z + 23.1f);
	w[1] = noise_perlin(ns, x + 71.7f, y + 5.3f, z + 89.9f);
	w[2] = noise_perlin(ns, x + 37.1f, y + 63.7f, z + 13.9f);
}

/* density.glsl control_value: the control map's c in [0, 1] at (x, z) */
static float control_value(const struct params *p, const struct noise_set *ns, const struct edits *ed, float x,
			   float z)
{
	const struct heightmap *m = &ed->control;
	if (!m->w) {
		float n = noise_perlin(ns, x * p->control_freq + 3.7f, 0.5f, z * p->control_freq + 9.1f);
		return clampf(0.5f + 1.8f * n, 0.0f, 1.0f);
	}
	float gx = x / p->control_map_scale + 0.5f * (float)(m->w - 1);
	float gz = z / p->control_map_scale + 0.5f * (float)(m->h - 1);
	float x0 = floorf(gx), z0 = floorf(gz), fx = gx - x0, fz = gz - z0;
	int ix = (int)x0, iz = (int)z0;
	float t[4];
	for (int k = 0; k < 4; k++) {
		int cx = ix + (k & 1), cz = iz + (k >> 1);
		cx = cx < 0 ? 0 : (cx > m->w - 1 ? m->w - 1 : cx);
		cz = cz < 0 ? 0 : (cz > m->h - 1 ? m->h - 1 : cz);
		t[k] = m->v[(size_t)cz * (size_t)m->w + (size_t)cx];
	}
	float top = t[0] + fx * (t[1] - t[0]), bot = t[2] + fx * (t[3] - t[2]);
	return (top + fz * (bot - top)) * (1.0f / 65535.0f);
}

static float marble_term(const struct params *p, const struct noise_set *ns, const float ws[3])
{
	float h = 0.5f * p->marble_freq;
	float x = ws[0] * h + 5.17f, y = ws[1] * h + 31.3f, z = ws[2] * h + 11.9f;
	float t = 0.0f, a = 1.0f;
	for (int k = 0; k < 4; k++) {
		t += fabsf(noise_perlin(ns, x, y, z)) * a;
		x *= 2.0f;
		y *= 2.0f;
		z *= 2.0f;
		a *= 0.5f;
	}
	return p->marble_amp * sinf(2.0f * PI_F * p->marble_freq * (ws[1] + p->marble_turb * t));
}

static float terrace_term(const struct params *p, float y)
{
	float u = y * (1.0f / p->terrace_step);
	float f = u - floorf(u);
	return -p->terrace_strength * p->terrace_step * (f - f * f * (3.0f - 2.0f * f));
}

static float shelf_term(const struct params *p, float y)
{
	float dy = y - p->shelf_y;
	float w = dy >= 0.0f ? p->shelf_width : 3.0f * p->shelf_width;
	return p->shelf_strength * (1.0f - smooth01(fabsf(dy) * (1.0f / w)));
}

/* no curves, no heightmap (ed == NULL) */
static const struct edits no_edits;

/* heightmap.glsl's height: bilinear (heightmap_ref_base) plus, with detail,
 * the fractal interpolation (Clua §4.1.1): noise octaves weighted by a bump
 * that vanishes at the samples. */
float heightmap_ref_height(const struct edits *e, const struct params *p, const struct noise_set *ns, float x,
			   float z, bool detail)
{
	const struct heightmap *hm = &e->hm;
	if (!hm->w)
		return 0.0f;
	float h = heightmap_ref_base(e, p, x, z);
	if (!detail || p->heightmap_detail == 0.0f)
		return h;
	float gx = x / p->heightmap_scale + 0.5f * (float)(hm->w - 1);
	float gz = z / p->heightmap_scale + 0.5f * (float)(hm->h - 1);
	float fx = gx - floorf(gx), fz = gz - floorf(gz);
	float m00 = sqrtf(fx * fx + fz * fz), m10 = sqrtf((fx - 1.0f) * (fx - 1.0f) + fz * fz);
	float m01 = sqrtf(fx * fx + (fz - 1.0f) * (fz - 1.0f));
	float m11 = sqrtf((fx - 1.0f) * (fx - 1.0f) + (fz - 1.0f) * (fz - 1.0f));
	float sm = m00 + m10 + m01 + m11;
	float sm2 = sm * sm;
	float bump = 256.0f * (m00 * m10 * m01 * m11) / (sm2 * sm2);
	float n = 0.0f, amp = 0.5f, fr = 1.0f;
	for (int i = 0; i < p->heightmap_octaves; i++) {
		n += amp * noise_perlin(ns, gx * fr + (float)i * 17.31f, 0.5f, gz * fr - (float)i * 9.17f);
		fr *= 2.0f;
		amp *= 0.5f;
	}
	return h + p->heightmap_detail * bump * n;
}

float density_ref(const struct params *p, const struct noise_set *ns, const struct edits *ed, float x, float y,
		  float z)
{
	if (!ed)
		ed = &no_edits;
	x += p->time * p->scroll_speed;
	if (p->field == FIELD_HEIGHTMAP) { /* carve_ref.c; needs edits_load(ed, p) */
		const float hp[3] = { x, y, z };
		float hd = heightmap_ref_height(ed, p, ns, x, z, true) - y;
		if (p->heightmap_noise != 0.0f)
			hd += p->heightmap_noise * p->noise_amp * fractal_ref(p, ns, hp);
		return carve_ref_density(ed, p, x, y, z, hd);
	}
	if (p->field != FIELD_TERRAIN)
		return test_field(p, x, y, z);

	const float orig[3] = { x, y, z };
	float ws[3] = { x, y, z };
	if (p->warp_amp != 0.0f) {
		float w[3];
		domain_warp(p, ns, orig, w);
		for (int c = 0; c < 3; c++)
			ws[c] += w[c] * p->warp_amp;
	}

	float d;
	if (p->shape == SHAPE_PLANET) {
		float cx = ws[0] - 0.0f, cy = ws[1] - (-p->planet_radius), cz = ws[2] - 0.0f;
		d = p->planet_radius - sqrtf(cx * cx + cy * cy + cz * cz);
	} else if (p->shape == SHAPE_CAVES) {
		d = p->cave_bias;
	} else {
		d = -ws[1] * p->ground_slope;
	}

	float amp = p->noise_amp;
	if (p->control_strength != 0.0f)
		amp *= 1.0f - p->control_strength * (1.0f - control_value(p, ns, ed, orig[0], orig[2]));
	const float wn[3] = { ws[0], ws[1] * p->noise_y_scale, ws[2] }; /* density.glsl noise_domain */
	d += amp * fractal_ref(p, ns, wn);

	d += sat((p->floor_y - orig[1]) * p->floor_sharpness) * p->floor_strength;

	if (p->marble_amp != 0.0f)
		d += marble_term(p, ns, ws);

	if (p->terrace == TERRACE_PRE)
		d += terrace_term(p, orig[1]);
	else if (p->terrace == TERRACE_POST)
		d += terrace_term(p, ws[1]);

	if (p->shelf == TERRACE_PRE) /* same off|pre|post choices */
		d += shelf_term(p, orig[1]);
	else if (p->shelf == TERRACE_POST)
		d += shelf_term(p, ws[1]);

	if (p->flat_spot) {
		float dx = orig[0] - p->flat_x, dz = orig[2] - p->flat_z;
		float dist = sqrtf(dx * dx + dz * dz);
		float amount = sat((p->flat_outer - dist) * (1.0f / fmaxf(p->flat_outer - p->flat_inner, 1e-4f))) * 0.9f;
		d = d + amount * ((p->flat_y - orig[1]) - d);
	}
	return carve_ref_density(ed, p, orig[0], orig[1], orig[2], d); /* curves: cut and fill */
}

void density_ref_volume(const struct params *p, const struct noise_set *ns, const struct edits *ed,
			const float origin[3], float cell, int nx, int ny, int nz, float *out)
{
	int sx = nx + 3, sy = ny + 3, sz = nz + 3;
	for (int k = 0; k < sz; k++)
		for (int j = 0; j < sy; j++)
			for (int i = 0; i < sx; i++) {
				float x = origin[0] + (float)(i - 1) * cell;
				float y = origin[1] + (float)(j - 1) * cell;
				float z = origin[2] + (float)(k - 1) * cell;
				float d = density_ref(p, ns, ed, x, y, z);
				if (p->closed) {
					/* as the density pass (common.glsl): air on the border,
					 * more in the margin */
					if (i == 0 || j == 0 || k == 0 || i == sx - 1 || j == sy - 1 || k == sz - 1)
						d = fminf(d, p->iso - cell);
					else if (i == 1 || j == 1 || k == 1 || i == sx - 2 || j == sy - 2 || k == sz - 2)
						d = fminf(d, p->iso - 1e-3f * cell);
				}
				out[((size_t)k * (size_t)sy + (size_t)j) * (size_t)sx + (size_t)i] = d;
			}
}
