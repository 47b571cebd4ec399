// isoterra — terrain shading (GPU Gems 3 ch.1 §4, seed 001 soils):
// triplanar projection of the generated surface texture with a bump per
// projection, detail at two finer scales near the camera (normal and
// albedo), per-vertex ambient occlusion and sun shadows (baked by the
// extraction: ao.glsl, sun.glsl), altitude/strata colour bands over a soil
// colour table, rock and grass by slope, snow on flat high ground by slope
// and height with a noisy edge, sun + hemispheric sky light summed in
// linear space, aerial perspective (shade.glsl), tone mapping.  Compiled
// for the parameters (params_glsl_specialization, app/render/render.c):
// the shape's and the soil's branches are constants, the marble colour and
// the shadows are in only when on, the detail only in the variants for
// meshes near the eye (its finer scale only in the nearest's).
in vec3 v_pos;
in vec3 v_nrm;
in float v_ao;
in float v_sun;
in float v_fog;  // render.vert
in float v_slow;
uniform vec3 u_eye;
layout(binding = TEX_SURFACE) uniform highp sampler2D u_surface; // R albedo, GB slopes, A height
#ifndef ROAD_MAP
#define ROAD_MAP 0
#endif
#if ROAD_MAP
// the curves' road map (edit/curves_gl.c edits_road_map): R paint, G surface, B height - y0
layout(binding = TEX_ROADS) uniform highp sampler2D u_roads;
uniform vec4 u_road_rect; // origin x, z; 1 / size x, z
uniform vec2 u_road_y;    // y0, the height tolerance

// A road's surface over the albedo: its paint where the road map's height
// is this fragment's (the ground over a tunnel and under a bridge keeps
// its colours).  Asphalt dark and fine-grained, gravel pale and speckled,
// dirt brown, ballast grey-brown and coarse.
vec3 road_paint(vec3 albedo, vec3 pos, float tex, float hgt)
{
	vec2 uv = (pos.xz - u_road_rect.xy) * u_road_rect.zw;
	if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))))
		return albedo;
	vec4 m = texture(u_roads, uv);
	float w = m.r * (1.0 - smoothstep(u_road_y.y, 2.0 * u_road_y.y, abs(pos.y - u_road_y.x - m.b)));
	if (w <= 0.0)
		return albedo;
	int s = int(m.g + 0.5);
	vec3 c = vec3(0.20, 0.20, 0.21) * (0.9 + 0.2 * tex);
	if (s == ROAD_SURFACE_GRAVEL)
		c = vec3(0.62, 0.58, 0.50) * (0.75 + 0.5 * hgt);
	else if (s == ROAD_SURFACE_DIRT)
		c = vec3(0.50, 0.40, 0.28) * (0.8 + 0.4 * tex);
	else if (s == ROAD_SURFACE_BALLAST)
		c = vec3(0.42, 0.38, 0.35) * (0.6 + 0.8 * hgt);
	return mix(albedo, c, clamp(w, 0.0, 1.0));
}
#endif
out vec4 frag;

#include "shade.glsl"

// soil colour tables (sRGB), indexed by a slow variation; interpolated
// piecewise linearly between the four entries by three mixes, each clamped
// to its segment (no array indexed by a variable: a CPU driver keeps such
// an array in memory and gathers from it, pixel by pixel)
vec3 soil_color(float t)
{
	vec3 c0, c1, c2, c3;
	if (u_soil == SOIL_ARID) {
		c0 = vec3(0.76, 0.60, 0.42); c1 = vec3(0.70, 0.47, 0.30);
		c2 = vec3(0.84, 0.72, 0.52); c3 = vec3(0.62, 0.42, 0.28);
	} else if (u_soil == SOIL_VOLCANIC) {
		c0 = vec3(0.22, 0.20, 0.20); c1 = vec3(0.36, 0.22, 0.18);
		c2 = vec3(0.30, 0.30, 0.32); c3 = vec3(0.45, 0.28, 0.20);
	} else {
		c0 = vec3(0.50, 0.42, 0.33); c1 = vec3(0.60, 0.52, 0.40);
		c2 = vec3(0.42, 0.36, 0.30); c3 = vec3(0.66, 0.58, 0.46);
	}
	float x = clamp(t, 0.0, 0.999) * 3.0;
	vec3 c = mix(c0, c1, clamp(x, 0.0, 1.0));
	c = mix(c, c2, clamp(x - 1.0, 0.0, 1.0));
	return mix(c, c3, clamp(x - 2.0, 0.0, 1.0));
}

