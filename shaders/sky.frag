// isoterra — sky gradient from the horizon to the zenith, a soft sun.
in vec3 v_world;
uniform vec3 u_eye;
out vec4 frag;
#include "shade.glsl"

void main()
{
	vec3 d = normalize(v_world - u_eye);
	vec3 col = mix(srgb_to_linear(SKY_HORIZON), srgb_to_linear(SKY_ZENITH), pow(clamp(d.y, 0.0, 1.0), 0.6));
	float s = max(dot(d, sun_dir()), 0.0);
	col += vec3(1.0, 0.9, 0.7) * (pow(s, 400.0) * 4.0 + pow(s, 12.0) * 0.15) * u_sun;
	frag = vec4(linear_to_srgb(col), 1.0);
}
