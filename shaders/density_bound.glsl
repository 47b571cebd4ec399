// isoterra — a conservative bound of the terrain's density over a box, for
// the streaming world's coarse pre-pass (block_bound.glsl; GPU Gems 3 ch.1's
// empty-block test made safe).  Mirrors density() in density.glsl term by
// term; app/terrain/density_bound.c says on the host which parameter states
// it covers (density_bound_supported) and the world generates every block
// of any other state.
//
//   vec2 density_bound(vec3 c, vec3 e, int keep)
//
// returns (lo, hi) with lo <= density(x) <= hi for every x in the box of
// centre c and half-extent e, for the field with any number of octaves from
// `keep` up to u_octaves.  The field at c is evaluated with its `keep`
// lowest octaves (and the full domain warp); the rest is bounded:
//   * the octaves left out: |sum| <= amp * sum_i w_i * NOISE_BOUND_MAX
//   * the change of the kept part over the box: its Lipschitz bound times
//     |e| (octave i: amp * w_i * f_i * NOISE_BOUND_LIP; the ground plane's
//     slope; all times the warp's stretch 1 + warp_amp * warp_freq *
//     NOISE_BOUND_LIP * sqrt(3))
//   * the terms of y alone (floor, shelf) by their range over the box's y,
//     the bounded ones (terraces, marble) by their range, the landing pad
//     as the convex blend it is.
// NOISE_BOUND_MAX / NOISE_BOUND_LIP: |perlin| and |grad perlin|, sampled
// at 16 M points over 4 seeds as 0.998 and 3.29 (docs/WORLD.md), with a
// margin.

#define NOISE_BOUND_MAX 1.1
#define NOISE_BOUND_LIP 4.0
#define TERRACE_BOUND 0.0963 // max |f - smoothstep(f)| on [0, 1], at f = (3 - sqrt 3) / 6

// the kept octaves' weights: sum w_i (value), sum w_i f_i (slope); the rest's sum w_i
void bound_weights(int keep, out float wk, out float lk, out float wr)
{
	float hstep = pow(u_lacunarity, -u_hurst);
	float w = 1.0, f = u_noise_freq;
	wk = 0.0;
	lk = 0.0;
	wr = 0.0;
	for (int i = 0; i < u_octaves; i++) {
		if (i < keep) {
			wk += w;
			lk += w * f;
		} else {
			wr += w;
		}
		w *= u_fractal == FRACTAL_FBM ? hstep : u_gain;
		f *= u_lacunarity;
	}
}

vec2 density_bound(vec3 c, vec3 e, int keep)
{
	float r = length(e);
	vec3 ws = c;
	float stretch = 1.0;
#if TERM_WARP_AMP
	if (u_warp_amp != 0.0) {
		ws += domain_warp(c) * u_warp_amp;
		stretch += abs(u_warp_amp) * u_warp_freq * NOISE_BOUND_LIP * 1.7320508;
	}
#endif
	// the ground shape at the warped centre, and its slope
	float d, slope;
	if (u_shape == SHAPE_PLANET) {
		vec3 q = ws - vec3(0.0, -u_planet_radius, 0.0);
		d = u_planet_radius - sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
		slope = 1.0;
	} else if (u_shape == SHAPE_CAVES) {
		d = u_cave_bias;
		slope = 0.0;
	} else {
		d = -ws.y * u_ground_slope;
		slope = abs(u_ground_slope);
	}
	float dev = slope * stretch * r;
#if TERM_NOISE_AMP
	float wk, lk, wr;
	bound_weights(keep, wk, lk, wr);
	// turbulence: |n| - E|n| lies in [-E|n|, max - E|n|]
	float vmax = u_fractal == FRACTAL_TURBULENCE ? NOISE_BOUND_MAX - NOISE_MEAN_ABS : NOISE_BOUND_MAX;
	float amp = abs(u_noise_amp), k = 1.0;
	g_octave_drop = u_octaves - keep;
	float fk = fractal(noise_domain(ws));
	g_octave_drop = 0;
#if TERM_CONTROL_STRENGTH
	// amplitude x k(x), k = 1 - s (1 - control) in [1 - s, 1], control =
	// clamp(0.5 + 1.8 perlin(xz * control_freq)): slope 1.8 f_c max|grad|
	k = 1.0 - u_control_strength * (1.0 - control_value(c.xz));
	dev += amp * u_control_strength * 1.8 * u_control_freq * NOISE_BOUND_LIP * r * wk * vmax;
#endif
	d += u_noise_amp * k * fk;
	dev += amp * lk * NOISE_BOUND_LIP * stretch * r + amp * wr * vmax;
#endif
	float lo = d - dev, hi = d + dev;
#if TERM_FLOOR_STRENGTH
	// decreasing in the pre-warp y
	lo += dens_sat((u_floor_y - (c.y + e.y)) * u_floor_sharpness) * u_floor_strength;
	hi += dens_sat((u_floor_y - (c.y - e.y)) * u_floor_sharpness) * u_floor_strength;
#endif
#if TERM_MARBLE_AMP
	lo -= abs(u_marble_amp);
	hi += abs(u_marble_amp);
#endif
	if (u_terrace != TERRACE_OFF) {
		float t = abs(u_terrace_strength) * u_terrace_step * TERRACE_BOUND;
		lo -= t;
		hi += t;
	}
	if (u_shelf != SHELF_OFF) {
		// non-zero only for y in (shelf_y - 3 width, shelf_y + width)
		float ylo = c.y - e.y, yhi = c.y + e.y;
		if (u_shelf == SHELF_POST) { // the warped y: within warp_amp * max|n| of y
			float m = abs(u_warp_amp) * NOISE_BOUND_MAX;
			ylo -= m;
			yhi += m;
		}
		if (yhi > u_shelf_y - 3.0 * u_shelf_width && ylo < u_shelf_y + u_shelf_width) {
			lo += min(u_shelf_strength, 0.0);
			hi += max(u_shelf_strength, 0.0);
		}
	}
	if (u_flat_spot != 0) {
		// d' = d + a ((flat_y - y) - d), a in [0, 0.9]: between d and flat_y - y;
		// a = 0 outside flat_outer of the pad's centre
		vec2 q = max(abs(c.xz - vec2(u_flat_x, u_flat_z)) - e.xz, vec2(0.0));
		if (length(q) < u_flat_outer) {
			lo = min(lo, u_flat_y - (c.y + e.y));
			hi = max(hi, u_flat_y - (c.y - e.y));
		}
	}
	// GPU and CPU rounding of the evaluated part
	float eps = 1e-4 * (abs(d) + 1.0);
	return vec2(lo - eps, hi + eps);
}
