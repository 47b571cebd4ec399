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

vec3 octave_point(vec3 ws, int i, float freq)
{
	vec3 p = ws * freq;
#if TERM_ROTATED_OCTAVES // 0: no rotation code
	if (i < u_rotated_octaves && i < 4)
		p = noise_rotate(i, p);
#endif
	return p + float(i) * OCTAVE_SHIFT;
}

// Noise basis of octave i at lattice-space point p.
float octave_noise(vec3 p, int i)
{
	if (u_noise == NOISE_TEXTURE) {
		int k = i % 3;
		int ch = (i / 3) & 3;
		// the lowest (rotated) octaves: manual fp32 trilinear (GPU Gems' advice)
#if TERM_ROTATED_OCTAVES
		vec4 t = (i < u_rotated_octaves) ? noise_tex_manual(k, p) : noise_tex_hw(k, p);
#else
		vec4 t = noise_tex_hw(k, p);
#endif
		return t[ch] * NOISE_TEX_GAIN;
	}
	return perlin(p);
}

// Octaves left out (the "lightweight" density of long AO rays drops 3).
int g_octave_drop = 0;

float fractal(vec3 ws)
{
	float freq = u_noise_freq;
	float ga = 1.0;                            // gain^i
	float hw = 1.0;                            // (f_i/f_0)^-H
	float hstep = pow(u_lacunarity, -u_hurst);
	float sum = 0.0;
	float center = 0.0;
	float weight = 1.0;                        // ridged
	float es = u_ridge_offset * u_ridge_offset - 2.0 * u_ridge_offset * NOISE_MEAN_ABS + NOISE_MEAN_SQ;
	float ew = 1.0;                            // ridged: approximate E[w_i]
	float wc = u_worley_c1 * WORLEY_MEAN.x + u_worley_c2 * WORLEY_MEAN.y + u_worley_c3 * WORLEY_MEAN.z +
		   u_worley_c4 * WORLEY_MEAN.w;
	if (u_fractal == FRACTAL_MULTIFRACTAL) {
		sum = 1.0;
		center = 1.0;
	}
	for (int i = 0; i < u_octaves - g_octave_drop; i++) {
		vec3 p = octave_point(ws, i, freq);
		if (u_fractal == FRACTAL_WORLEY) {
			vec4 F = worley(p, i);
			float v = u_worley_c1 * F.x + u_worley_c2 * F.y + u_worley_c3 * F.z + u_worley_c4 * F.w;
			sum += ga * (v - wc);
		} else {
			float n = octave_noise(p, i);
			if (u_fractal == FRACTAL_FBM) {
				sum += hw * n;
			} else if (u_fractal == FRACTAL_TURBULENCE) {
				sum += ga * (abs(n) - NOISE_MEAN_ABS);
			} else if (u_fractal == FRACTAL_RIDGED) {
				float s = u_ridge_offset - abs(n);
				s = s * s * weight;
				sum += hw * s;
				weight = clamp(s * u_ridge_gain, 0.0, 1.0);
				center += hw * es * ew;
				ew = min(es * ew * u_ridge_gain, 1.0);
			} else if (u_fractal == FRACTAL_MULTIFRACTAL) {
				sum *= u_mf_offset + u_mf_contrast * hw * n;
				center *= u_mf_offset;
			} else if (u_fractal == FRACTAL_HETERO) {
				if (i == 0) {
					sum = u_mf_offset + n;
					center = u_mf_offset;
				} else {
					sum += (n + u_mf_offset) * hw * sum;
					center += u_mf_offset * hw * center;
				}
			} else { // FRACTAL_GEISS
				sum += ga * n;
			}
		}
		freq *= u_lacunarity;
		ga *= u_gain;
		hw *= hstep;
	}
	return sum - center;
}
