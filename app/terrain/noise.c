/* isoterra — noise tables and CPU mirrors of shaders/noise.glsl.
 *
 * Everything here is deterministic per seed (splitmix64, no rand()) and the
 * mirrors use the same float operations in the same order as the GLSL, so
 * GPU and CPU agree to rounding (a few 1e-7 relative). */
#include "noise.h"

#include <math.h>
#include <string.h>

/* Ken Perlin's reference permutation (ImprovedNoise.java), used for seed 0. */
static const uint8_t perlin_ref_perm[256] = {
	151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,   225, 140, 36,  103, 30,  69,  142,
	8,   99,  37,  240, 21,  10,  23,  190, 6,   148, 247, 120, 234, 75,  0,   26,  197, 62,  94,  252, 219, 203,
	117, 35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174, 20,  125, 136, 171, 168, 68,  175, 74,  165,
	71,  134, 139, 48,  27,  166, 77,  146, 158, 231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,
	55,  46,  245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209, 76,  132, 187, 208, 89,
	18,  169, 200, 196, 135, 130, 116, 188, 159, 86,  164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250,
	124, 123, 5,   202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,  58,  17,  182, 189,
	28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,  154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,
	129, 22,  39,  253, 19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,  228, 251, 34,
	242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,  145, 235, 249, 14,  239, 107, 49,  192, 214, 31,
	181, 199, 106, 157, 184, 84,  204, 176, 115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,  222, 114,
	67,  29,  24,  72,  243, 141, 128, 195, 78,  66,  215, 61,  156, 180,
};

static uint64_t splitmix64(uint64_t *s)
{
	uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	return z ^ (z >> 31);
}

/* uniform in [0,1), 53 bits */
static double rnd01(uint64_t *s)
{
	return (double)(splitmix64(s) >> 11) * (1.0 / 9007199254740992.0);
}

/* uniform integer in [0, n) without modulo bias */
static uint32_t rnd_below(uint64_t *s, uint32_t n)
{
	uint64_t lim = UINT64_MAX - UINT64_MAX % n;
	uint64_t r;
	do
		r = splitmix64(s);
	while (r >= lim);
	return (uint32_t)(r % n);
}

/* ---- half floats --------------------------------------------------------- */

uint16_t noise_float_to_half(float f)
{
	uint32_t x;
	memcpy(&x, &f, sizeof(x));
	uint32_t sign = (x >> 16) & 0x8000u;
	uint32_t ex = (x >> 23) & 0xffu;
	uint32_t mant = x & 0x7fffffu;
	if (ex == 0xffu) /* inf / NaN (keep NaN quiet and non-zero) */
		return (uint16_t)(sign | 0x7c00u | (mant ? 0x200u | (mant >> 13) : 0u));
	int e = (int)ex - 127 + 15;
	if (e >= 31)
		return (uint16_t)(sign | 0x7c00u);
	if (e <= 0) { /* half subnormal (or zero) */
		if (e < -10)
			return (uint16_t)sign;
		uint32_t m = mant | 0x800000u;
		int shift = 14 - e; /* 14..24 */
		uint32_t h = m >> shift;
		uint32_t rem = m & ((1u << shift) - 1u);
		uint32_t half = 1u << (shift - 1);
		if (rem > half || (rem == half && (h & 1u)))
			h++; /* may carry into the smallest normal: correct */
		return (uint16_t)(sign | h);
	}
	uint32_t h = ((uint32_t)e << 10) | (mant >> 13);
	uint32_t rem = mant & 0x1fffu;
	if (rem > 0x1000u || (rem == 0x1000u && (h & 1u)))
		h++; /* carry may reach the exponent, up to inf: correct */
	return (uint16_t)(sign | h);
}

float noise_half_to_float(uint16_t h)
{
	uint32_t sign = (uint32_t)(h & 0x8000u) << 16;
	uint32_t ex = (h >> 10) & 0x1fu;
	uint32_t mant = h & 0x3ffu;
	uint32_t x;
	if (ex == 0) {
		float v = ldexpf((float)mant, -24);
		return sign ? -v : v;
	} else if (ex == 31) {
		x = sign | 0x7f800000u | (mant << 13);
	} else {
		x = sign | ((ex + 112u) << 23) | (mant << 13);
	}
	float f;
	memcpy(&f, &x, sizeof(f));
	return f;
}

/* ---- tables --------------------------------------------------------------- */

