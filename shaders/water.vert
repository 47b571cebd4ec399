// isoterra — water: a horizontal quad at u_water_level over u_water_rect.
uniform mat4 u_viewproj;
uniform vec4 u_water_rect; // x0, z0, x1, z1
out vec3 v_pos;

void main()
{
	vec2 c = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
	v_pos = vec3(mix(u_water_rect.x, u_water_rect.z, c.x), u_water_level, mix(u_water_rect.y, u_water_rect.w, c.y));
	gl_Position = u_viewproj * vec4(v_pos, 1.0);
}
