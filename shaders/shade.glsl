// isoterra — shared by the terrain, water and sky shaders: sun direction,
// sky colours, aerial perspective (height fog with in-scattering towards
// the sun), tone mapping, gamma.  Light is summed in linear space and
// tone-mapped once, at the end of each shader (display()).
const vec3 SKY_HORIZON = vec3(0.62, 0.74, 0.88); // sRGB; also the clear colour
const vec3 SKY_ZENITH = vec3(0.30, 0.48, 0.78);
const vec3 SUN_COLOR = vec3(1.0, 0.95, 0.86);    // linear
const vec3 SUN_HAZE = vec3(1.0, 0.86, 0.62);     // linear: the air lit towards the sun
const float EXPOSURE = 0.85;

// Gamma 2.2 both ways.  Of constant colours, pow (folded by the compiler);
// of a colour per pixel, least-squares fits that a software rasterizer
// runs in a few multiplies and square roots instead of six pows' log2 and
// exp2 (a twelfth of a 640x480 world frame on llvmpipe): within 1.2 levels
// of 255 of pow (albedo, up to 1.3), within 0.53 (display, 0 .. 1);
// tests/test_shading.c holds them to that.
vec3 srgb_to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 albedo_to_linear(vec3 c)
{
	vec3 c2 = c * c;
	return c2 * (0.63985677 + c * (0.52951925 - 0.16584197 * c));
}
vec3 linear_to_srgb(vec3 c)
{
	vec3 s1 = sqrt(max(c, 0.0)), s2 = sqrt(s1), s3 = sqrt(s2);
	return 0.86218152 * s1 + 0.22088813 * s2 - 0.02558681 * c - 0.05760610 * s3;
}

// Filmic tone mapping (Narkowicz's fit of the ACES curve): a toe that
// deepens the shadows, a shoulder that rolls bright snow and the sun's
// glare off instead of clipping them.
vec3 tonemap(vec3 x)
{
	x *= EXPOSURE;
	return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// linear light -> the colour written
vec3 display(vec3 c) { return linear_to_srgb(tonemap(c)); }

// towards the sun: from light_el / light_az, worked out once a frame on
// the CPU (app/render/render.c)
uniform vec3 u_sun_dir;
vec3 sun_dir() { return u_sun_dir; }

// The colour of the air along direction rd far away: the horizon's, lit
// towards the sun (the in-scattering of Quilez's "better fog"); in caves,
// darkness.  The sky (sky.frag) has it at its horizon, so the fog ends in
// the sky behind it.
const vec3 CAVE_DARK = vec3(0.012, 0.010, 0.009); // linear: the air deep in a cave
vec3 haze_color(vec3 rd)
{
	// caves: no sky, the far passages fade into the dark
	if (u_shape == SHAPE_CAVES)
		return CAVE_DARK;
	float s = max(dot(rd, sun_dir()), 0.0);
	return mix(srgb_to_linear(SKY_HORIZON), SUN_HAZE, 0.55 * s * s * s * s * s * s * s * s * min(u_sun, 1.5));
}

// Aerial perspective: the fog's density falls with height as
// exp(-fog_height * y), integrated along the ray from the eye (thick in the
// valleys, thin on the peaks, a low view through more air than a high
// one): the fraction of the light from pos that the air replaces.
// tests/test_shading.c integrates the same on the CPU, numerically.
float fog_amount(vec3 pos, vec3 eye, float density)
{
	vec3 ray = pos - eye;
	float dist = length(ray);
	float b = u_fog_height, dy = ray.y;
	float y0 = max(eye.y, -50.0);
	// the integral of exp(-b y) over the ray, per unit of length: exp(-b y0) * (1 - exp(-b dy)) / (b dy)
	float bdy = b * dy;
	float mean = abs(bdy) > 1e-3 ? (1.0 - exp(-bdy)) / bdy : 1.0 - 0.5 * bdy;
	float k = density * u_fog * exp(-b * y0) * mean;
	return clamp(1.0 - exp(-dist * min(k, 50.0 / max(dist, 1e-3))), 0.0, 1.0);
}

// ... towards haze_color
vec3 apply_fog(vec3 col, vec3 pos, vec3 eye, float density)
{
	vec3 ray = pos - eye;
	return mix(col, haze_color(ray / max(length(ray), 1e-6)), fog_amount(pos, eye, density));
}

// Snow cover 0 .. 1 at altitude alt (over the snow line u_snow_line) on
// ground whose normal's up component is up_n: above the line, which
// wanders by 1.5 units with the slow variation `slow` (0 .. 1) and is
// frayed by the texture's height `hgt` (0 .. 1, 1.6 units); on ground flat
// enough to hold it, the steeper the higher (up_n 0.82 at the line, 0.62
// 8 units over it).  None where up_n <= 0.5, nor 2.2 units under the
// line; full cover where up_n >= 0.92 from 2.2 units over it; more snow
// the higher and the flatter (tests/test_shading.c).
float snow_cover(float alt, float up_n, float slow, float hgt)
{
	float over = alt - u_snow_line + (slow - 0.5) * 1.5 + (hgt - 0.5) * 1.6;
	float hold = mix(0.82, 0.62, clamp(over * 0.125, 0.0, 1.0));
	return smoothstep(-0.6, 0.6, over) * smoothstep(hold - 0.06, hold + 0.04, up_n + (hgt - 0.5) * 0.12);
}
