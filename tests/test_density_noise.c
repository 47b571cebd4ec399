/* isoterra — test_density (test_density.c), the noise: half-float
 * conversion, the noise tables (determinism per seed, rotations), improved
 * Perlin noise against Perlin's formula on its hashed lattice gradients,
 * the hash's spread, texture noise, Worley. */
#include "density_test.h"
#include "density_ref.h"
#include "terrain.h"
#include "gpu.h"
#include "image.h"
#include "noise.h"
#include "params.h"
#include "pipeline.h"
#include "platform.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- half floats ----------------------------------------------------------- */

void test_half(void)
{
	int bad = 0;
	for (uint32_t h = 0; h < 65536; h++) {
		if ((h & 0x7c00u) == 0x7c00u && (h & 0x3ffu))
			continue; /* NaN */
		float f = noise_half_to_float((uint16_t)h);
		if (noise_float_to_half(f) != h)
			bad++;
	}
	CHECK(bad == 0, "%d half values do not round-trip", bad);
	CHECK(noise_float_to_half(1.0f) == 0x3c00, "1.0");
	CHECK(noise_float_to_half(-2.0f) == 0xc000, "-2.0");
	CHECK(noise_float_to_half(0.5f) == 0x3800, "0.5");
	CHECK(noise_float_to_half(65504.0f) == 0x7bff, "max half");
	CHECK(noise_float_to_half(65519.0f) == 0x7bff, "below the overflow tie");
	CHECK(noise_float_to_half(65520.0f) == 0x7c00, "overflow tie rounds to inf");
	CHECK(noise_float_to_half(1.0f + 0x1p-11f) == 0x3c00, "tie to even (down)");
	CHECK(noise_float_to_half(1.0f + 3 * 0x1p-11f) == 0x3c02, "tie to even (up)");
	CHECK(noise_float_to_half(1.0f + 0x1p-11f + 0x1p-20f) == 0x3c01, "above the tie");
	CHECK(noise_float_to_half(0x1p-24f) == 0x0001, "smallest subnormal");
	CHECK(noise_float_to_half(0x1p-25f) == 0x0000, "subnormal tie to even (zero)");
	CHECK(noise_float_to_half(0x1.8p-25f) == 0x0001, "above the subnormal tie");
	CHECK(noise_float_to_half(0x1.ff8p-15f) == 0x03ff, "largest subnormal");
	CHECK(noise_float_to_half(0x1.ffcp-15f) == 0x0400, "subnormal tie rounds up to the smallest normal");
	CHECK(noise_float_to_half(-0.0f) == 0x8000, "-0");
	CHECK(noise_float_to_half(INFINITY) == 0x7c00, "inf");
	uint16_t hn = noise_float_to_half(NAN);
	CHECK((hn & 0x7c00u) == 0x7c00u && (hn & 0x3ffu), "NaN stays NaN (0x%04x)", hn);
	CHECK(noise_half_to_float(0x3555) == 0x1.554p-2f, "0x3555");
	CHECK(noise_half_to_float(0x0001) == 0x1p-24f, "subnormal to float");
}

/* ---- noise tables and functions ----------------------------------------- */