#if TERM_MARBLE_COLOR
// Marble colour (Perlin 1985): sine veins along y pushed by a turbulence
// of the surface texture's height channel (four octaves of |h - 0.5|),
// mixed into the rock by marble_color.
vec3 marble_color(vec3 rock, vec3 pos)
{
	float t = 0.0, a = 1.0, f = 0.5 * u_marble_freq;
	for (int k = 0; k < 4; k++) {
		t += abs(texture(u_surface, pos.xz * f + pos.y * f * 0.37).a - 0.5) * 2.0 * a;
		f *= 2.0;
		a *= 0.5;
	}
	float s = sin(6.2831853 * u_marble_freq * (pos.y + u_marble_turb * t));
	float vein = pow(1.0 - abs(s), 6.0);
	vec3 stone = mix(vec3(0.86, 0.84, 0.80), vec3(0.30, 0.32, 0.36), vein);
	return mix(rock, stone * (0.85 + 0.15 * s), u_marble_color);
}
#endif

void main()
{
	vec3 n0 = normalize(v_nrm);
	float back = gl_FrontFacing ? 1.0 : 0.45; // inside of the volume's cut
	if (!gl_FrontFacing)
		n0 = -n0;

	// triplanar weights (the chapter's: (|n| - 0.2) * 7, normalised)
	vec3 w = max((abs(n0) - 0.2) * 7.0, 0.0);
	w /= max(w.x + w.y + w.z, 1e-4);
	vec2 c1 = v_pos.yz * u_tex_scale, c2 = v_pos.zx * u_tex_scale, c3 = v_pos.xy * u_tex_scale;
	vec4 t1 = texture(u_surface, c1), t2 = texture(u_surface, c2), t3 = texture(u_surface, c3);
	// bump per projection, in that projection's tangent plane
	vec2 b1 = (t1.gb - 0.5) * u_bump, b2 = (t2.gb - 0.5) * u_bump, b3 = (t3.gb - 0.5) * u_bump;
	vec3 bump = vec3(0.0, b1.x, b1.y) * w.x + vec3(b2.y, 0.0, b2.x) * w.y + vec3(b3.x, b3.y, 0.0) * w.z;
	vec3 n = normalize(n0 - bump);
	float tex = t1.r * w.x + t2.r * w.y + t3.r * w.z;
#if DETAIL_NORMALS
	// detail at two finer scales (5.1 and 23 times), fading out with
	// distance: the grain of the rock and the grass close up, where the
	// base texture's texels would smear.  DETAIL_NORMALS 2: both scales,
	// 1: the coarser only (the governor's step, and meshes that stay
	// beyond a quarter of DETAIL_RANGE, where the finer has faded out);
	// compiled out of the variant for meshes that stay beyond DETAIL_RANGE
	// (render.c): a software rasterizer runs a branch's texture taps in
	// every pixel, taken or not
	float dist = length(v_pos - u_eye);
	float near = u_detail * clamp(1.0 - dist / DETAIL_RANGE, 0.0, 1.0);
	float grain = 0.0;
	if (near > 0.0) {
		vec4 d1 = texture(u_surface, c1 * 5.1), d2 = texture(u_surface, c2 * 5.1), d3 = texture(u_surface, c3 * 5.1);
		vec3 db = vec3(0.0, d1.g - 0.5, d1.b - 0.5) * w.x + vec3(d2.b - 0.5, 0.0, d2.g - 0.5) * w.y +
			  vec3(d3.g - 0.5, d3.b - 0.5, 0.0) * w.z;
		n = n - db * near;
		grain = ((d1.r * w.x + d2.r * w.y + d3.r * w.z) - 0.5) * near;
#if DETAIL_NORMALS > 1
		float nearer = near * clamp(1.0 - dist / (DETAIL_FINE_SHARE * DETAIL_RANGE), 0.0, 1.0);
		vec4 e1 = texture(u_surface, c1 * 23.0), e2 = texture(u_surface, c2 * 23.0), e3 = texture(u_surface, c3 * 23.0);
		vec3 eb = vec3(0.0, e1.g - 0.5, e1.b - 0.5) * w.x + vec3(e2.b - 0.5, 0.0, e2.g - 0.5) * w.y +
			  vec3(e3.g - 0.5, e3.b - 0.5, 0.0) * w.z;
		n = n - eb * (0.6 * nearer);
		grain += ((e1.r * w.x + e2.r * w.y + e3.r * w.z) - 0.5) * nearer;
#endif
		n = normalize(n);
	}
#endif
	float hgt = t1.a * w.x + t2.a * w.y + t3.a * w.z;

	// "up" and altitude: +y and y, on a planet away from its centre and the
	// height over planet_radius (grass, snow and strata follow the sphere)
	float up_n = n0.y, alt = v_pos.y;
	if (u_shape == SHAPE_PLANET) {
		vec3 cv = v_pos + vec3(0.0, u_planet_radius, 0.0);
		up_n = dot(n0, normalize(cv));
		alt = length(cv) - u_planet_radius;
	}

	// albedo: soil table along slow variation, strata bands by altitude
	float slow = v_slow;
	float band = 0.5 + 0.5 * sin(alt * 1.7 + slow * 6.0 + up_n * 0.8);
	vec3 rock = soil_color(slow * 0.8 + band * 0.25);
	rock *= mix(1.0, 0.72 + 0.5 * band * band, u_strata);
	rock *= 0.75 + 0.5 * tex;
#if TERM_MARBLE_COLOR
	if (u_marble_color > 0.0)
		rock = marble_color(rock, v_pos);
#endif
	// the ground cover of the soil: green grass, dry scrub on arid land,
	// dark moss and ash on volcanic
	vec3 grass = u_soil == SOIL_ARID ? mix(vec3(0.62, 0.50, 0.32), vec3(0.72, 0.60, 0.38), tex)
		   : u_soil == SOIL_VOLCANIC ? mix(vec3(0.16, 0.17, 0.12), vec3(0.28, 0.26, 0.20), tex)
					     : mix(vec3(0.22, 0.34, 0.12), vec3(0.40, 0.44, 0.20), tex);
	// grass on gentle slopes, rock on steep ones (the mesh's normal: the
	// bumps only fray the edge)
	float flat_ground = smoothstep(0.62, 0.86, up_n + (hgt - 0.5) * 0.3);
	vec3 albedo = mix(rock, grass, flat_ground);
	albedo = mix(albedo, vec3(0.88, 0.90, 0.93), snow_cover(alt, up_n, slow, hgt));
#if DETAIL_NORMALS
	albedo *= 1.0 + 0.45 * grain;
#endif
#if ROAD_MAP
	albedo = road_paint(albedo, v_pos, tex, hgt);
#endif
	albedo = albedo_to_linear(albedo);

	vec3 l = sun_dir();
	float ndl = max(dot(n, l), 0.0);
	float occ = mix(1.0, clamp(v_ao, 0.0, 1.0), u_ao_strength);
	vec3 sky_amb = srgb_to_linear(SKY_HORIZON) * (0.55 + 0.45 * n.y);
	vec3 ground_amb = vec3(0.09, 0.07, 0.05) * (0.5 - 0.5 * n.y);
#if TERM_SHADOWS
	float lit = mix(1.0, clamp(v_sun, 0.0, 1.0), u_shadows);
#else
	float lit = 1.0;
#endif
	vec3 light = u_sun * SUN_COLOR * ndl * lit * mix(1.0, occ, 0.5) + u_ambient * 2.0 * (sky_amb + ground_amb) * occ;
	vec3 col = albedo * light * back;
	col = mix(col, haze_color(normalize(v_pos - u_eye)), v_fog);
	frag = vec4(display(col), 1.0);
}
