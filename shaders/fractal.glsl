// isoterra — fractal sums of the noise basis (GLSL ES 3.10).  Mirrored in
// app/terrain/density_ref.c (fractal_ref); change both together.
//
// fractal(ws) returns a dimensionless height-like value h, roughly centred on
// zero for every family (so switching families keeps the ground near y = 0);
// density.glsl adds u_noise_amp * h.
//
// Octave i samples the basis at  p_i = R_i (ws * f_i) + i * OCTAVE_SHIFT
// with f_i = noise_freq * lacunarity^i (accumulated by repeated
// multiplication), R_i one of the seeded rotations for i < rotated_octaves
// (identity otherwise), and a fixed per-octave shift that keeps the lattices
// of different octaves from lining up at the origin.
//
//   geiss         h = sum gain^i n_i                          (GPU Gems 3 ch.1)
//   fbm           h = sum (f_i/f_0)^-H n_i                    (Clua 1999 eq. 3.3b)
//   turbulence    h = sum gain^i (|n_i| - E|n|)               (Perlin 1985, centred)
//   ridged        Musgrave's ridged multifractal: s_i = (offset - |n_i|)^2 * w_i,
//                 w_0 = 1, w_{i+1} = saturate(s_i * ridge_gain),
//                 h = sum (f_i/f_0)^-H s_i - (its expectation, approximately)
//   multifractal  v = prod (mf_offset + mf_contrast (f_i/f_0)^-H n_i),
//                 h = v - mf_offset^octaves                   (multiplicative cascade)
//   hetero        v = mf_offset + n_0;  v += (n_i + mf_offset) (f_i/f_0)^-H v,
//                 h = v - (v with all n_i = 0)                (height-damped, Musgrave)
//   worley        h = sum gain^i (C . F(p_i) - C . E[F])      (F1..F4, Worley 1996)
//   hybrid        Musgrave's hybrid multifractal: v = (n_0 + mf_offset),
//                 w = v; then  w = min(w, 1), s_i = (n_i + mf_offset) (f_i/f_0)^-H,
//                 v += w s_i, w *= s_i;  h = v - (v with all n_i = 0)
//   slope_damped  v = n_0;  v += saturate(mf_slope |grad_xz v|) (f_i/f_0)^-H n_i
//                 (Clua 1999 fig. 4.3: the octaves' weight follows the slope of
//                 the sum so far, so plateaus stay smooth); the gradient is a
//                 forward difference of SLOPE_EPS lattice cells of octave 0,
//                 the sum being carried at ws, ws + e x and ws + e z
//   abs_multifractal  v = prod (mf_offset + mf_contrast (f_i/f_0)^-H |n_i|),
//                 h = v - prod (mf_offset + mf_contrast (f_i/f_0)^-H E|n|)
//                 (Clua 1999 fig. 4.5: the cascade on |n|, as turbulence does)

#include "noise.glsl"

// Texture values are uniform in [-1,1]; trilinear filtering gives them a
// standard deviation of 0.3137, Perlin noise has 0.2710.  Scaling the
// texture basis by the ratio makes both sources interchangeable.
#define NOISE_TEX_GAIN 0.864
// Statistics of the (normalized) basis: E|n| and E[n^2].
#define NOISE_MEAN_ABS 0.2205
#define NOISE_MEAN_SQ 0.0734
// E[F1..F4] for one feature point per unit cube.
#define WORLEY_MEAN vec4(0.5205, 0.7167, 0.8451, 0.9437)
#define OCTAVE_SHIFT vec3(17.31, -9.17, 23.53)
// slope_damped: the gradient's step, lattice cells of octave 0
#define SLOPE_EPS 0.05

// The octaves below rotated_octaves (the rotated ones) and those above
// run in separate loops, each with only its own code: a branch on the
// octave index would make llvmpipe and small GPUs run the rotation and
// (texture noise) the manual trilinear for every octave.  `rotated` is a
// constant at each call, so the other side is not compiled.
vec3 octave_point(vec3 ws, int i, float freq, bool rotated)
{
	vec3 p = ws * freq;
	if (rotated && i < 4)
		p = noise_rotate(i, p);
	return p + float(i) * OCTAVE_SHIFT;
}

// Noise basis of octave i at lattice-space point p.
float octave_noise(vec3 p, int i, bool rotated)
{
	if (u_noise == NOISE_TEXTURE) {
		int k = i % 3;
		int ch = (i / 3) & 3;
		// the lowest (rotated) octaves: manual fp32 trilinear (GPU Gems' advice)
		vec4 t = rotated ? noise_tex_manual(k, p) : noise_tex_hw(k, p);
		return t[ch] * NOISE_TEX_GAIN;
	}
	return perlin(p);
}

// lacunarity^-hurst, the fbm weights' ratio from octave to octave: from the
// host (app/terrain/terrain.c, powf as density_ref.c), not a pow() per
// sample.
uniform float u_fractal_hstep;

// Octaves left out (the "lightweight" density of long AO rays drops 3).
int g_octave_drop = 0;

