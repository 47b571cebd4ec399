// isoterra — the curves' 2D displacement map (Nascimento 2020 ch. 8): one
// invocation per texel, disp = Θ_closest · (h - H(x,z)), H the heightmap
// (bilinear) when one is loaded, else 0.  Compiled as is (closed form +
// spatial hash) and with CURVE_ITERATIVE (32 line segments per curve, every
// curve, no hash) for the benchmark's baseline.
layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;
#include "curves.glsl"
#include "heightmap.glsl"
layout(std430, binding = 12) restrict writeonly buffer BakeOut { float bake_out[]; };
uniform ivec2 u_bake_res;
uniform vec2 u_bake_origin; // x, z of the map's corner
uniform vec2 u_bake_texel;  // world size of a texel

void main()
{
	ivec2 id = ivec2(gl_GlobalInvocationID.xy);
	if (id.x >= u_bake_res.x || id.y >= u_bake_res.y)
		return;
	vec2 xz = u_bake_origin + (vec2(id) + 0.5) * u_bake_texel;
	vec4 e = curve_eval(xz);
	float base = u_heightmap_size.x > 0 ? hm_height(xz, false) : 0.0;
	bake_out[id.x + id.y * u_bake_res.x] = e.y * (e.x - base);
}
