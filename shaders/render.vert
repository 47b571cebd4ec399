// isoterra — terrain vertex shader: world-space position and normal through;
// u_sink > 0 moves the surface that far into the rock along its normal (a
// level of detail rising out of, or sinking behind, the coarser one).
layout(location = 0) in vec4 a_pos;
layout(location = 1) in vec4 a_nrm;
uniform mat4 u_viewproj;
uniform float u_sink;
out vec3 v_pos;
out vec3 v_nrm;
out float v_ao;

void main()
{
	v_pos = a_pos.xyz; // shaded where it is: no texture swimming while it rises
	v_nrm = a_nrm.xyz;
	v_ao = a_nrm.w;
	gl_Position = u_viewproj * vec4(a_pos.xyz - a_nrm.xyz * u_sink, 1.0);
}