#ifdef DENSITY_CUT
// Far samples (common.glsl, app/extract/field.h): the density pass stops
// a sample's octaves once the ones left cannot change its sign.  The
// stored value is g_cut_base + g_cut_scale * sum (density.glsl's terms
// around the noise, cut_setup); an octave adds at most CUT_NOISE_BOUND
// (abi.h) times its weight.  |improved Perlin| < 1.11: a corner's
// gradient has two components of +-1, so its product with the offset d
// is at most the sum of d's two largest |components|; the fade-weighted
// sum of that over the eight corners peaks at 1.0363 on a 201^3 grid of
// the cell, and its slope (< 16.5) adds at most 0.071 between the grid's
// points.  The texture basis is at most 0.864, turbulence's |n| - E|n|
// within -0.22 .. 0.89.  u_cut_tail is the sum of all the
// octaves' weights (fbm (f_i/f_0)^-H, geiss and turbulence gain^i, a
// little over, from the host: app/terrain/terrain.c).  A sample is cut
// when the value, moved by the most the octaves left can add, stays on its
// side of the iso level, and on the rock side also u_cut_rock above it,
// where ambient occlusion sees no difference (ao.glsl saturates there).
// The cut is tried before octaves 0 .. CUT_LAST_OCTAVE (abi.h) only.  A
// sample near the surface that is cut must be computed again whole (the
// refine pass); later octaves leave so small a margin that they would cut
// many such samples to save an octave or two (the benchmark field at
// 128^3: 101 388 samples to refine when every octave may cut, 66 when the
// first three may, for 1.5 ms more in the density pass, llvmpipe).
uniform float u_cut_tail;
uniform float u_cut_rock;
float g_cut_base, g_cut_scale;

void cut_setup(float base, float scale)
{
	g_cut_base = base;
	g_cut_scale = scale;
}

// before octave i, with `tail` the weights of octaves i.. : stop here?
bool cut_far(float sum, float tail, int i)
{
	float v = g_cut_base + g_cut_scale * sum;
	float m = abs(g_cut_scale) * CUT_NOISE_BOUND * tail;
	float iso = u_iso + u_density_bias;
	if (v < iso - m || v > iso + m + u_cut_rock) {
		g_density_cut = true;
		g_density_tag = i; // the octave to go on from (refine)
		return true;
	}
	return false;
}
#endif

#ifdef DENSITY_REFINE
// A cut sample near the surface, computed whole: the octaves before the
// one it was cut at (g_refine_tag) are in its stored value, from which
// cut_setup, called where the density pass called it, recovers their sum;
// the sum goes on from there.  g_refine_tag -1: from scratch.
float g_resume_sum;

void cut_setup(float base, float scale)
{
	if (g_refine_tag >= 0)
		g_resume_sum = ((g_refine_stored + u_density_bias) - base) / scale;
}
#endif

// The running state of the fractal sum, octave to octave.
struct FractalSum {
	float freq;   // f_i
	float ga;     // gain^i
	float hw;     // (f_i/f_0)^-H
	float sum;
	float center;
	float weight; // ridged
	float ew;     // ridged: approximate E[w_i]; hybrid: w with all n_i = 0
	float sx;     // slope_damped: the sum at ws + e x
	float sz;     // slope_damped: the sum at ws + e z
};

// slope_damped: octave i at ws and at the two gradient points, weighted by
// the slope of the sum so far.
void slope_octave(inout FractalSum s, vec3 ws, int i, bool rotated)
{
	float e = SLOPE_EPS / max(u_noise_freq, 1e-6);
	float n = octave_noise(octave_point(ws, i, s.freq, rotated), i, rotated);
	float nx = octave_noise(octave_point(ws + vec3(e, 0.0, 0.0), i, s.freq, rotated), i, rotated);
	float nz = octave_noise(octave_point(ws + vec3(0.0, 0.0, e), i, s.freq, rotated), i, rotated);
	float w = 1.0;
	if (i > 0) {
		float gx = (s.sx - s.sum) * (1.0 / SLOPE_EPS), gz = (s.sz - s.sum) * (1.0 / SLOPE_EPS);
		w = clamp(u_mf_slope * sqrt(gx * gx + gz * gz), 0.0, 1.0);
	}
	float k = w * s.hw;
	s.sum += k * n;
	s.sx += k * nx;
	s.sz += k * nz;
}

