// isoterra — heightmap terrain (16-bit grayscale samples, TEX_HEIGHTMAP,
// app/edit/curves_gl.c) with Clua's fractal interpolation (1999, §4.1.1).
// Mirrored term by term in app/edit/carve_ref.c; change both together.
//
// The map is centred on x = z = 0, one sample every u_heightmap_scale world
// units; sample value v (0..65535) is the world height
//   heightmap_base + v * heightmap_height / 65535.
// Between samples: the distance weights of Eq. 4.3 (corrected 4.1) — in 2D
// the product of the 1D weights, i.e. bilinear — plus the noise bump of Eq.
// 4.2/4.3 generalised to the k = 4 surrounding samples,
//   bump = k^k · Π m_j / (Σ m_j)^k     (Eq. 4.3 for k = 2: 4 m1 m2 / (m1+m2)²)
// which is 0 at every sample, 1 at the cell centre and continuous across
// cell edges; times heightmap_detail (TaxaRuído) and an fBm of Perlin noise
// at one lattice cell per sample and finer.

#include "noise.glsl"

layout(binding = TEX_HEIGHTMAP) uniform highp sampler2D u_heightmap_tex;
uniform ivec2 u_heightmap_size; // samples in x, z (0 = no map)

float hm_texel(ivec2 c)
{
	return texelFetch(u_heightmap_tex, clamp(c, ivec2(0), u_heightmap_size - 1), 0).r;
}

// Heightmap height at xz without detail (bilinear) and, with detail, the
// fractal interpolation.
float hm_height(vec2 xz, bool detail)
{
	vec2 g = xz / u_heightmap_scale + 0.5 * vec2(u_heightmap_size - 1);
	vec2 g0 = floor(g);
	vec2 f = g - g0;
	ivec2 c = ivec2(g0);
	float h00 = hm_texel(c), h10 = hm_texel(c + ivec2(1, 0));
	float h01 = hm_texel(c + ivec2(0, 1)), h11 = hm_texel(c + ivec2(1, 1));
	float a = h00 + (h10 - h00) * f.x;
	float b = h01 + (h11 - h01) * f.x;
	float v = a + (b - a) * f.y;
	float h = u_heightmap_base + v * (u_heightmap_height * (1.0 / 65535.0));
#if TERM_HEIGHTMAP_DETAIL // 0: bilinear only, the detail is not compiled
	if (detail && u_heightmap_detail != 0.0) {
		float m00 = length(f), m10 = length(f - vec2(1.0, 0.0));
		float m01 = length(f - vec2(0.0, 1.0)), m11 = length(f - vec2(1.0, 1.0));
		float sm = m00 + m10 + m01 + m11;
		float sm2 = sm * sm;
		float bump = 256.0 * (m00 * m10 * m01 * m11) / (sm2 * sm2);
		float n = 0.0, amp = 0.5, fr = 1.0;
		for (int i = 0; i < u_heightmap_octaves; i++) {
			n += amp * perlin(vec3(g.x * fr + float(i) * 17.31, 0.5, g.y * fr - float(i) * 9.17));
			fr *= 2.0;
			amp *= 0.5;
		}
		h += u_heightmap_detail * bump * n;
	}
#endif
	return h;
}
