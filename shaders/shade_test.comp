// isoterra — the shading's functions on given inputs (tests only:
// tests/test_shading.c): per item, in: eye, pos (fog), or alt, up_n, slow,
// hgt (snow), or a colour (gamma); out: the fog amount and the haze colour
// towards pos, or the snow cover, or the colour through albedo_to_linear
// (.xyz) and the first channel through linear_to_srgb (.w).
layout(local_size_x = WG_SIZE) in;
#include "shade.glsl"
layout(std430, binding = BIND_AUX_IN) restrict readonly buffer TestIn { vec4 test_in[]; };
layout(std430, binding = BIND_AUX_OUT) restrict writeonly buffer TestOut { vec4 test_out[]; };
uniform int u_mode; // 0: fog (in: 2 vec4 an item, eye and pos), 1: snow (in: 1 vec4), 2: gamma (1 vec4)
uniform uint u_n;
uniform float u_density;

void main()
{
	uint i = gl_GlobalInvocationID.x;
	if (i >= u_n)
		return;
	if (u_mode == 0) {
		vec3 eye = test_in[2u * i].xyz, pos = test_in[2u * i + 1u].xyz;
		vec3 h = haze_color(normalize(pos - eye));
		test_out[i] = vec4(fog_amount(pos, eye, u_density), h);
	} else if (u_mode == 1) {
		vec4 a = test_in[i];
		test_out[i] = vec4(snow_cover(a.x, a.y, a.z, a.w), 0.0, 0.0, 0.0);
	} else {
		vec3 c = test_in[i].xyz;
		test_out[i] = vec4(albedo_to_linear(c), linear_to_srgb(c).x);
	}
}