void noise_set_init(struct noise_set *ns, int seed)
{
	memset(ns, 0, sizeof(*ns));
	ns->seed = seed;
	uint64_t s = 0x1505c0de00000000ull ^ (uint64_t)(uint32_t)seed;
	splitmix64(&s);

	if (seed == 0) {
		memcpy(ns->perm, perlin_ref_perm, sizeof(ns->perm));
	} else {
		for (int i = 0; i < 256; i++)
			ns->perm[i] = (uint8_t)i;
		for (int i = 255; i > 0; i--) { /* Fisher-Yates */
			int j = (int)rnd_below(&s, (uint32_t)i + 1u);
			uint8_t t = ns->perm[i];
			ns->perm[i] = ns->perm[j];
			ns->perm[j] = t;
		}
	}

	for (int k = 0; k < NOISE_TEX_COUNT; k++)
		for (int i = 0; i < NOISE_TEX_TEXELS * 4; i++) {
			float v = (float)(rnd01(&s) * 2.0 - 1.0);
			uint16_t h = noise_float_to_half(v);
			ns->tex_half[k][i] = h;
			ns->tex[k][i] = noise_half_to_float(h);
		}

	/* Rotations: random axis (uniform on the sphere), angle 0.35..1.2 rad,
	 * Rodrigues in double; rows re-orthonormalized (Gram-Schmidt). */
	for (int r = 0; r < 4; r++) {
		double z = rnd01(&s) * 2.0 - 1.0;
		double phi = rnd01(&s) * 6.283185307179586;
		double rr = sqrt(1.0 - z * z);
		double ax = rr * cos(phi), ay = rr * sin(phi), az = z;
		double a = 0.35 + rnd01(&s) * 0.85;
		double c = cos(a), sn = sin(a), t = 1.0 - c;
		double m[3][3] = {
			{ t * ax * ax + c, t * ax * ay - sn * az, t * ax * az + sn * ay },
			{ t * ax * ay + sn * az, t * ay * ay + c, t * ay * az - sn * ax },
			{ t * ax * az - sn * ay, t * ay * az + sn * ax, t * az * az + c },
		};
		for (int i = 0; i < 3; i++) {
			for (int j = 0; j < i; j++) {
				double d = m[i][0] * m[j][0] + m[i][1] * m[j][1] + m[i][2] * m[j][2];
				for (int c2 = 0; c2 < 3; c2++)
					m[i][c2] -= d * m[j][c2];
			}
			double l = sqrt(m[i][0] * m[i][0] + m[i][1] * m[i][1] + m[i][2] * m[i][2]);
			for (int c2 = 0; c2 < 3; c2++)
				m[i][c2] /= l;
		}
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				ns->rot[r][i * 3 + j] = (float)m[i][j];
	}
}

void noise_ubo_pack(const struct noise_set *ns, unsigned char out[NOISE_UBO_SIZE])
{
	memset(out, 0, NOISE_UBO_SIZE);
	for (int i = 0; i < 256; i++) {
		int32_t v = ns->perm[i];
		memcpy(out + i * 4, &v, 4);
	}
	for (int r = 0; r < 4; r++)
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				memcpy(out + 1024 + (r * 3 + i) * 16 + j * 4, &ns->rot[r][i * 3 + j], 4);
	int32_t seed = ns->seed;
	memcpy(out + 1216, &seed, 4);
}

/* ---- improved Perlin noise (mirror of perlin() in noise.glsl) ------------ */

