// isoterra — test hook for the curve functions (tests/test_curves.c).
//   mode 0: in[4i..4i+3] = quadratic p0, p1, p2 (x, y, z, I) and (x, z, -, -)
//           -> out[i] = curve_closest-style (signed d, t, h, I)
//   mode 1: in[i] = (x, z, y, d) -> out[i] = (curve_eval(xz).xyz, carve_density)
//   mode 2: in[i] = (x, z, -, -) -> out[i] = (hm_height(xz, true), hm_height(xz, false), 0, 0)
layout(local_size_x = WG_SIZE) in;
#include "carve.glsl"
layout(std430, binding = BIND_AUX_IN) restrict readonly buffer TestIn { vec4 test_in[]; };
layout(std430, binding = BIND_AUX_OUT) restrict writeonly buffer TestOut { vec4 test_out[]; };
uniform int u_test_mode;
uniform int u_test_n;

void main()
{
	int i = int(gl_GlobalInvocationID.x);
	if (i >= u_test_n)
		return;
	if (u_test_mode == 0) {
		vec4 c0 = test_in[4 * i], c1 = test_in[4 * i + 1], c2 = test_in[4 * i + 2];
		vec2 pos = test_in[4 * i + 3].xy;
		float t = quad_closest_t(c0.xz, c1.xz, c2.xz, pos);
		float u = 1.0 - t;
		vec2 A = c1.xz - c0.xz, B = c0.xz - 2.0 * c1.xz + c2.xz;
		vec2 off = pos - (c0.xz + (2.0 * A + B * t) * t);
		float side = curve_cross(A + B * t, off) >= 0.0 ? 1.0 : -1.0;
		test_out[i] = vec4(side * sqrt(dot(off, off)), t, u * u * c0.y + 2.0 * u * t * c1.y + t * t * c2.y,
				   u * u * c0.w + 2.0 * u * t * c1.w + t * t * c2.w);
	} else if (u_test_mode == 1) {
		vec4 q = test_in[i];
		vec4 e = curve_eval(q.xy);
		test_out[i] = vec4(e.xyz, carve_density(vec3(q.x, q.z, q.y), q.w));
	} else {
		vec2 xz = test_in[i].xy;
		test_out[i] = vec4(u_heightmap_size.x > 0 ? hm_height(xz, true) : 0.0,
				   u_heightmap_size.x > 0 ? hm_height(xz, false) : 0.0, 0.0, 0.0);
	}
}
