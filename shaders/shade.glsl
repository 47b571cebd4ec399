// isoterra — shared by the terrain, water and sky shaders: sun direction,
// sky colours, fog, gamma.
const vec3 SKY_HORIZON = vec3(0.62, 0.74, 0.88); // sRGB; also the clear colour
const vec3 SKY_ZENITH = vec3(0.30, 0.48, 0.78);

vec3 srgb_to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 linear_to_srgb(vec3 c) { return pow(max(c, 0.0), vec3(1.0 / 2.2)); }

// towards the sun: from light_el / light_az, worked out once a frame on
// the CPU (app/render/render.c)
uniform vec3 u_sun_dir;
vec3 sun_dir() { return u_sun_dir; }

// distance fog, thinner with height, towards the horizon colour
vec3 apply_fog(vec3 col, vec3 pos, vec3 eye, float density)
{
	float dist = length(pos - eye);
	float h = max(min(pos.y, eye.y), -50.0);
	float k = density * u_fog * exp(-u_fog_height * max(h, 0.0));
	float fog = 1.0 - exp(-dist * k);
	return mix(col, srgb_to_linear(SKY_HORIZON), clamp(fog, 0.0, 1.0));
}
