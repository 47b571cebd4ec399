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
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#include "curves.glsl"
#ifdef BAKE_HEIGHTMAP
#include "heightmap.glsl"
#endif
layout(std430, binding = BIND_AUX_OUT) restrict writeonly buffer BakeOut { float bake_out[]; };
#ifndef BAKE_DENSE
layout(std430, binding = BIND_AUX_IN) restrict readonly buffer BakeTiles { uint bake_tiles[]; }; // (tx | ty << 16)
uniform int u_bake_ntiles;
uniform int u_bake_groups_x;
#endif
uniform ivec2 u_bake_res;
uniform vec2 u_bake_origin; // x, z of the map's corner
uniform vec2 u_bake_texel;  // world size of a texel

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
	vec4 e = curve_eval(xz);
#ifdef BAKE_HEIGHTMAP
	float base = hm_height(xz, false);
#else
	float base = 0.0;
#endif
	bake_out[id.x + id.y * u_bake_res.x] = e.y * (e.x - base);
}
