// isoterra — terrain fragment shader: directional sun + hemispheric ambient,
// slope/altitude colouring, distance fog, gamma-correct output.
in vec3 v_pos;
in vec3 v_nrm;
in float v_ao;
uniform vec3 u_eye;
uniform float u_fog_density;
uniform float u_fade; // < 1: dissolve (ordered dither) while a block fades in/out
out vec4 frag;

const vec3 SKY = vec3(0.62, 0.74, 0.88); // sRGB of the clear colour

vec3 srgb_to_linear(vec3 c) { return pow(c, vec3(2.2)); }

float bayer4(ivec2 p)
{
	int m[16] = int[16](0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5);
	return (float(m[(p.y & 3) * 4 + (p.x & 3)]) + 0.5) / 16.0;
}

void main()
{
	if (u_fade < 1.0 && u_fade <= bayer4(ivec2(gl_FragCoord.xy)))
		discard;
	vec3 n = normalize(v_nrm);
	float back = gl_FrontFacing ? 1.0 : 0.45; // inside of the volume's cut
	if (!gl_FrontFacing)
		n = -n;
	float el = radians(u_light_el), az = radians(u_light_az);
	vec3 l = vec3(cos(el) * cos(az), sin(el), cos(el) * sin(az));

	// albedo: rock with strata on steep faces, grass/soil on flat ground
	float strata = 0.5 + 0.5 * sin(v_pos.y * 1.9 + sin(v_pos.x * 0.13 + v_pos.z * 0.11) * 2.0);
	strata = strata * strata;
	vec3 rock = mix(vec3(0.47, 0.38, 0.30), vec3(0.62, 0.52, 0.40), strata);
	vec3 grass = mix(vec3(0.24, 0.36, 0.13), vec3(0.38, 0.42, 0.20), strata);
	float flat_ground = smoothstep(0.62, 0.86, n.y);
	vec3 albedo = mix(rock, grass, flat_ground);
	albedo = mix(albedo, vec3(0.85, 0.87, 0.90), smoothstep(6.0, 10.0, v_pos.y) * smoothstep(0.5, 0.8, n.y));
	albedo = srgb_to_linear(albedo);

	float ndl = max(dot(n, l), 0.0);
	vec3 sky_amb = srgb_to_linear(SKY) * (0.55 + 0.45 * n.y);
	vec3 ground_amb = vec3(0.09, 0.07, 0.05) * (0.5 - 0.5 * n.y);
	float occ = mix(1.0, clamp(v_ao, 0.0, 1.0), u_ao_strength);
	vec3 light = u_sun * vec3(1.0, 0.95, 0.86) * ndl * mix(1.0, occ, 0.5) + u_ambient * 2.0 * (sky_amb + ground_amb) * occ;
	vec3 col = albedo * light * back;

	float dist = length(v_pos - u_eye);
	float fog = 1.0 - exp(-dist * u_fog_density);
	col = mix(col, srgb_to_linear(SKY), clamp(fog, 0.0, 1.0));
	frag = vec4(pow(col, vec3(1.0 / 2.2)), 1.0);
}