void test_tables(void)
{
	noise_set_init(&ns_a, 42);
	noise_set_init(&ns_b, 42);
	CHECK(memcmp(&ns_a, &ns_b, sizeof(ns_a)) == 0, "same seed gives the same tables");
	noise_set_init(&ns_b, 43);
	CHECK(ns_a.perlin_key != ns_b.perlin_key, "different seeds: different Perlin keys");
	CHECK(memcmp(ns_a.tex, ns_b.tex, sizeof(ns_a.tex)) != 0, "different seeds: different volumes");
	CHECK(memcmp(ns_a.rot, ns_b.rot, sizeof(ns_a.rot)) != 0, "different seeds: different rotations");

	int out = 0, mism = 0;
	double mean = 0;
	for (int k = 0; k < NOISE_TEX_COUNT; k++)
		for (int i = 0; i < NOISE_TEX_TEXELS * 4; i++) {
			float v = ns_a.tex[k][i];
			out += v < -1.0f || v > 1.0f;
			mism += noise_half_to_float(ns_a.tex_half[k][i]) != v;
			mean += v;
		}
	mean /= NOISE_TEX_COUNT * NOISE_TEX_TEXELS * 4;
	CHECK(out == 0, "%d texture values outside [-1,1]", out);
	CHECK(mism == 0, "%d texture floats differ from their half", mism);
	CHECK(fabs(mean) < 0.02, "texture values centred (mean %g)", mean);

	for (int r = 0; r < 4; r++) {
		const float *m = ns_a.rot[r];
		double worst = 0;
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++) {
				double d = 0;
				for (int c = 0; c < 3; c++)
					d += (double)m[i * 3 + c] * m[j * 3 + c];
				worst = fmax(worst, fabs(d - (i == j)));
			}
		double det = m[0] * ((double)m[4] * m[8] - (double)m[5] * m[7]) -
			     m[1] * ((double)m[3] * m[8] - (double)m[5] * m[6]) +
			     m[2] * ((double)m[3] * m[7] - (double)m[4] * m[6]);
		CHECK(worst < 1e-6, "rotation %d orthonormal (err %g)", r, worst);
		CHECK(fabs(det - 1.0) < 1e-6, "rotation %d det %g", r, det);
		CHECK(fabs(m[0] + m[4] + m[8] - 3.0f) > 1e-3, "rotation %d is not the identity", r);
	}

	unsigned char ubo[NOISE_UBO_SIZE];
	noise_ubo_pack(&ns_a, ubo);
	int32_t v;
	float fr;
	memcpy(&fr, ubo + (2 * 3 + 1) * 16 + 2 * 4, 4);
	CHECK(fr == ns_a.rot[2][1 * 3 + 2], "UBO rot[2] row 1 col 2 (std140 vec4 rows)");
	memcpy(&v, ubo + 192, 4);
	CHECK(v == 42, "UBO seed");
	uint32_t key;
	memcpy(&key, ubo + 196, 4);
	CHECK(key == ns_a.perlin_key && key == noise_perlin_key(42), "UBO Perlin key");
}

static float frand(uint32_t *s, float lo, float hi)
{
	*s = *s * 1664525u + 1013904223u;
	return lo + (hi - lo) * (float)(*s >> 8) * (1.0f / 16777216.0f);
}

/* Ken Perlin's improved noise (ImprovedNoise.java) in double, on the
 * gradient indices noise_perlin_gradient() gives: the fade, the 16
 * gradients and the interpolation, independently of the lattice hash. */
static double perlin_formula(const struct noise_set *ns, double x, double y, double z)
{
	double X = floor(x), Y = floor(y), Z = floor(z);
	x -= X;
	y -= Y;
	z -= Z;
	int32_t ix = (int32_t)X, iy = (int32_t)Y, iz = (int32_t)Z;
	double u = x * x * x * (x * (x * 6 - 15) + 10), v = y * y * y * (y * (y * 6 - 15) + 10),
	       w = z * z * z * (z * (z * 6 - 15) + 10);
	double c[2][2][2];
	for (int k = 0; k < 2; k++)
		for (int j = 0; j < 2; j++)
			for (int i = 0; i < 2; i++) {
				int h = (int)noise_perlin_gradient(ns, ix + i, iy + j, iz + k);
				double px = x - i, py = y - j, pz = z - k;
				double gu = h < 8 ? px : py, gv = h < 4 ? py : (h == 12 || h == 14 ? px : pz);
				c[k][j][i] = ((h & 1) == 0 ? gu : -gu) + ((h & 2) == 0 ? gv : -gv);
			}
	double e[2];
	for (int k = 0; k < 2; k++) {
		double a = c[k][0][0] + u * (c[k][0][1] - c[k][0][0]), b = c[k][1][0] + u * (c[k][1][1] - c[k][1][0]);
		e[k] = a + v * (b - a);
	}
	return e[0] + w * (e[1] - e[0]);
}

