/* isoterra — noise sources shared by the GPU density shader and the CPU
 * reference: seeded permutation (improved Perlin noise, quintic fade),
 * three 16^3 RGBA repeating noise volumes (GPU Gems' way; values quantized to
 * half floats exactly as uploaded), the rotation matrices of the low octaves
 * and the Worley feature-point hash.  Same seed -> same tables -> same
 * terrain. */
#ifndef ISOTERRA_NOISE_H
#define ISOTERRA_NOISE_H

#include <stdint.h>
#include <stddef.h>

#define NOISE_TEX_SIZE 16
#define NOISE_TEX_COUNT 3
#define NOISE_TEX_TEXELS (NOISE_TEX_SIZE * NOISE_TEX_SIZE * NOISE_TEX_SIZE)

struct noise_set {
	int seed;
	uint8_t perm[256];
	/* RGBA values in [-1,1], x fastest, then y, then z; already rounded to
	 * what GL_RGBA16F stores. */
	float tex[NOISE_TEX_COUNT][NOISE_TEX_TEXELS * 4];
	uint16_t tex_half[NOISE_TEX_COUNT][NOISE_TEX_TEXELS * 4];
	float rot[4][9]; /* row-major 3x3 rotations for the lowest octaves */
};

/* seed 0 gives Ken Perlin's reference permutation (ImprovedNoise.java). */
void noise_set_init(struct noise_set *ns, int seed);

/* CPU mirrors of the GLSL functions in shaders/noise.glsl. */
float noise_perlin(const struct noise_set *ns, float x, float y, float z);
/* Trilinear, repeating sample of volume k at texel-space point (x,y,z)
 * (one lattice cell per texel), channel c.  Full fp32 weights: the same as
 * noise_tex_manual() in GLSL; hardware filtering only approximates it. */
float noise_tex_sample(const struct noise_set *ns, int k, float x, float y, float z, int c);
/* Worley cellular basis: one feature point per unit cube, placed by a hash
 * of (cube, seed, salt); searches the 27 cubes around (x,y,z) and returns the
 * four smallest distances F1 <= F2 <= F3 <= F4 in f[0..3]. */
void noise_worley(const struct noise_set *ns, float x, float y, float z, int salt, float f[4]);
/* The 32-bit integer hash used by noise_worley (== nhash() in GLSL). */
uint32_t noise_hash(uint32_t x);

/* IEEE binary16 conversions (round to nearest even, subnormals, inf/NaN),
 * as GL stores RGBA16F. */
uint16_t noise_float_to_half(float f);
float noise_half_to_float(uint16_t h);

/* The std140 "NoiseTables" uniform block (binding 0) of noise.glsl:
 *   ivec4 nt_perm[64];  256 permutation entries, 4 per ivec4   (offset 0)
 *   vec4  nt_rot[12];   4 rotations x 3 rows (xyz used)        (offset 1024)
 *   ivec4 nt_info;      x = seed                               (offset 1216) */
#define NOISE_UBO_SIZE 1232
void noise_ubo_pack(const struct noise_set *ns, unsigned char out[NOISE_UBO_SIZE]);

/* GL side (noise_gl.c).  Textures use units 0..2 (layout binding in GLSL),
 * the permutation/rotation uniform block uses UBO binding 0. */
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
