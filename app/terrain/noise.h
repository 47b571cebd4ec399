/* isoterra — noise sources shared by the GPU density shader and the CPU
 * reference: improved Perlin noise (quintic fade, Perlin's 16 gradients)
 * whose lattice gradients come from an integer hash of the corner and the
 * seed (no permutation table), three 16^3 RGBA repeating noise volumes (GPU
 * Gems' way; values quantized to half floats exactly as uploaded), the
 * rotation matrices of the low octaves and the Worley feature-point hash.
 * Same seed -> same terrain. */
#ifndef ISOTERRA_NOISE_H
#define ISOTERRA_NOISE_H

#include <stdint.h>
#include <stddef.h>
#include "gpu.h" /* NOISE_TEX_SIZE: the textures' size, which the GL limits check too */

#define NOISE_TEX_COUNT 3
#define NOISE_TEX_TEXELS (NOISE_TEX_SIZE * NOISE_TEX_SIZE * NOISE_TEX_SIZE)

/* Perlin's lattice hash: corner (X,Y,Z) gets gradient
 *   noise_hash((X*NOISE_KX + key) ^ (Y*NOISE_KY) ^ (Z*NOISE_KZ)) >> 28
 * in uint32_t arithmetic, key = noise_perlin_key(seed).  The same constants
 * are #defined in shaders/noise.glsl. */
#define NOISE_KX 0x8da6b343u
#define NOISE_KY 0xd8163841u
#define NOISE_KZ 0xcb1ab31fu

struct noise_set {
	int seed;
	uint32_t perlin_key; /* noise_perlin_key(seed) */
	/* RGBA values in [-1,1], x fastest, then y, then z; already rounded to
	 * what GL_RGBA16F stores. */
	float tex[NOISE_TEX_COUNT][NOISE_TEX_TEXELS * 4];
	uint16_t tex_half[NOISE_TEX_COUNT][NOISE_TEX_TEXELS * 4];
	float rot[4][9]; /* row-major 3x3 rotations for the lowest octaves */
};

void noise_set_init(struct noise_set *ns, int seed);
/* The seed's key in Perlin's lattice hash: a bijection of the seed, so
 * different seeds give different noise. */
uint32_t noise_perlin_key(int seed);

/* CPU mirrors of the GLSL functions in shaders/noise.glsl. */
float noise_perlin(const struct noise_set *ns, float x, float y, float z);
/* The gradient index (0..15, Perlin's grad(): 12 directions, 4 twice) of
 * lattice corner (X,Y,Z): what noise_perlin uses at that corner. */
unsigned noise_perlin_gradient(const struct noise_set *ns, int32_t X, int32_t Y, int32_t Z);
/* Trilinear, repeating sample of volume k at texel-space point (x,y,z)
 * (one lattice cell per texel), channel c.  Full fp32 weights: the same as
 * noise_tex_manual() in GLSL; hardware filtering only approximates it. */
float noise_tex_sample(const struct noise_set *ns, int k, float x, float y, float z, int c);
/* Worley cellular basis: one feature point per unit cube, placed by a hash
 * of (cube, seed, salt); searches the 27 cubes around (x,y,z) and returns the
 * four smallest distances F1 <= F2 <= F3 <= F4 in f[0..3]. */
void noise_worley(const struct noise_set *ns, float x, float y, float z, int salt, float f[4]);
/* The 32-bit integer hash ("lowbias32") of Perlin's lattice and of
 * noise_worley (== nhash() in GLSL). */
uint32_t noise_hash(uint32_t x);

/* IEEE binary16 conversions (round to nearest even, subnormals, inf/NaN),
 * as GL stores RGBA16F. */
uint16_t noise_float_to_half(float f);
float noise_half_to_float(uint16_t h);

/* The std140 "NoiseTables" uniform block (UBIND_NOISE) of noise.glsl:
 *   vec4  nt_rot[12];   4 rotations x 3 rows (xyz used)        (offset 0)
 *   ivec4 nt_info;      x = seed, y = perlin_key (its bits)    (offset 192) */
#define NOISE_UBO_SIZE 208
void noise_ubo_pack(const struct noise_set *ns, unsigned char out[NOISE_UBO_SIZE]);

/* GL side (noise_gl.c).  Textures use units TEX_NOISE0..2, the rotation and
 * seed uniform block UBIND_NOISE. */
struct noise_gl {
	unsigned tex[NOISE_TEX_COUNT];
	unsigned ubo;
	int seed;
};
int noise_gl_init(struct noise_gl *ng, const struct noise_set *ns, char *err, size_t errlen);
/* Binds textures and the UBO for the next dispatch/draw. */
void noise_gl_bind(const struct noise_gl *ng);
void noise_gl_destroy(struct noise_gl *ng);

#endif