// Octave i added to s (hstep = lacunarity^-H, es and wc: the ridged and
// Worley expectations, constant over the octaves).
void fractal_octave(inout FractalSum s, vec3 ws, int i, bool rotated, float hstep, float es, float wc)
{
	if (u_fractal == FRACTAL_SLOPE_DAMPED) {
		slope_octave(s, ws, i, rotated);
	} else if (u_fractal == FRACTAL_WORLEY) {
		vec3 p = octave_point(ws, i, s.freq, rotated);
		vec4 F = worley(p, i);
		float v = u_worley_c1 * F.x + u_worley_c2 * F.y + u_worley_c3 * F.z + u_worley_c4 * F.w;
		s.sum += s.ga * (v - wc);
	} else {
		float n = octave_noise(octave_point(ws, i, s.freq, rotated), i, rotated);
		if (u_fractal == FRACTAL_FBM) {
			s.sum += s.hw * n;
		} else if (u_fractal == FRACTAL_TURBULENCE) {
			s.sum += s.ga * (abs(n) - NOISE_MEAN_ABS);
		} else if (u_fractal == FRACTAL_RIDGED) {
			float r = u_ridge_offset - abs(n);
			r = r * r * s.weight;
			s.sum += s.hw * r;
			s.weight = clamp(r * u_ridge_gain, 0.0, 1.0);
			s.center += s.hw * es * s.ew;
			s.ew = min(es * s.ew * u_ridge_gain, 1.0);
		} else if (u_fractal == FRACTAL_MULTIFRACTAL) {
			s.sum *= u_mf_offset + u_mf_contrast * s.hw * n;
			s.center *= u_mf_offset;
		} else if (u_fractal == FRACTAL_HETERO) {
			if (i == 0) {
				s.sum = u_mf_offset + n;
				s.center = u_mf_offset;
			} else {
				s.sum += (n + u_mf_offset) * s.hw * s.sum;
				s.center += u_mf_offset * s.hw * s.center;
			}
		} else if (u_fractal == FRACTAL_HYBRID) {
			if (i == 0) {
				s.sum = n + u_mf_offset;
				s.weight = s.sum;
				s.center = u_mf_offset;
				s.ew = u_mf_offset;
			} else {
				float sig = (n + u_mf_offset) * s.hw, csig = u_mf_offset * s.hw;
				s.weight = min(s.weight, 1.0);
				s.ew = min(s.ew, 1.0);
				s.sum += s.weight * sig;
				s.center += s.ew * csig;
				s.weight *= sig;
				s.ew *= csig;
			}
		} else if (u_fractal == FRACTAL_ABS_MULTIFRACTAL) {
			s.sum *= u_mf_offset + u_mf_contrast * s.hw * abs(n);
			s.center *= u_mf_offset + u_mf_contrast * s.hw * NOISE_MEAN_ABS;
		} else { // FRACTAL_GEISS
			s.sum += s.ga * n;
		}
	}
	s.freq *= u_lacunarity;
	s.ga *= u_gain;
	s.hw *= hstep;
}

float fractal(vec3 ws)
{
	FractalSum s;
	s.freq = u_noise_freq;
	s.ga = 1.0;
	s.hw = 1.0;
	float hstep = u_fractal_hstep;
	s.sum = 0.0;
	s.center = 0.0;
	s.weight = 1.0;
	float es = u_ridge_offset * u_ridge_offset - 2.0 * u_ridge_offset * NOISE_MEAN_ABS + NOISE_MEAN_SQ;
	s.ew = 1.0;
	float wc = u_worley_c1 * WORLEY_MEAN.x + u_worley_c2 * WORLEY_MEAN.y + u_worley_c3 * WORLEY_MEAN.z +
		   u_worley_c4 * WORLEY_MEAN.w;
	s.sx = 0.0;
	s.sz = 0.0;
	if (u_fractal == FRACTAL_MULTIFRACTAL || u_fractal == FRACTAL_ABS_MULTIFRACTAL) {
		s.sum = 1.0;
		s.center = 1.0;
	}
	// The loops test at their end (do-while): a loop testing at its top
	// makes a SIMD driver (llvmpipe) run one more, masked, octave after the
	// last, whose exit it only sees there.
	int n = u_octaves - g_octave_drop;
	int i = 0;
#ifdef DENSITY_REFINE
	if (g_refine_tag >= 0) { // the octaves before it: their sum, and the state they leave
		s.sum = g_resume_sum;
		for (; i < g_refine_tag; i++) {
			s.freq *= u_lacunarity;
			s.ga *= u_gain;
			s.hw *= hstep;
		}
	}
#endif
#ifdef DENSITY_CUT
	// the weights of the octaves not summed yet (see cut_far)
	float tail = u_cut_tail;
	bool fbm_weights = u_fractal == FRACTAL_FBM;
#endif
#if TERM_ROTATED_OCTAVES // 0: no rotation code
	int nr = min(u_rotated_octaves, n);
	if (i < nr) {
		do {
#ifdef DENSITY_CUT
			if (i <= CUT_LAST_OCTAVE && cut_far(s.sum, tail, i))
				return s.sum - s.center;
			tail -= fbm_weights ? s.hw : s.ga;
#endif
			fractal_octave(s, ws, i, true, hstep, es, wc);
		} while (++i < nr);
	}
#endif
	if (i < n) {
		do {
#ifdef DENSITY_CUT
			if (i <= CUT_LAST_OCTAVE && cut_far(s.sum, tail, i))
				break;
			tail -= fbm_weights ? s.hw : s.ga;
#endif
			fractal_octave(s, ws, i, false, hstep, es, wc);
		} while (++i < n);
	}
	return s.sum - s.center;
}
