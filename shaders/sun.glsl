// isoterra — sun shadows of a vertex: one ray towards the sun through the
// density field, soft (Quilez's penumbra estimate: the smallest
// clearance / distance along the ray, the density standing in for the
// clearance).  Baked into the vertex like the ambient occlusion (ao.glsl),
// at the block's generation: the frame pays nothing for it.
//
// The ray starts half a cell off the surface along the normal and takes
// u_shadow_steps steps whose lengths grow geometrically from one cell to
// u_shadow_reach world units: fine near the surface, where the shadow's
// edge is, coarse far out, where only mountains block the sun.  A step in
// the block's density volume reads it: trilinearly for the first
// SUN_LINEAR_STEPS (5), where the shadow's edge forms, the nearest sample
// after them (the penumbra is wider than a cell there; a fifth less time
// for the vertex pass, docs/PERFORMANCE.md); one outside reads
// density_far() for a block of a larger world (AO_FAR_OUTSIDE), and for a
// lone volume, where nothing outside is drawn, ends the ray: open sky.
//
// Visibility: min over the steps of clamp((iso - d) / (u_shadow_soft * t)),
// smoothed; 0 = the sun is hidden, 1 = in full sun.  The CPU reference is
// tests/test_shadows.c.

#define SUN_LINEAR_STEPS 5
float density_far(vec3 ws); // the field's, without its finest detail (app/extract/field.h)

// the stored density at grid coordinates g (within [lo, hi - 1]), trilinear
float D_lin(vec3 g)
{
	vec3 f0 = floor(g), f = g - f0;
	ivec3 c = ivec3(f0);
	float d00 = mix(D(c), D(c + ivec3(1, 0, 0)), f.x);
	float d10 = mix(D(c + ivec3(0, 1, 0)), D(c + ivec3(1, 1, 0)), f.x);
	float d01 = mix(D(c + ivec3(0, 0, 1)), D(c + ivec3(1, 0, 1)), f.x);
	float d11 = mix(D(c + ivec3(0, 1, 1)), D(c + ivec3(1, 1, 1)), f.x);
	return mix(mix(d00, d10, f.y), mix(d01, d11, f.y), f.z);
}

// towards the sun, from light_el / light_az (shade.glsl's u_sun_dir, made
// here: the extraction passes do not get the renderer's uniforms)
vec3 sun_ray_dir()
{
	float el = radians(u_light_el), az = radians(u_light_az);
	return vec3(cos(el) * cos(az), sin(el), cos(el) * sin(az));
}

// one step of the ray at distance t: false when it left a lone volume
bool sun_step(vec3 start, vec3 dir, float t, bool linear, vec3 lo, vec3 hi, inout float res)
{
	vec3 p = start + dir * t;
	vec3 g = (p - u_origin) / u_cell - vec3(u_base);
	float d;
	if (all(greaterThanEqual(g, lo)) && all(lessThanEqual(g, hi)))
		d = linear ? D_lin(g) : D(ivec3(floor(g + 0.5)));
	else
#ifdef AO_FAR_OUTSIDE
		d = density_far(p);
#else
		return false; // a lone volume: nothing outside
#endif
	res = min(res, clamp((u_iso - d) / (u_shadow_soft * t), 0.0, 1.0));
	return true;
}

float sun_visibility(vec3 ws, vec3 nrm)
{
	int n = u_shadow_steps;
	if (n <= 0)
		return 1.0;
	vec3 dir = sun_ray_dir();
	vec3 lo = vec3(-u_margin), hi = vec3(u_cells + u_margin) - 0.001;
	vec3 start = ws + nrm * (0.5 * u_cell);
	// t_k = u_cell * q^k, k = 1 .. n: the last at the reach
	float q = pow(max(u_shadow_reach / u_cell, 1.0), 1.0 / float(n));
	float t = u_cell, res = 1.0;
	int k = 0;
	bool in_vol = true;
	// near the surface, where the shadow's edge is, trilinear; farther, the
	// nearest sample (the penumbra is wider than a cell there)
	int nl = min(n, SUN_LINEAR_STEPS);
	do { // tested at the end (ao.glsl says why)
		t *= q;
		in_vol = sun_step(start, dir, t, true, lo, hi, res);
	} while (++k < nl && res > 0.0 && in_vol);
	if (k < n && res > 0.0 && in_vol) {
		do {
			t *= q;
			in_vol = sun_step(start, dir, t, false, lo, hi, res);
		} while (++k < n && res > 0.0 && in_vol);
	}
	return res * res * (3.0 - 2.0 * res);
}
