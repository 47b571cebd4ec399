// isoterra — terrain vertex shader: world-space position and normal through.
layout(location = 0) in vec4 a_pos;
layout(location = 1) in vec4 a_nrm;
uniform mat4 u_viewproj;
out vec3 v_pos;
out vec3 v_nrm;
out float v_ao;

void main()
{
	v_pos = a_pos.xyz;
	v_nrm = a_nrm.xyz;
	v_ao = a_nrm.w;
	gl_Position = u_viewproj * vec4(a_pos.xyz, 1.0);
}
