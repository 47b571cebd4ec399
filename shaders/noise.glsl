// isoterra — noise sources (GLSL ES 3.10).  Mirrored operation by operation
// in app/terrain/noise.c; change both together.
//
//  * perlin(p): Ken Perlin's improved noise (2002) — the 12 gradient
//    directions in his 16-entry set, quintic fade 6t^5-15t^4+10t^3 — with
//    each lattice corner's gradient chosen by an integer hash of the corner
//    and the seed instead of the permutation table: no table, no gathers.
//    Zero at lattice points, about [-1,1], std 0.271.
//  * noise_tex_hw / noise_tex_manual: the three 16^3 RGBA16F volumes with
//    values in [-1,1] (GPU Gems 3 ch.1), repeating, one lattice cell per
//    texel.  _hw uses the sampler's trilinear filter; _manual does the
//    trilinear interpolation in fp32 from texelFetch (for the lowest,
//    rotated octaves, where hardware weight precision shows).
//  * worley(p, salt): F1..F4 with one feature point per unit cube (hash of
//    cube, seed, salt), 27 cubes searched.

layout(std140, binding = UBIND_NOISE) uniform NoiseTables {
	vec4 nt_rot[12]; // 4 row-major 3x3 rotations, one vec4 per row
	ivec4 nt_info;   // x = seed, y = Perlin's seed key (uint bits: noise_perlin_key)
};

// Perlin's lattice hash: odd multipliers of the corner's coordinates (the
// Worley cube hash's), as noise.h's NOISE_KX..KZ.
#define NOISE_KX 0x8da6b343u
#define NOISE_KY 0xd8163841u
#define NOISE_KZ 0xcb1ab31fu

layout(binding = TEX_NOISE0) uniform highp sampler3D u_noise0;
layout(binding = TEX_NOISE1) uniform highp sampler3D u_noise1;
layout(binding = TEX_NOISE2) uniform highp sampler3D u_noise2;

