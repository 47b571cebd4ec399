// isoterra — water: deep colour, sky reflection by Fresnel (Schlick), sun
// glint, small moving waves from the surface texture, fog.
in vec3 v_pos;
uniform vec3 u_eye;
uniform float u_fog_density;
layout(binding = TEX_SURFACE) uniform highp sampler2D u_surface;
out vec4 frag;
#include "shade.glsl"

void main()
{
	vec2 uv = v_pos.xz * 0.15;
	vec2 w1 = texture(u_surface, uv + vec2(u_time * 0.02, u_time * 0.013)).gb - 0.5;
	vec2 w2 = texture(u_surface, uv * 2.3 - vec2(u_time * 0.017, -u_time * 0.021)).gb - 0.5;
	vec3 n = normalize(vec3((w1.x + w2.x) * 0.6, 1.0, (w1.y + w2.y) * 0.6));
	vec3 v = normalize(u_eye - v_pos);
	float f = 0.02 + 0.98 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
	vec3 r = reflect(-v, n);
	vec3 sky = mix(srgb_to_linear(SKY_HORIZON), srgb_to_linear(SKY_ZENITH), pow(clamp(r.y, 0.0, 1.0), 0.6));
	vec3 deep = srgb_to_linear(vec3(0.05, 0.20, 0.26));
	vec3 col = mix(deep, sky, f);
	col += vec3(1.0, 0.9, 0.7) * pow(max(dot(r, sun_dir()), 0.0), 200.0) * u_sun * 2.0;
	col = apply_fog(col, v_pos, u_eye, u_fog_density);
	frag = vec4(linear_to_srgb(col), mix(0.72, 0.95, f));
}
