// isoterra — the density function (GLSL ES 3.10): positive in rock, negative
// in air, zero on the surface; roughly a distance in world units near the
// surface.  After Geiss, "Generating Complex Procedural Terrains Using the
// GPU", GPU Gems 3 ch.1.  Mirrored term by term in app/terrain/density_ref.c.
//
// Needs (from the host prelude): the u_* parameter uniforms and the enum
// #defines (FIELD_*, SHAPE_*, NOISE_*, FRACTAL_*, TERRACE_*, SHELF_*).
// Resources: NoiseTables UBO (UBIND_NOISE), u_noise0..2 (TEX_NOISE0..2),
// uploaded by app/terrain/noise_gl.c; the curves and the heightmap
// (app/edit/curves_gl.c); bound by the terrain field (app/terrain/terrain.c).
//
// Code for a term that is off is not compiled (llvmpipe and small GPUs run
// both sides of a uniform branch): the enum terms are constants in a
// specialized program (#define u_field 0, ...), and each term a parameter
// value of 0 turns off is compiled under TERM_<NAME> (P_TERM in params.def,
// 0|1 in the specialization, 1 where a program is not specialized); the
// curves under HAS_CURVES (carve.glsl), which the terrain provider defines
// from the edit state.  docs/PIPELINE.md, "Specialization".
//
//   float density(vec3 ws);
//   float density_far(vec3 ws);  // three octaves fewer (long AO rays)

#include "noise.glsl"
#include "fractal.glsl"
#include "carve.glsl" // curves (cut and fill) and the heightmap base

#define PI_F 3.14159265358979

float dens_sat(float x)
{
	return clamp(x, 0.0, 1.0);
}

float dens_smooth(float t) // smoothstep(0, 1, t) written out (mirrored in C)
{
	t = clamp(t, 0.0, 1.0);
	return t * t * (3.0 - 2.0 * t);
}

// Analytic test fields, q = ws / field_scale, result * field_scale so the
// field is in world units.
float test_field(vec3 ws)
{
	float s = u_field_scale;
	float inv = 1.0 / s;
	vec3 q = ws * inv;
	float v;
	if (u_field == FIELD_TORUS) {
		float r = 0.6 - sqrt(q.x * q.x + q.z * q.z);
		v = 0.16 - r * r - q.y * q.y;
	} else if (u_field == FIELD_BUMPS) {
		v = sin(5.0 * q.x) * cos(5.0 * q.z) * 0.2 - q.y;
	} else if (u_field == FIELD_RIPPLE) {
		v = sin(10.0 * (q.x * q.x + q.z * q.z)) * 0.1 - q.y;
	} else if (u_field == FIELD_SPHERE) {
		v = 1.0 - sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
	} else { // FIELD_CHECKER: +-1 at the lattice points spaced s (worst case for MC)
		v = cos(PI_F * q.x) * cos(PI_F * q.y) * cos(PI_F * q.z);
	}
	return v * s;
}

vec3 domain_warp(vec3 ws)
{
	vec3 p = ws * u_warp_freq;
	if (u_noise == NOISE_TEXTURE) // low frequency: fp32 filtering
		return noise_tex_manual(1, p).xyz * NOISE_TEX_GAIN;
	return vec3(perlin(p + vec3(11.3, 47.9, 23.1)), perlin(p + vec3(71.7, 5.3, 89.9)),
		    perlin(p + vec3(37.1, 63.7, 13.9)));
}

// Terraces on height y: a continuous, C1 staircase.  With u = y/step,
// f = fract(u), the term is  -strength * step * (f - smoothstep(f)), which
// makes the surface's height steep in density near y = k*step (flat treads)
// and slack in between (risers): strength 2 gives vertical risers, more
// gives overhanging lips, 0 none.
float terrace_term(float y)
{
	float u = y * (1.0 / u_terrace_step);
	float f = u - floor(u);
	return -u_terrace_strength * u_terrace_step * (f - f * f * (3.0 - 2.0 * f));
}

// A single ledge at shelf_y: extra rock falling off within shelf_width above
// (crisp flat top) and 3*shelf_width below.
float shelf_term(float y)
{
	float dy = y - u_shelf_y;
	float w = dy >= 0.0 ? u_shelf_width : 3.0 * u_shelf_width;
	return u_shelf_strength * (1.0 - dens_smooth(abs(dy) * (1.0 / w)));
}

// The 2D control map (GPU Gems 3 ch.1): a low-frequency value c in [0, 1]
// over x, z that sets the terrain's character -- the noise term's amplitude
// is scaled by 1 - control_strength (1 - c): plains where c = 0, mountains
// where c = 1.  From the control map file (R32F samples 0..65535, centred
// on x = z = 0, control_map_scale world units apart, bilinear, clamped at
// the edges; HAS_CONTROL_MAP, from the terrain provider) or, without one,
// 2D Perlin noise at control_freq.
#ifndef HAS_CONTROL_MAP
#define HAS_CONTROL_MAP 0
#endif
#if TERM_CONTROL_STRENGTH
#if HAS_CONTROL_MAP
layout(binding = TEX_CONTROL) uniform highp sampler2D u_control_tex;
uniform ivec2 u_control_size;

float control_texel(ivec2 c)
{
	return texelFetch(u_control_tex, clamp(c, ivec2(0), u_control_size - 1), 0).r;
}
#endif

