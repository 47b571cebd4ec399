// isoterra — water: deep colour, sky reflection by Fresnel (Schlick), sun
// glint, fog; the surface normal from layered fBm waves (seed 001): octaves
// of 2D gradient noise with analytic derivatives, each octave at
// water_lacunarity times the frequency and water_gain times the height of
// the one before, turned by its own angle and moving along it at the
// deep-water phase speed of its wavelength (sqrt(g / k)), so the long swell
// moves faster than the ripples.
// On a planet's sea sphere the waves of the plane's xz are laid on the
// sphere's tangent plane (x and z projected onto it).
in vec3 v_pos;
uniform vec3 u_eye;
uniform float u_water_sphere; // sphere radius; 0: the plane
uniform vec3 u_water_centre;
uniform float u_fog_density;
out vec4 frag;
#include "shade.glsl"

// A pseudo-random unit gradient per lattice point (integer hash).
vec2 wave_grad(ivec2 c)
{
	uint h = uint(c.x) * 0x8da6b343u ^ uint(c.y) * 0xd8163841u;
	h ^= h >> 13;
	h *= 0x5bd1e995u;
	h ^= h >> 15;
	float a = float(h & 0xffffu) * (6.2831853 / 65536.0);
	return vec2(cos(a), sin(a));
}

// 2D gradient noise and its derivative (quintic fade): (n, dn/dx, dn/dy).
vec3 wave_noise(vec2 p)
{
	vec2 i = floor(p), f = p - i;
	ivec2 c = ivec2(i);
	vec2 u = f * f * f * (f * (f * 6.0 - 15.0) + 10.0);
	vec2 du = 30.0 * f * f * (f * (f - 2.0) + 1.0);
	vec2 ga = wave_grad(c), gb = wave_grad(c + ivec2(1, 0)), gc = wave_grad(c + ivec2(0, 1)),
	     gd = wave_grad(c + ivec2(1, 1));
	float va = dot(ga, f), vb = dot(gb, f - vec2(1.0, 0.0)), vc = dot(gc, f - vec2(0.0, 1.0)),
	      vd = dot(gd, f - vec2(1.0, 1.0));
	float n = va + u.x * (vb - va) + u.y * (vc - va) + u.x * u.y * (va - vb - vc + vd);
	vec2 d = ga + u.x * (gb - ga) + u.y * (gc - ga) + u.x * u.y * (ga - gb - gc + gd) +
		 du * (u.yx * (va - vb - vc + vd) + vec2(vb, vc) - va);
	return vec3(n, d);
}

// Slope (dh/dx, dh/dz) of the wave field at xz, time t.
vec2 wave_slope(vec2 xz, float t)
{
	vec2 s = vec2(0.0);
	float freq = u_water_freq, amp = u_water_wave;
	for (int i = 0; i < u_water_octaves; i++) {
		float a = float(i) * 2.39996; // golden angle: no two octaves share a direction
		mat2 r = mat2(cos(a), sin(a), -sin(a), cos(a));
		float speed = sqrt(9.81 / (6.2831853 * freq)); // world units per second
		vec2 p = r * xz * freq - vec2(t * speed * freq, 0.0) + float(i) * vec2(17.3, 5.9);
		vec3 n = wave_noise(p);
		s += amp * freq * (transpose(r) * n.yz); // chain rule back to world axes
		freq *= u_water_lacunarity;
		amp *= u_water_gain;
	}
	return s;
}

void main()
{
	vec2 sl = wave_slope(v_pos.xz, u_time);
	vec3 n;
	if (u_water_sphere > 0.0) {
		vec3 up = normalize(v_pos - u_water_centre);
		vec3 ex = vec3(1.0, 0.0, 0.0) - up * up.x, ez = vec3(0.0, 0.0, 1.0) - up * up.z;
		n = normalize(up - sl.x * ex - sl.y * ez);
	} else {
		n = normalize(vec3(-sl.x, 1.0, -sl.y));
	}
	vec3 v = normalize(u_eye - v_pos);
	float f = 0.02 + 0.98 * pow(1.0 - max(dot(n, v), 0.0), 5.0);
	vec3 r = reflect(-v, n);
	vec3 sky = mix(haze_color(r), srgb_to_linear(SKY_ZENITH), pow(clamp(r.y, 0.0, 1.0), 0.6));
	vec3 deep = srgb_to_linear(vec3(0.05, 0.20, 0.26));
	vec3 col = mix(deep, sky, f);
	col += vec3(1.0, 0.9, 0.7) * pow(max(dot(r, sun_dir()), 0.0), 200.0) * u_sun * 2.0;
	col = apply_fog(col, v_pos, u_eye, u_fog_density);
	// a planet's sea: deeper (more opaque) than a lake seen from above
	float a0 = u_water_sphere > 0.0 ? 0.86 : 0.72;
	frag = vec4(display(col), mix(a0, 0.95, f));
}