static inline float nfade(float t)
{
	return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

static inline float nlerp(float t, float a, float b)
{
	return a + t * (b - a);
}

static inline float ngrad(int h, float x, float y, float z)
{
	h &= 15;
	float u = h < 8 ? x : y;
	float v = h < 4 ? y : (h == 12 || h == 14 ? x : z);
	return ((h & 1) == 0 ? u : -u) + ((h & 2) == 0 ? v : -v);
}

float noise_perlin(const struct noise_set *ns, float x, float y, float z)
{
	const uint8_t *p = ns->perm;
	float Px = floorf(x), Py = floorf(y), Pz = floorf(z);
	float fx = x - Px, fy = y - Py, fz = z - Pz;
	Px = Px - 256.0f * floorf(Px * (1.0f / 256.0f));
	Py = Py - 256.0f * floorf(Py * (1.0f / 256.0f));
	Pz = Pz - 256.0f * floorf(Pz * (1.0f / 256.0f));
	int X = (int)Px & 255, Y = (int)Py & 255, Z = (int)Pz & 255;
	float u = nfade(fx), v = nfade(fy), w = nfade(fz);
	int A = p[X] + Y, AA = p[A & 255] + Z, AB = p[(A + 1) & 255] + Z;
	int B = p[(X + 1) & 255] + Y, BA = p[B & 255] + Z, BB = p[(B + 1) & 255] + Z;
	float gx0 = fx - 1.0f, gy0 = fy - 1.0f, gz0 = fz - 1.0f;
	float x00 = nlerp(u, ngrad(p[AA & 255], fx, fy, fz), ngrad(p[BA & 255], gx0, fy, fz));
	float x10 = nlerp(u, ngrad(p[AB & 255], fx, gy0, fz), ngrad(p[BB & 255], gx0, gy0, fz));
	float x01 = nlerp(u, ngrad(p[(AA + 1) & 255], fx, fy, gz0), ngrad(p[(BA + 1) & 255], gx0, fy, gz0));
	float x11 = nlerp(u, ngrad(p[(AB + 1) & 255], fx, gy0, gz0), ngrad(p[(BB + 1) & 255], gx0, gy0, gz0));
	return nlerp(w, nlerp(v, x00, x10), nlerp(v, x01, x11));
}

/* ---- texture noise (mirror of noise_tex_manual() in noise.glsl) ---------- */

static inline const float *texel(const struct noise_set *ns, int k, int x, int y, int z)
{
	return &ns->tex[k][((z * NOISE_TEX_SIZE + y) * NOISE_TEX_SIZE + x) * 4];
}

float noise_tex_sample(const struct noise_set *ns, int k, float x, float y, float z, int c)
{
	float Px = floorf(x), Py = floorf(y), Pz = floorf(z);
	float fx = x - Px, fy = y - Py, fz = z - Pz;
	Px = Px - 16.0f * floorf(Px * (1.0f / 16.0f));
	Py = Py - 16.0f * floorf(Py * (1.0f / 16.0f));
	Pz = Pz - 16.0f * floorf(Pz * (1.0f / 16.0f));
	int x0 = (int)Px & 15, y0 = (int)Py & 15, z0 = (int)Pz & 15;
	int x1 = (x0 + 1) & 15, y1 = (y0 + 1) & 15, z1 = (z0 + 1) & 15;
	float a = nlerp(fx, texel(ns, k, x0, y0, z0)[c], texel(ns, k, x1, y0, z0)[c]);
	float b = nlerp(fx, texel(ns, k, x0, y1, z0)[c], texel(ns, k, x1, y1, z0)[c]);
	float d = nlerp(fx, texel(ns, k, x0, y0, z1)[c], texel(ns, k, x1, y0, z1)[c]);
	float e = nlerp(fx, texel(ns, k, x0, y1, z1)[c], texel(ns, k, x1, y1, z1)[c]);
	return nlerp(fz, nlerp(fy, a, b), nlerp(fy, d, e));
}

/* ---- Worley (mirror of worley() in noise.glsl) --------------------------- */

uint32_t noise_hash(uint32_t x)
{
	/* "lowbias32" (Chris Wellons' hash prospector) */
	x ^= x >> 16;
	x *= 0x7feb352du;
	x ^= x >> 15;
	x *= 0x846ca68bu;
	x ^= x >> 16;
	return x;
}

void noise_worley(const struct noise_set *ns, float x, float y, float z, int salt, float f[4])
{
	float Px = floorf(x), Py = floorf(y), Pz = floorf(z);
	float fx = x - Px, fy = y - Py, fz = z - Pz;
	Px = Px - 4096.0f * floorf(Px * (1.0f / 4096.0f));
	Py = Py - 4096.0f * floorf(Py * (1.0f / 4096.0f));
	Pz = Pz - 4096.0f * floorf(Pz * (1.0f / 4096.0f));
	int X = (int)Px, Y = (int)Py, Z = (int)Pz;
	uint32_t sb = noise_hash((uint32_t)ns->seed ^ ((uint32_t)salt * 0x9e3779b9u));
	float F0 = 1e9f, F1 = 1e9f, F2 = 1e9f, F3 = 1e9f;
	for (int dz = -1; dz <= 1; dz++)
		for (int dy = -1; dy <= 1; dy++)
			for (int dx = -1; dx <= 1; dx++) {
				uint32_t cx = (uint32_t)((X + dx) & 4095), cy = (uint32_t)((Y + dy) & 4095),
					 cz = (uint32_t)((Z + dz) & 4095);
				uint32_t h = noise_hash((cx * 0x8da6b343u) ^ (cy * 0xd8163841u) ^ (cz * 0xcb1ab31fu) ^ sb);
				float rx = (float)(h >> 8) * (1.0f / 16777216.0f);
				h = noise_hash(h);
				float ry = (float)(h >> 8) * (1.0f / 16777216.0f);
				h = noise_hash(h);
				float rz = (float)(h >> 8) * (1.0f / 16777216.0f);
				float ddx = ((float)dx + rx) - fx;
				float ddy = ((float)dy + ry) - fy;
				float ddz = ((float)dz + rz) - fz;
				float d2 = ddx * ddx + ddy * ddy + ddz * ddz;
				if (d2 < F3) {
					if (d2 < F2) {
						F3 = F2;
						if (d2 < F1) {
							F2 = F1;
							if (d2 < F0) {
								F1 = F0;
								F0 = d2;
							} else {
								F1 = d2;
							}
						} else {
							F2 = d2;
						}
					} else {
						F3 = d2;
					}
				}
			}
	f[0] = sqrtf(F0);
	f[1] = sqrtf(F1);
	f[2] = sqrtf(F2);
	f[3] = sqrtf(F3);
}
