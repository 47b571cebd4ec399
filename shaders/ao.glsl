// isoterra — ambient occlusion of a vertex from rays through the density
// field (GPU Gems 3 ch.1 §4): short range from the block's density volume
// (nearest samples, u_ao_short_steps steps of one cell), long range
// (u_ao_long_steps steps of u_ao_long_step world units) from the same
// volume, nearest sample too: one load a step, not an evaluation of the
// field (trilinear samples cost eight loads for no visible difference).
// A step that lands outside the volume: for a block of a larger world
// (AO_FAR_OUTSIDE, the pipeline defines it for grids with an extra margin)
// the density function with its highest octaves dropped, so gorges and
// overhangs beyond the block darken too; for a lone volume, where nothing
// outside is drawn, the volume's nearest point.  (A compile-time switch: a
// SIMD driver runs both sides of a divergent branch.)  Returns visibility,
// 1 = open sky.
// Rays: a spherical Fibonacci set of u_ao_rays directions, the same for
// every vertex.

float density_far(vec3 ws); // the field's, without its finest detail (app/extract/field.h)

// Ray i of n: height y = 1 - (2i + 1) / n, azimuth i times the golden
// angle; (cos, sin) of the azimuth is cs, advanced by one rotation per ray
// (no trigonometry per ray and vertex).
const vec2 AO_GOLDEN = vec2(-0.73736888, 0.67549029); // cos, sin of 2.39996323
vec3 ao_dir(int i, int n, inout vec2 cs)
{
	float y = 1.0 - (2.0 * float(i) + 1.0) / float(n);
	float r = sqrt(max(0.0, 1.0 - y * y));
	vec3 d = vec3(r * cs.x, y, r * cs.y);
	cs = vec2(cs.x * AO_GOLDEN.x - cs.y * AO_GOLDEN.y, cs.x * AO_GOLDEN.y + cs.y * AO_GOLDEN.x);
	return d;
}

// the stored density nearest to grid coordinates g (g within [lo, hi])
float D_near(vec3 g)
{
	return D(ivec3(floor(g + 0.5)));
}

float ao_visibility(vec3 ws, vec3 nrm)
{
	int n = u_ao_rays;
	if (n <= 0)
		return 1.0;
	ivec3 lo = ivec3(-u_margin), hi = u_cells + u_margin;
	vec3 gpos = (ws - u_origin) / u_cell - vec3(u_base); // grid coordinates
	float vis = 0.0;
	vec2 cs = vec2(1.0, 0.0);
	// The loops test at their end (do-while), their counts checked first: a
	// loop testing at its top makes llvmpipe run one more, masked, round
	// after the last (fractal.glsl), here a whole ray.
	int r = 0;
	do {
		vec3 dir = ao_dir(r, n, cs);
		if (dot(dir, nrm) < -0.2)
			dir = reflect(dir, nrm); // rays into the rock tell nothing
		float v = 1.0;
		int s = 1;
		if (u_ao_short_steps >= 1) {
			do {
				ivec3 c = ivec3(floor(gpos + dir * (float(s) + 0.5) + 0.5));
				c = clamp(c, lo, hi);
				v *= clamp(1.0 - (D(c) - u_iso) * u_ao_short_k, 0.0, 1.0);
			} while (++s <= u_ao_short_steps);
		}
		s = 1;
		if (u_ao_long_steps >= 1) {
			do {
				float dist = float(s) * u_ao_long_step;
				vec3 q = gpos + dir * (dist / u_cell);
#ifdef AO_FAR_OUTSIDE
				float d;
				if (all(greaterThanEqual(q, vec3(lo))) && all(lessThanEqual(q, vec3(hi))))
					d = D_near(q);
				else
					d = density_far(ws + dir * dist);
#else
				float d = D_near(clamp(q, vec3(lo), vec3(hi)));
#endif
				v *= clamp(1.0 - (d - u_iso) * u_ao_long_k, 0.0, 1.0);
			} while (++s <= u_ao_long_steps);
		}
		vis += v;
	} while (++r < n);
	return vis / float(n);
}
