/* isoterra — GL resources of the noise: three 16^3 GL_RGBA16F repeating
 * volumes (trilinear, texture units TEX_NOISE0..2) and the std140
 * NoiseTables uniform block (the low octaves' rotations, the seed and
 * Perlin's seed key; UBIND_NOISE).  Perlin noise itself needs no table.
 * See noise.h and shaders/noise.glsl. */
#include "noise.h"
#include "gpu.h"

#include <GLES3/gl31.h>
#include <stdio.h>
#include <string.h>

int noise_gl_init(struct noise_gl *ng, const struct noise_set *ns, char *err, size_t errlen)
{
	memset(ng, 0, sizeof(*ng));
	while (glGetError() != GL_NO_ERROR)
		;
	GLint prev_unit = 0;
	glGetIntegerv(GL_ACTIVE_TEXTURE, &prev_unit);
	glActiveTexture(GL_TEXTURE0);
	glGenTextures(NOISE_TEX_COUNT, ng->tex);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	for (int k = 0; k < NOISE_TEX_COUNT; k++) {
		glBindTexture(GL_TEXTURE_3D, ng->tex[k]);
		glTexStorage3D(GL_TEXTURE_3D, 1, GL_RGBA16F, NOISE_TEX_SIZE, NOISE_TEX_SIZE, NOISE_TEX_SIZE);
		glTexSubImage3D(GL_TEXTURE_3D, 0, 0, 0, 0, NOISE_TEX_SIZE, NOISE_TEX_SIZE, NOISE_TEX_SIZE, GL_RGBA,
				GL_HALF_FLOAT, ns->tex_half[k]);
		glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
		glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
		glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_S, GL_REPEAT);
		glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_T, GL_REPEAT);
		glTexParameteri(GL_TEXTURE_3D, GL_TEXTURE_WRAP_R, GL_REPEAT);
	}
	glBindTexture(GL_TEXTURE_3D, 0);
	glActiveTexture((GLenum)prev_unit);

	unsigned char ubo[NOISE_UBO_SIZE];
	noise_ubo_pack(ns, ubo);
	glGenBuffers(1, &ng->ubo);
	glBindBuffer(GL_UNIFORM_BUFFER, ng->ubo);
	glBufferData(GL_UNIFORM_BUFFER, NOISE_UBO_SIZE, ubo, GL_STATIC_DRAW);
	glBindBuffer(GL_UNIFORM_BUFFER, 0);

	GLenum e = glGetError();
	if (e != GL_NO_ERROR) {
		snprintf(err, errlen, "noise textures/uniform block: GL error 0x%04x", e);
		noise_gl_destroy(ng);
		return -1;
	}
	ng->seed = ns->seed;
	return 0;
}

void noise_gl_bind(const struct noise_gl *ng)
{
	for (int k = 0; k < NOISE_TEX_COUNT; k++) {
		glActiveTexture(GL_TEXTURE0 + TEX_NOISE0 + (GLenum)k);
		glBindTexture(GL_TEXTURE_3D, ng->tex[k]);
	}
	glActiveTexture(GL_TEXTURE0);
	glBindBufferBase(GL_UNIFORM_BUFFER, UBIND_NOISE, ng->ubo);
}

void noise_gl_destroy(struct noise_gl *ng)
{
	if (ng->tex[0] || ng->tex[1] || ng->tex[2])
		glDeleteTextures(NOISE_TEX_COUNT, ng->tex);
	if (ng->ubo)
		glDeleteBuffers(1, &ng->ubo);
	memset(ng, 0, sizeof(*ng));
}
