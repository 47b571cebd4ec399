/* isoterra — noise tables and CPU mirrors of shaders/noise.glsl.
 *
 * Everything here is deterministic per seed (splitmix64, no rand()) and the
 * mirrors use the same float operations in the same order as the GLSL, so
 * GPU and CPU agree to rounding (a few 1e-7 relative). */
#include "noise.h"

#include <math.h>
#include <string.h>

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
	ns->perlin_key = noise_perlin_key(seed);

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
	for (int r = 0; r < 4; r++)
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				memcpy(out + (r * 3 + i) * 16 + j * 4, &ns->rot[r][i * 3 + j], 4);
	int32_t seed = ns->seed;
	memcpy(out + 192, &seed, 4);
	memcpy(out + 196, &ns->perlin_key, 4);
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

/* v with its sign flipped when neg (0 or 1): -v exactly, without a branch */
static inline float nflip(float v, uint32_t neg)
{
	uint32_t b;
	memcpy(&b, &v, sizeof(b));
	b ^= neg << 31;
	memcpy(&v, &b, sizeof(v));
	return v;
}

/* Perlin's 16 gradients (12 cube-edge directions, 4 of them twice), h in 0..15:
 * u = x or y, v = y, x or z (h 12 and 14: x), their signs from h's two low
 * bits; selects and sign flips, no branch (h is random: branches on it
 * mispredict half the time; the CPU's autopilot and references call this
 * eight times a sample and octave) */
static inline float ngrad(uint32_t h, float x, float y, float z)
{
	float u = h < 8u ? x : y;
	float v = h < 4u ? y : ((h | 2u) == 14u ? x : z);
	return nflip(u, h & 1u) + nflip(v, (h >> 1) & 1u);
}

/* lowbias32 is a bijection, so is this (0x5851f42d: any odd salt; it keeps
 * seed 0 away from the hash's fixed point 0). */
uint32_t noise_perlin_key(int seed)
{
	return noise_hash((uint32_t)seed ^ 0x5851f42du);
}

/* The lattice's floor as int32_t.  Beyond 2^31 GLSL's int() gives some value
 * and C's conversion is undefined behaviour, so C clamps to 2^30 (GLSL does
 * not spend the instructions): the noise is 0 there whatever gradients the
 * corners get, since every float beyond 2^23 is a lattice point (f = 0). */
static inline int32_t lattice(float P)
{
	/* fminf(fmaxf(P, -2^30), 2^30) without libm's calls: NaN gives -2^30 too */
	return P >= 0x1p30f ? (int32_t)0x40000000 : P >= -0x1p30f ? (int32_t)P : -(int32_t)0x40000000;
}

unsigned noise_perlin_gradient(const struct noise_set *ns, int32_t X, int32_t Y, int32_t Z)
{
	uint32_t h = ((uint32_t)X * NOISE_KX + ns->perlin_key) ^ ((uint32_t)Y * NOISE_KY) ^ ((uint32_t)Z * NOISE_KZ);
	return noise_hash(h) >> 28;
}

float noise_perlin(const struct noise_set *ns, float x, float y, float z)
{
	float Px = floorf(x), Py = floorf(y), Pz = floorf(z);
	float fx = x - Px, fy = y - Py, fz = z - Pz;
	uint32_t hx0 = (uint32_t)lattice(Px) * NOISE_KX + ns->perlin_key, hx1 = hx0 + NOISE_KX;
	uint32_t hy0 = (uint32_t)lattice(Py) * NOISE_KY, hy1 = hy0 + NOISE_KY;
	uint32_t hz0 = (uint32_t)lattice(Pz) * NOISE_KZ, hz1 = hz0 + NOISE_KZ;
	const uint32_t hxy[4] = { hx0 ^ hy0, hx1 ^ hy0, hx0 ^ hy1, hx1 ^ hy1 };
	uint32_t g0[4], g1[4]; /* corners at z and z+1; x fastest, then y */
	for (int i = 0; i < 4; i++) {
		g0[i] = noise_hash(hxy[i] ^ hz0) >> 28;
		g1[i] = noise_hash(hxy[i] ^ hz1) >> 28;
	}
	float u = nfade(fx), v = nfade(fy), w = nfade(fz);
	float gx0 = fx - 1.0f, gy0 = fy - 1.0f, gz0 = fz - 1.0f;
	float x00 = nlerp(u, ngrad(g0[0], fx, fy, fz), ngrad(g0[1], gx0, fy, fz));
	float x10 = nlerp(u, ngrad(g0[2], fx, gy0, fz), ngrad(g0[3], gx0, gy0, fz));
	float x01 = nlerp(u, ngrad(g1[0], fx, fy, gz0), ngrad(g1[1], gx0, fy, gz0));
	float x11 = nlerp(u, ngrad(g1[2], fx, gy0, gz0), ngrad(g1[3], gx0, gy0, gz0));
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
