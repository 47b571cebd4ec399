// isoterra — terrain editing in the density function: the curves' cut and
// fill (Nascimento 2020, for a volume instead of a displacement map) and
// the heightmap base terrain.  Mirrored in app/edit/carve_ref.c.
//
// Inside a curve's profile the density is pulled toward that of a flat
// ground at the curve's (blended, inclined) height h:
//   d' = d + Θ · curve_strength · ((h - y) - d)
// so at Θ = 1 the surface is exactly at h: a road cuts through a mountain
// (rock above h removed) and crosses a valley on an embankment (rock below
// h added); the falloff λ gives the side slopes; a river below the surface
// carves a canyon.
//
// A tunnel curve is no surface: it carves a tube and leaves the rock above
// (curves.glsl, tunnel_eval), and carries its floor on an embankment in the
// open:  d' = min(max(d, fill), tube), blended by curve_strength.

// HAS_CURVES 0: the edit state holds no curves, so the carve is not
// compiled, nor the curves' storage block declared (the field provider,
// app/terrain/terrain.c, defines it in the terrain's programs; every other
// program keeps the code and its u_curve_count check).
#ifndef HAS_CURVES
#define HAS_CURVES 1
#endif
#include "curves.glsl"
#include "heightmap.glsl"

// HAS_TUNNELS 0: no tunnel curve, so the second walk over the curves (in
// 3D) is not compiled.
#ifndef HAS_TUNNELS
#define HAS_TUNNELS 1
#endif

float carve_density(vec3 ws, float d)
{
#if HAS_CURVES && TERM_CURVE_STRENGTH
	if (u_curve_count == 0)
		return d;
	vec4 e = curve_eval(ws.xz);
	float k = e.y * u_curve_strength;
	d += k * ((e.x - ws.y) - d);
#if HAS_TUNNELS
	vec2 tn = tunnel_eval(ws);
	d += u_curve_strength * (min(max(d, tn.x), tn.y) - d);
#endif
	return d;
#else
	return d;
#endif
}