float control_value(vec2 xz)
{
#if HAS_CONTROL_MAP
	vec2 g = xz / u_control_map_scale + 0.5 * vec2(u_control_size - 1);
	vec2 g0 = floor(g);
	vec2 f = g - g0;
	ivec2 c = ivec2(g0);
	float a = control_texel(c), b = control_texel(c + ivec2(1, 0));
	float e = control_texel(c + ivec2(0, 1)), h = control_texel(c + ivec2(1, 1));
	float top = a + f.x * (b - a), bot = e + f.x * (h - e);
	return (top + f.y * (bot - top)) * (1.0 / 65535.0);
#else
	float n = perlin(vec3(xz.x * u_control_freq + 3.7, 0.5, xz.y * u_control_freq + 9.1));
	return clamp(0.5 + 1.8 * n, 0.0, 1.0);
#endif
}
#endif

// Marble (Perlin 1985; Clua 1999 §3.2): sine bands along y pushed by
// turbulence, T = sum_k |n(p 2^k)| / 2^k over four octaves at half the
// bands' frequency.
float marble_term(vec3 ws)
{
	vec3 p = ws * (0.5 * u_marble_freq) + vec3(5.17, 31.3, 11.9);
	float t = 0.0, a = 1.0;
	for (int k = 0; k < 4; k++) {
		t += abs(perlin(p)) * a;
		p *= 2.0;
		a *= 0.5;
	}
	return u_marble_amp * sin(2.0 * PI_F * u_marble_freq * (ws.y + u_marble_turb * t));
}

// Where the noise term is sampled: y scaled by noise_y_scale (1: isotropic;
// towards 0 a height field).  Mirrored by density_ref.c and the bound
// (density_bound.glsl: a y scale of at most 1 only lowers the noise's slope,
// so its Lipschitz bound holds).
vec3 noise_domain(vec3 ws)
{
	return vec3(ws.x, ws.y * u_noise_y_scale, ws.z);
}

float density(vec3 ws)
{
#if TERM_SCROLL_SPEED
	ws.x += u_time * u_scroll_speed; // animation: the field scrolls along x
#endif
	if (u_field == FIELD_HEIGHTMAP) { // heightmap base (+ 3D noise detail), then the curves
		float hd = hm_height(ws.xz, true) - ws.y;
#if TERM_HEIGHTMAP_NOISE && TERM_NOISE_AMP
		if (u_heightmap_noise != 0.0)
			hd += u_heightmap_noise * u_noise_amp * fractal(ws);
#endif
		return carve_density(ws, hd);
	}
	if (u_field != FIELD_TERRAIN)
		return test_field(ws);

	vec3 ws_orig = ws;
#if TERM_WARP_AMP
	if (u_warp_amp != 0.0)
		ws += domain_warp(ws) * u_warp_amp;
#endif

	float d;
	if (u_shape == SHAPE_PLANET) {
		vec3 c = ws - vec3(0.0, -u_planet_radius, 0.0);
		d = u_planet_radius - sqrt(c.x * c.x + c.y * c.y + c.z * c.z);
	} else if (u_shape == SHAPE_CAVES) {
		d = u_cave_bias;
	} else {
		d = -ws.y * u_ground_slope;
	}

	// the terms that do not depend on the noise, summed first (the far
	// samples' cut below weighs the noise against everything else)
	float extra = 0.0;
#if TERM_FLOOR_STRENGTH
	// hard floor on the pre-warp height ("sediment")
	extra += dens_sat((u_floor_y - ws_orig.y) * u_floor_sharpness) * u_floor_strength;
#endif

#if TERM_MARBLE_AMP
	if (u_marble_amp != 0.0)
		extra += marble_term(ws);
#endif

	if (u_terrace == TERRACE_PRE)
		extra += terrace_term(ws_orig.y);
	else if (u_terrace == TERRACE_POST)
		extra += terrace_term(ws.y);

	if (u_shelf == SHELF_PRE)
		extra += shelf_term(ws_orig.y);
	else if (u_shelf == SHELF_POST)
		extra += shelf_term(ws.y);

	// landing pad (GPU Gems' corrected formula): d + flat_k ((flat_y - y) - d)
	float flat_k = 0.0, flat_to = 0.0;
	if (u_flat_spot != 0) {
		float dx = ws_orig.x - u_flat_x, dz = ws_orig.z - u_flat_z;
		float dist = sqrt(dx * dx + dz * dz);
		flat_k = dens_sat((u_flat_outer - dist) * (1.0 / max(u_flat_outer - u_flat_inner, 1e-4))) * 0.9;
		flat_to = u_flat_y - ws_orig.y;
	}

#if TERM_NOISE_AMP
	float amp = u_noise_amp;
#if TERM_CONTROL_STRENGTH
	amp *= 1.0 - u_control_strength * (1.0 - control_value(ws_orig.xz));
#endif
#if defined(DENSITY_CUT) || defined(DENSITY_REFINE)
	// the stored value as an affine function of the fractal sum
	cut_setup((1.0 - flat_k) * (d + extra) + flat_k * flat_to, (1.0 - flat_k) * amp);
#endif
	d += amp * fractal(noise_domain(ws));
#endif
	d += extra;
	if (u_flat_spot != 0)
		d = d + flat_k * (flat_to - d);
	return carve_density(ws_orig, d); // curves: cut and fill
}

// The field without its three finest octaves: the long ambient-occlusion
// rays (ao.glsl) need the shape, not the detail.
float density_far(vec3 ws)
{
	g_octave_drop = 3;
	float d = density(ws);
	g_octave_drop = 0;
	return d;
}
