// isoterra — water: a horizontal quad at u_water_level over u_water_rect, or
// (u_water_sphere > 0, planet mode) a sphere of that radius around
// u_water_centre, WATER_SEG_U x WATER_SEG_V quads of latitude and longitude
// made from gl_VertexID (six vertices a quad, no buffers).
uniform mat4 u_viewproj;
uniform vec4 u_water_rect; // x0, z0, x1, z1
uniform float u_water_sphere; // sphere radius; 0: the plane
uniform vec3 u_water_centre;
out vec3 v_pos;

#define WATER_SEG_U 96
#define WATER_SEG_V 48

void main()
{
	if (u_water_sphere > 0.0) {
		int q = gl_VertexID / 6, k = gl_VertexID - 6 * (gl_VertexID / 6);
		// corners of the quad's two triangles, counter-clockwise from outside
		int dv = (k == 1 || k == 2 || k == 4) ? 1 : 0, du = (k == 2 || k == 4 || k == 5) ? 1 : 0;
		int u = q % WATER_SEG_U + du, v = q / WATER_SEG_U + dv;
		float lon = float(u) * (6.2831853 / float(WATER_SEG_U)), lat = float(v) * (3.14159265 / float(WATER_SEG_V));
		vec3 dir = vec3(sin(lat) * cos(lon), -cos(lat), sin(lat) * sin(lon));
		v_pos = u_water_centre + u_water_sphere * dir;
	} else {
		vec2 c = vec2(float(gl_VertexID & 1), float((gl_VertexID >> 1) & 1));
		v_pos = vec3(mix(u_water_rect.x, u_water_rect.z, c.x), u_water_level,
			     mix(u_water_rect.y, u_water_rect.w, c.y));
	}
	gl_Position = u_viewproj * vec4(v_pos, 1.0);
}
