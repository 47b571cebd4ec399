// isoterra — the curves' 2D displacement map (Nascimento 2020 ch. 8): one
// invocation per texel, disp = Θ_closest · (h - H(x,z)), H the heightmap
// (bilinear, with BAKE_HEIGHTMAP) or 0.
//   default        closed form + spatial hash, over the 8x8 tiles that
//                  overlap some quadratic's padded box (the host lists
//                  them and zeroes the map first): texels no curve reaches
//                  cost nothing
//   BAKE_DENSE     closed form + hash, every texel (the thesis's dispatch)
//   CURVE_ITERATIVE (+ BAKE_DENSE) the benchmark's baseline: 32 line
//                  segments per curve, every curve, no hash
//   BAKE_MATERIAL  the road map instead (render.frag): per texel the
//                  curve of any kind with a surface that paints it most,
//                  as two words of half floats, (paint, surface) and
//                  (height - u_bake_y0, 0)
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#include "curves.glsl"
#ifdef BAKE_HEIGHTMAP
#include "heightmap.glsl"
#endif
#ifdef BAKE_MATERIAL
layout(std430, binding = BIND_AUX_OUT) restrict writeonly buffer BakeOut { uint bake_out[]; };

// The most paint of the curves with a surface (every kind: a bridge's deck
// and a tunnel's floor are roads too), so that a narrow path crossing a
// wide road leaves the road painted: (paint, surface, height at the
// closest point) of the curve with the most, on a tie the wider (a path
// crossing a road is the road's), then the nearer.
vec3 material_at(vec2 pos)
{
	ivec2 piv = curve_cell(pos);
	float bd = 1e30, bw = 0.0, kind = 0.0;
	vec3 best = vec3(0.0);
	best.x = -1.0;
	for (int i = piv.x; i < piv.x + piv.y; i++) {
		int f = curve_index(i);
		vec4 prm = curve_prm(f);
		if (prm.w == 0.0 || !curve_near(f, pos))
			continue;
		vec4 cl = curve_closest(f, pos);
		float ad = abs(cl.x);
		// the paint covers the flat part, w/2, fading over a tenth of it
		float paint = 1.0 - smoothstep(prm.x * 0.9, prm.x * 1.1, ad);
		if (paint > best.x || (paint == best.x && (prm.x > bw || (prm.x == bw && ad < bd)))) {
			bw = prm.x;
			bd = ad;
			kind = prm.z;
			best = vec3(paint, prm.w, cl.z);
		}
	}
	// a surface curve's ground is the blended, inclined height the carve
	// gives (crossings average), a deck's and a floor's their own
	if (best.x > 0.0 && kind < float(CURVE_KIND_TUNNEL))
		best.z = curve_eval(pos).x;
	return vec3(max(best.x, 0.0), best.yz);
}
#else
layout(std430, binding = BIND_AUX_OUT) restrict writeonly buffer BakeOut { float bake_out[]; };
#endif
#ifndef BAKE_DENSE
layout(std430, binding = BIND_AUX_IN) restrict readonly buffer BakeTiles { uint bake_tiles[]; }; // (tx | ty << 16)
uniform int u_bake_ntiles;
uniform int u_bake_groups_x;
#endif
uniform ivec2 u_bake_res;
uniform vec2 u_bake_origin; // x, z of the map's corner
uniform vec2 u_bake_texel;  // world size of a texel
#ifdef BAKE_MATERIAL
uniform float u_bake_y0;    // heights are stored less this (half floats: near 0 is finer)
#endif

void main()
{
#ifdef BAKE_DENSE
	ivec2 id = ivec2(gl_GlobalInvocationID.xy);
#else
	int tile = int(gl_WorkGroupID.y) * u_bake_groups_x + int(gl_WorkGroupID.x);
	if (tile >= u_bake_ntiles)
		return;
	uint t = bake_tiles[tile];
	ivec2 id = ivec2(int(t & 0xffffu), int(t >> 16)) * 8 + ivec2(gl_LocalInvocationID.xy);
#endif
	if (id.x >= u_bake_res.x || id.y >= u_bake_res.y)
		return;
	vec2 xz = u_bake_origin + (vec2(id) + 0.5) * u_bake_texel;
#ifdef BAKE_MATERIAL
	vec3 m = material_at(xz);
	int i = 2 * (id.x + id.y * u_bake_res.x);
	bake_out[i] = packHalf2x16(m.xy);
	bake_out[i + 1] = packHalf2x16(vec2(m.z - u_bake_y0, 0.0));
#else
	vec4 e = curve_eval(xz);
#ifdef BAKE_HEIGHTMAP
	float base = hm_height(xz, false);
#else
	float base = 0.0;
#endif
	bake_out[id.x + id.y * u_bake_res.x] = e.y * (e.x - base);
#endif
}