void test_perlin(void)
{
	struct noise_set *ref = &ns_b;
	noise_set_init(ref, 0);
	/* the float noise is Perlin's formula on its lattice gradients, near
	 * the origin and far from it (negative lattice coordinates included) */
	uint32_t s = 1;
	double worst = 0;
	for (int i = 0; i < 20000; i++) {
		float r = i < 10000 ? 300.0f : 1e6f;
		float x = frand(&s, -r, r), y = frand(&s, -r, r), z = frand(&s, -r, r);
		const struct noise_set *ns = i & 1 ? ref : &ns_a;
		worst = fmax(worst, fabs(noise_perlin(ns, x, y, z) - perlin_formula(ns, x, y, z)));
	}
	CHECK(worst < 2e-6, "Perlin noise = Perlin's formula on the hashed gradients (max diff %g)", worst);
	/* beyond 2^23 every float is a lattice point: 0, also where the
	 * lattice coordinate leaves int's range */
	CHECK(noise_perlin(&ns_a, 3e9f, -5e9f, 0x1p23f) == 0.0f, "Perlin noise 0 far away");

	/* the lattice hash: every gradient index about equally often, and the
	 * corners next along x, y, z (and 256 apart, a permutation table's
	 * period) independent: equal 1/16 of the time */
	int hist[16] = { 0 }, same[4] = { 0 }, nc = 0;
	for (int z = -20; z < 20; z++)
		for (int y = -20; y < 20; y++)
			for (int x = -20; x < 20; x++) {
				unsigned h = noise_perlin_gradient(&ns_a, x, y, z);
				hist[h]++;
				same[0] += h == noise_perlin_gradient(&ns_a, x + 1, y, z);
				same[1] += h == noise_perlin_gradient(&ns_a, x, y + 1, z);
				same[2] += h == noise_perlin_gradient(&ns_a, x, y, z + 1);
				same[3] += h == noise_perlin_gradient(&ns_a, x + 256, y, z);
				nc++;
			}
	double chi2 = 0;
	for (int h = 0; h < 16; h++)
		chi2 += (hist[h] - nc / 16.0) * (hist[h] - nc / 16.0) / (nc / 16.0);
	CHECK(chi2 < 45.0, "gradient indices uniform (chi^2 %.1f, 15 dof)", chi2);
	for (int d = 0; d < 4; d++)
		CHECK(fabs(same[d] / (double)nc - 1.0 / 16) < 0.01, "neighbouring gradients independent (%d: %.4f equal)", d,
		      same[d] / (double)nc);
	CHECK(noise_perlin_key(0) != noise_perlin_key(1), "seed keys differ");

	int nonzero = 0;
	for (int z = -3; z <= 3; z++)
		for (int y = -300; y <= 300; y += 37)
			for (int x = -5; x <= 5; x++)
				nonzero += noise_perlin(&ns_a, (float)x, (float)y, (float)z) != 0.0f;
	CHECK(nonzero == 0, "Perlin noise is zero at %d lattice points", nonzero);

	s = 1;
	float mx = 0;
	double sum = 0, sum2 = 0;
	int n = 200000;
	for (int i = 0; i < n; i++) {
		float v = noise_perlin(&ns_a, frand(&s, -300, 300), frand(&s, -300, 300), frand(&s, -300, 300));
		mx = fmaxf(mx, fabsf(v));
		sum += v;
		sum2 += (double)v * v;
	}
	CHECK(mx <= 1.05f, "Perlin range (max |n| = %g)", mx);
	CHECK(mx > 0.6f, "Perlin range not degenerate (max |n| = %g)", mx);
	CHECK(fabs(sum / n) < 0.01, "Perlin mean %g", sum / n);
	CHECK(fabs(sqrt(sum2 / n) - 0.271) < 0.02, "Perlin std %g (fractal.glsl assumes 0.271)", sqrt(sum2 / n));

	/* continuity across a lattice plane */
	float a = noise_perlin(&ns_a, 4.0f - 1e-4f, 0.3f, 0.7f), b = noise_perlin(&ns_a, 4.0f + 1e-4f, 0.3f, 0.7f);
	CHECK(fabsf(a - b) < 1e-3f, "Perlin continuous across x = 4 (%g vs %g)", a, b);
	a = noise_perlin(&ns_a, 0.3f, -1e-4f, -7.3f);
	b = noise_perlin(&ns_a, 0.3f, 1e-4f, -7.3f);
	CHECK(fabsf(a - b) < 1e-3f, "Perlin continuous across y = 0 (%g vs %g)", a, b);
	/* seeds differ */
	float d = 0;
	for (int i = 0; i < 100; i++) {
		float x = frand(&s, -50, 50), y = frand(&s, -50, 50), z = frand(&s, -50, 50);
		d += fabsf(noise_perlin(&ns_a, x, y, z) - noise_perlin(ref, x, y, z));
	}
	CHECK(d > 1.0f, "different seeds give different noise (sum |diff| %g)", d);
}