float nfade(float t)
{
	return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

float nlerp(float t, float a, float b)
{
	return a + t * (b - a);
}

uint nhash(uint x)
{
	// "lowbias32" (Chris Wellons' hash prospector)
	x ^= x >> 16;
	x *= 0x7feb352du;
	x ^= x >> 15;
	x *= 0x846ca68bu;
	x ^= x >> 16;
	return x;
}

uvec4 nhash(uvec4 x)
{
	x ^= x >> 16;
	x *= 0x7feb352du;
	x ^= x >> 15;
	x *= 0x846ca68bu;
	x ^= x >> 16;
	return x;
}

// Perlin's 16 gradients (12 cube-edge directions, 4 of them twice), h in 0..15.
float ngrad(uint h, float x, float y, float z)
{
	float u = h < 8u ? x : y;
	float v = h < 4u ? y : ((h == 12u || h == 14u) ? x : z);
	return ((h & 1u) == 0u ? u : -u) + ((h & 2u) == 0u ? v : -v);
}

// Lattice corner (X,Y,Z) gets gradient nhash((X*KX + key) ^ Y*KY ^ Z*KZ) >> 28
// (uint arithmetic, wrapping; the top bits are the best mixed).  X+1 is
// X*KX + KX, so the eight corners cost three multiplies and eight hashes, in
// two uvec4s (corners z and z+1; x fastest, then y).  Beyond 2^23 every
// float is a lattice point and the noise 0 whatever int(P) gives (undefined
// beyond 2^31); noise.c clamps P to 2^30 to keep C's conversion defined.
float perlin(vec3 p)
{
	vec3 P = floor(p);
	vec3 f = p - P;
	ivec3 I = ivec3(P);
	uint hx0 = uint(I.x) * NOISE_KX + uint(nt_info.y), hx1 = hx0 + NOISE_KX;
	uint hy0 = uint(I.y) * NOISE_KY, hy1 = hy0 + NOISE_KY;
	uint hz0 = uint(I.z) * NOISE_KZ, hz1 = hz0 + NOISE_KZ;
	uvec4 hxy = uvec4(hx0 ^ hy0, hx1 ^ hy0, hx0 ^ hy1, hx1 ^ hy1);
	uvec4 g0 = nhash(hxy ^ hz0) >> 28u, g1 = nhash(hxy ^ hz1) >> 28u;
	float u = nfade(f.x), v = nfade(f.y), w = nfade(f.z);
	float gx0 = f.x - 1.0, gy0 = f.y - 1.0, gz0 = f.z - 1.0;
	float x00 = nlerp(u, ngrad(g0.x, f.x, f.y, f.z), ngrad(g0.y, gx0, f.y, f.z));
	float x10 = nlerp(u, ngrad(g0.z, f.x, gy0, f.z), ngrad(g0.w, gx0, gy0, f.z));
	float x01 = nlerp(u, ngrad(g1.x, f.x, f.y, gz0), ngrad(g1.y, gx0, f.y, gz0));
	float x11 = nlerp(u, ngrad(g1.z, f.x, gy0, gz0), ngrad(g1.w, gx0, gy0, gz0));
	return nlerp(w, nlerp(v, x00, x10), nlerp(v, x01, x11));
}

// rotation r (0..3) applied to p
vec3 noise_rotate(int r, vec3 p)
{
	vec3 r0 = nt_rot[r * 3].xyz, r1 = nt_rot[r * 3 + 1].xyz, r2 = nt_rot[r * 3 + 2].xyz;
	return vec3(r0.x * p.x + r0.y * p.y + r0.z * p.z,
		    r1.x * p.x + r1.y * p.y + r1.z * p.z,
		    r2.x * p.x + r2.y * p.y + r2.z * p.z);
}

vec4 noise_fetch(int k, ivec3 c)
{
	if (k == 0)
		return texelFetch(u_noise0, c, 0);
	else if (k == 1)
		return texelFetch(u_noise1, c, 0);
	return texelFetch(u_noise2, c, 0);
}

// Trilinear in fp32 from 8 texel fetches; p in texel units (lattice = texel).
vec4 noise_tex_manual(int k, vec3 p)
{
	vec3 P = floor(p);
	vec3 f = p - P;
	P = P - 16.0 * floor(P * (1.0 / 16.0));
	ivec3 i0 = ivec3(P) & 15;
	ivec3 i1 = (i0 + 1) & 15;
	vec4 c000 = noise_fetch(k, ivec3(i0.x, i0.y, i0.z)), c100 = noise_fetch(k, ivec3(i1.x, i0.y, i0.z));
	vec4 c010 = noise_fetch(k, ivec3(i0.x, i1.y, i0.z)), c110 = noise_fetch(k, ivec3(i1.x, i1.y, i0.z));
	vec4 c001 = noise_fetch(k, ivec3(i0.x, i0.y, i1.z)), c101 = noise_fetch(k, ivec3(i1.x, i0.y, i1.z));
	vec4 c011 = noise_fetch(k, ivec3(i0.x, i1.y, i1.z)), c111 = noise_fetch(k, ivec3(i1.x, i1.y, i1.z));
	vec4 x00 = c000 + f.x * (c100 - c000);
	vec4 x10 = c010 + f.x * (c110 - c010);
	vec4 x01 = c001 + f.x * (c101 - c001);
	vec4 x11 = c011 + f.x * (c111 - c011);
	vec4 y0 = x00 + f.y * (x10 - x00);
	vec4 y1 = x01 + f.y * (x11 - x01);
	return y0 + f.z * (y1 - y0);
}

// Hardware trilinear filtering with repeat.  p is wrapped to [0,16) first
// (exact) so the texture coordinate keeps its precision far from the origin.
vec4 noise_tex_hw(int k, vec3 p)
{
	vec3 pw = p - 16.0 * floor(p * (1.0 / 16.0));
	vec3 uv = (pw + 0.5) * (1.0 / 16.0);
	if (k == 0)
		return textureLod(u_noise0, uv, 0.0);
	else if (k == 1)
		return textureLod(u_noise1, uv, 0.0);
	return textureLod(u_noise2, uv, 0.0);
}

// F1..F4 (sorted distances to the 4 nearest feature points).
vec4 worley(vec3 p, int salt)
{
	vec3 P = floor(p);
	vec3 f = p - P;
	P = P - 4096.0 * floor(P * (1.0 / 4096.0));
	ivec3 I = ivec3(P);
	uint sb = nhash(uint(nt_info.x) ^ (uint(salt) * 0x9e3779b9u));
	vec4 F = vec4(1e9);
	for (int dz = -1; dz <= 1; dz++)
		for (int dy = -1; dy <= 1; dy++)
			for (int dx = -1; dx <= 1; dx++) {
				uint cx = uint((I.x + dx) & 4095), cy = uint((I.y + dy) & 4095), cz = uint((I.z + dz) & 4095);
				uint h = nhash((cx * 0x8da6b343u) ^ (cy * 0xd8163841u) ^ (cz * 0xcb1ab31fu) ^ sb);
				float rx = float(h >> 8u) * (1.0 / 16777216.0);
				h = nhash(h);
				float ry = float(h >> 8u) * (1.0 / 16777216.0);
				h = nhash(h);
				float rz = float(h >> 8u) * (1.0 / 16777216.0);
				float ddx = (float(dx) + rx) - f.x;
				float ddy = (float(dy) + ry) - f.y;
				float ddz = (float(dz) + rz) - f.z;
				float d2 = ddx * ddx + ddy * ddy + ddz * ddz;
				if (d2 < F.w) {
					if (d2 < F.z) {
						F.w = F.z;
						if (d2 < F.y) {
							F.z = F.y;
							if (d2 < F.x) {
								F.y = F.x;
								F.x = d2;
							} else {
								F.y = d2;
							}
						} else {
							F.z = d2;
						}
					} else {
						F.w = d2;
					}
				}
			}
	return sqrt(F);
}
