/* isoterra — the embedded surface texture set, generated at start-up (no
 * asset files): one tileable 128x128 RGBA8 texture whose channels hold a
 * rock/soil albedo variation (R), the slopes of a fractal height field
 * (G = d/du, B = d/dv, for per-projection bump mapping) and the height itself
 * (A, used for strata and detail).  Periodic value-noise fBm, so it tiles.
 * Its mip levels are averaged here too (a 2x2 box, what glGenerateMipmap
 * does for a power-of-two size): llvmpipe's glGenerateMipmap compiles a
 * blit's shaders first, 50-100 ms of the no-flag run's start, for 22 000
 * texels that take the CPU well under a millisecond. */
#include "render.h"
#include "gpu.h"

#include <math.h>
#include <stdlib.h>

#define S 128
#define LEVELS 8 /* 128 .. 1 */
_Static_assert(S >> (LEVELS - 1) == 1, "the mip chain ends at 1x1");

static float lattice(int x, int y, int period, uint32_t salt)
{
	x = ((x % period) + period) % period;
	y = ((y % period) + period) % period;
	uint32_t h = (uint32_t)x * 73856093u ^ (uint32_t)y * 19349663u ^ salt;
	h ^= h >> 13;
	h *= 0x5bd1e995u;
	h ^= h >> 15;
	return (float)(h & 0xffffff) / (float)0xffffff;
}

static float value_noise(float u, float v, int period, uint32_t salt)
{
	int x = (int)floorf(u), y = (int)floorf(v);
	float fx = u - (float)x, fy = v - (float)y;
	fx = fx * fx * (3.0f - 2.0f * fx);
	fy = fy * fy * (3.0f - 2.0f * fy);
	float a = lattice(x, y, period, salt), b = lattice(x + 1, y, period, salt);
	float c = lattice(x, y + 1, period, salt), d = lattice(x + 1, y + 1, period, salt);
	return (a + (b - a) * fx) + ((c + (d - c) * fx) - (a + (b - a) * fx)) * fy;
}

static float fbm(float u, float v, uint32_t salt)
{
	float s = 0, a = 0.5f;
	for (int o = 0, period = 8; o < 5; o++, period *= 2, a *= 0.5f)
		s += a * value_noise(u * (float)period / S, v * (float)period / S, period, salt + (uint32_t)o);
	return s;
}

/* The next mip level of an n x n RGBA8 image, in place (n/2 x n/2 at
 * its start): each texel the rounded mean of the 2x2 it covers. */
static void halve(unsigned char *px, int n)
{
	int h = n / 2;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < h; x++)
			for (int c = 0; c < 4; c++) {
				const unsigned char *a = px + 4 * ((2 * y) * n + 2 * x) + c, *b = a + 4 * n;
				px[4 * (y * h + x) + c] = (unsigned char)((a[0] + a[4] + b[0] + b[4] + 2) / 4);
			}
}

GLuint surface_texture_create(void)
{
	unsigned char *px = malloc(S * S * 4);
	float *hgt = malloc(sizeof(float) * S * S);
	if (!px || !hgt) {
		free(px);
		free(hgt);
		return 0;
	}
	for (int y = 0; y < S; y++)
		for (int x = 0; x < S; x++)
			hgt[y * S + x] = fbm((float)x, (float)y, 0x1234u);
	for (int y = 0; y < S; y++)
		for (int x = 0; x < S; x++) {
			float du = hgt[y * S + (x + 1) % S] - hgt[y * S + (x + S - 1) % S];
			float dv = hgt[((y + 1) % S) * S + x] - hgt[((y + S - 1) % S) * S + x];
			float alb = fbm((float)x * 2.0f, (float)y * 2.0f, 0x9876u);
			unsigned char *p = px + 4 * (y * S + x);
			p[0] = (unsigned char)fminf(255.0f, alb * 255.0f);
			p[1] = (unsigned char)fmaxf(0.0f, fminf(255.0f, 128.0f + du * 1200.0f));
			p[2] = (unsigned char)fmaxf(0.0f, fminf(255.0f, 128.0f + dv * 1200.0f));
			p[3] = (unsigned char)fminf(255.0f, hgt[y * S + x] * 255.0f);
		}
	GLuint tex = 0;
	glGenTextures(1, &tex);
	glBindTexture(GL_TEXTURE_2D, tex);
	glTexStorage2D(GL_TEXTURE_2D, LEVELS, GL_RGBA8, S, S);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	for (int level = 0, n = S;; level++, n /= 2) {
		glTexSubImage2D(GL_TEXTURE_2D, level, 0, 0, n, n, GL_RGBA, GL_UNSIGNED_BYTE, px);
		if (n == 1)
			break;
		halve(px, n);
	}
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
	/* bilinear within the nearest mip level, not trilinear: half the texels
	 * of each of the terrain's four to seven taps a pixel (a software
	 * rasterizer fetches them one by one: about a tenth of a world frame
	 * here), and on this noise texture no visible change (the world's
	 * first frame: PSNR 58 dB against trilinear, no pixel off by more
	 * than 8) */
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
	glBindTexture(GL_TEXTURE_2D, 0);
	free(px);
	free(hgt);
	if (gpu_check("surface texture") < 0) {
		glDeleteTextures(1, &tex);
		return 0;
	}
	return tex;
}
