// isoterra — terrain vertex shader: world-space position and normal through;
// u_sink > 0 moves the surface that far into the rock along its normal (a
// level of detail rising out of, or sinking behind, the coarser one).
#include "vertex.glsl"
layout(location = 0) in vec3 a_pos;
layout(location = 1) in uint a_nao; // normal, ambient and sun visibility, packed (vertex.glsl)
uniform mat4 u_viewproj;
uniform float u_sink;
out vec3 v_pos;
out vec3 v_nrm;
out float v_ao;
out float v_sun;
// the depth pre-pass (depth.frag) runs this too: the same depth, bit for bit
invariant gl_Position;

void main()
{
	vec3 n = unpack_normal(a_nao);
	v_pos = a_pos; // shaded where it is: no texture swimming while it rises
	v_nrm = n;
	v_ao = unpack_ao(a_nao);
	v_sun = unpack_sun(a_nao);
	gl_Position = u_viewproj * vec4(a_pos - n * u_sink, 1.0);
}
