// isoterra — the sky: the haze at the horizon (lit towards the sun: the
// fog's colour far away, shade.glsl), the zenith's blue above it, the sun's
// disk with a limb and its glare; in caves, the dark.
in vec3 v_world;
uniform vec3 u_eye;
out vec4 frag;
#include "shade.glsl"

void main()
{
	vec3 d = normalize(v_world - u_eye);
	if (u_shape == SHAPE_CAVES) { // no sky under the rock: the dark behind the passages
		frag = vec4(display(haze_color(d)), 1.0);
		return;
	}
	vec3 col = mix(haze_color(d), srgb_to_linear(SKY_ZENITH), pow(clamp(d.y, 0.0, 1.0), 0.6));
	float s = max(dot(d, sun_dir()), 0.0);
	// the disk (about 1.5 degrees across, a soft limb) and a wide glare
	float disk = smoothstep(0.99955, 0.99975, s);
	col += SUN_COLOR * (disk * 12.0 + pow(s, 600.0) * 2.0 + pow(s, 24.0) * 0.12) * u_sun;
	frag = vec4(display(col), 1.0);
}
