// isoterra — terrain vertex shader: world-space position and normal through;
// u_sink > 0 moves the surface that far into the rock along its normal (a
// level of detail rising out of, or sinking behind, the coarser one).
// What varies slowly over the surface is worked out here, per vertex, and
// interpolated: the aerial perspective's share (fog_amount: smooth over a
// triangle of a few pixels) and the soil's slow variation (the surface
// texture's height at 0.011 cycles a unit: a texel is 0.7 units, wider than
// the coarsest LOD's cells) — per pixel, the two were 8 % of a 640x480
// world frame on a software rasterizer (docs/PERFORMANCE.md).
#include "vertex.glsl"
#include "shade.glsl"
layout(location = 0) in vec3 a_pos;
layout(location = 1) in uint a_nao; // normal, ambient and sun visibility, packed (vertex.glsl)
uniform mat4 u_viewproj;
uniform float u_sink;
uniform vec3 u_eye;
uniform float u_fog_density;
layout(binding = TEX_SURFACE) uniform highp sampler2D u_surface; // A: height (surface_tex.c)
out vec3 v_pos;
out vec3 v_nrm;
out float v_ao;
out float v_sun;
out float v_fog;  // the fraction of the light the air replaces (shade.glsl)
out float v_slow; // the soil's slow variation, 0 .. 1
const float SLOW_FREQ = 0.011;
// the depth pre-pass (depth.frag) runs this too: the same depth, bit for bit
invariant gl_Position;

void main()
{
	vec3 n = unpack_normal(a_nao);
	v_pos = a_pos; // shaded where it is: no texture swimming while it rises
	v_nrm = n;
	v_ao = unpack_ao(a_nao);
	v_sun = unpack_sun(a_nao);
	v_fog = fog_amount(a_pos, u_eye, u_fog_density);
	v_slow = textureLod(u_surface, a_pos.xz * SLOW_FREQ, 0.0).a;
	gl_Position = u_viewproj * vec4(a_pos - n * u_sink, 1.0);
}
