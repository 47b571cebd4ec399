// isoterra — sky: one full-screen triangle at the far plane.
uniform mat4 u_inv_viewproj;
out vec3 v_world;

void main()
{
	vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
	vec4 w = u_inv_viewproj * vec4(p, 1.0, 1.0);
	v_world = w.xyz / w.w;
	gl_Position = vec4(p, 1.0, 1.0);
}
