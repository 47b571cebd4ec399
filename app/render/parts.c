/* isoterra — a mesh's draw split into parts (render_int.h): the plan, and
 * the compute pass (shaders/draw_parts.comp) that writes the parts'
 * indirect commands from the mesh's own, on the GPU. */
#include "render_int.h"
#include "gpu.h"
#include "core.h"

#include <string.h>

uint32_t parts_plan(uint32_t capacity, uint32_t triangles, uint32_t *per_part)
{
	uint32_t per = triangles;
	uint32_t least = (uint32_t)(((uint64_t)capacity + PARTS_MAX - 1) / PARTS_MAX);
	if (per < least)
		per = least;
	*per_part = per;
	uint32_t n = (uint32_t)(((uint64_t)capacity + per - 1) / per);
	return n ? n : 1;
}

static int parts_init(struct draw_parts *dp)
{
	char err[512];
	dp->prog = gpu_compute_program("draw_parts.comp", NULL, err, sizeof(err));
	if (!dp->prog) {
		log_error("draw in parts: %s", err);
		return -1;
	}
	dp->l_src = glGetUniformLocation(dp->prog, "u_src");
	dp->l_part = glGetUniformLocation(dp->prog, "u_part");
	dp->l_parts = glGetUniformLocation(dp->prog, "u_parts");
	dp->l_indexed = glGetUniformLocation(dp->prog, "u_indexed");
	glGenBuffers(1, &dp->buf);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, dp->buf);
	glBufferData(GL_SHADER_STORAGE_BUFFER, PARTS_MAX * PART_BYTES, NULL, GL_DYNAMIC_DRAW);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	if (gpu_check("the parts' command buffer") < 0) {
		parts_free(dp);
		return -1;
	}
	return 0;
}

int parts_split(struct draw_parts *dp, GLuint src, GLintptr offset, bool indexed, uint32_t parts, uint32_t per_part)
{
	if (!dp->prog && parts_init(dp) < 0)
		return -1;
	if (parts > PARTS_MAX || (uint64_t)per_part * 3 > UINT32_MAX) {
		log_error("draw in parts: %u parts of %u triangles is past the plan's bounds", parts, per_part);
		return -1;
	}
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_STATUS, src);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, dp->buf);
	glProgramUniform1ui(dp->prog, dp->l_src, (GLuint)(offset / 4));
	glProgramUniform1ui(dp->prog, dp->l_part, 3 * per_part);
	glProgramUniform1ui(dp->prog, dp->l_parts, parts);
	glProgramUniform1i(dp->prog, dp->l_indexed, indexed ? 1 : 0);
	glUseProgram(dp->prog);
	glDispatchCompute((parts + WG_SIZE - 1) / WG_SIZE, 1, 1);
	glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
	glUseProgram(0);
	return gpu_check("draw in parts") < 0 ? -1 : 0;
}

void parts_free(struct draw_parts *dp)
{
	if (dp->prog)
		glDeleteProgram(dp->prog);
	if (dp->buf)
		glDeleteBuffers(1, &dp->buf);
	memset(dp, 0, sizeof(*dp));
}