void test_tex_noise(void)
{
	/* lattice point = texel value, repeat every 16 texels, channel select */
	const float *t = &ns_a.tex[1][((5 * 16 + 3) * 16 + 7) * 4];
	CHECK(noise_tex_sample(&ns_a, 1, 7.0f, 3.0f, 5.0f, 2) == t[2], "texel value at a lattice point");
	CHECK(noise_tex_sample(&ns_a, 1, 7.0f - 32.0f, 3.0f + 16.0f, 5.0f - 160.0f, 2) == t[2], "repeat");
	uint32_t s = 7;
	int bad = 0;
	float mx = 0;
	for (int i = 0; i < 20000; i++) {
		float x = frand(&s, -100, 100), y = frand(&s, -100, 100), z = frand(&s, -100, 100);
		float v = noise_tex_sample(&ns_a, i % 3, x, y, z, i & 3);
		float w = noise_tex_sample(&ns_a, i % 3, x + 16.0f, y - 48.0f, z + 32.0f, i & 3);
		bad += fabsf(v - w) > 1e-4f;
		mx = fmaxf(mx, fabsf(v));
	}
	CHECK(bad == 0, "texture noise periodic with 16 (%d mismatches)", bad);
	CHECK(mx <= 1.0f, "texture noise within [-1,1] (%g)", mx);
	/* halfway between two texels along x: the average */
	float h = noise_tex_sample(&ns_a, 0, 2.5f, 9.0f, 4.0f, 0);
	float t0 = ns_a.tex[0][((4 * 16 + 9) * 16 + 2) * 4], t1 = ns_a.tex[0][((4 * 16 + 9) * 16 + 3) * 4];
	CHECK_NEAR(h, 0.5f * (t0 + t1), 1e-6, "trilinear midpoint");
}

void test_worley(void)
{
	uint32_t s = 3;
	int unsorted = 0, far = 0;
	for (int i = 0; i < 5000; i++) {
		float x = frand(&s, -40, 40), y = frand(&s, -40, 40), z = frand(&s, -40, 40);
		float f[4], g[4];
		noise_worley(&ns_a, x, y, z, 2, f);
		noise_worley(&ns_a, x, y, z, 2, g);
		unsorted += !(f[0] <= f[1] && f[1] <= f[2] && f[2] <= f[3]) || memcmp(f, g, sizeof(f)) != 0;
		far += f[0] > 1.7320509f;
	}
	CHECK(unsorted == 0, "Worley F1<=F2<=F3<=F4 and deterministic (%d bad)", unsorted);
	CHECK(far == 0, "F1 <= sqrt(3) (one point per cube)");
	/* each feature point is a zero of F1 */
	float f[4], g[4];
	noise_worley(&ns_a, 10.5f, 3.5f, -7.5f, 0, f);
	noise_worley(&ns_b, 10.5f, 3.5f, -7.5f, 0, g);
	float f2[4];
	noise_worley(&ns_a, 10.5f, 3.5f, -7.5f, 1, f2);
	CHECK(f[0] != g[0] || f[1] != g[1], "Worley differs between seeds");
	CHECK(f[0] != f2[0] || f[1] != f2[1], "Worley differs between octaves (salt)");
	CHECK(noise_hash(0) == 0 && noise_hash(1) != 1, "hash");
}
