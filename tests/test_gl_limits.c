/* isoterra — the GL limits table (app/gpu/gl_limits.c) against the shaders:
 * every pass is compiled as the program compiles it and the driver's
 * program introspection (storage blocks, uniform blocks, samplers, images,
 * uniform components, local size, bindings, attributes) must equal what
 * the table says, so the start-up check cannot drift from shaders/.  Then
 * the check itself: the limits as queried pass, and a lowered one
 * (ISOTERRA_GL_LIMIT_OVERRIDE) fails with one line naming the limit, the
 * value needed and the value found.  Prints the driver's values
 * (docs/PLATFORMS.md quotes them for llvmpipe). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_fixture.h"
#include "gl_limits.h"
#include "tcheck.h"

static int type_components(GLenum t)
{
	switch (t) {
	case GL_FLOAT: case GL_INT: case GL_UNSIGNED_INT: case GL_BOOL: return 1;
	case GL_FLOAT_VEC2: case GL_INT_VEC2: case GL_UNSIGNED_INT_VEC2: case GL_BOOL_VEC2: return 2;
	case GL_FLOAT_VEC3: case GL_INT_VEC3: case GL_UNSIGNED_INT_VEC3: case GL_BOOL_VEC3: return 3;
	case GL_FLOAT_VEC4: case GL_INT_VEC4: case GL_UNSIGNED_INT_VEC4: case GL_BOOL_VEC4: return 4;
	case GL_FLOAT_MAT2: return 4;
	case GL_FLOAT_MAT3: return 9;
	case GL_FLOAT_MAT4: return 16;
	case GL_FLOAT_MAT2x3: case GL_FLOAT_MAT3x2: return 6;
	case GL_FLOAT_MAT2x4: case GL_FLOAT_MAT4x2: return 8;
	case GL_FLOAT_MAT3x4: case GL_FLOAT_MAT4x3: return 12;
	default: return -1; /* opaque: sampler or image */
	}
}

static bool is_image(GLenum t)
{
	switch (t) {
	case GL_IMAGE_2D: case GL_IMAGE_3D: case GL_IMAGE_CUBE: case GL_IMAGE_2D_ARRAY:
	case GL_INT_IMAGE_2D: case GL_INT_IMAGE_3D: case GL_INT_IMAGE_CUBE: case GL_INT_IMAGE_2D_ARRAY:
	case GL_UNSIGNED_INT_IMAGE_2D: case GL_UNSIGNED_INT_IMAGE_3D: case GL_UNSIGNED_INT_IMAGE_CUBE:
	case GL_UNSIGNED_INT_IMAGE_2D_ARRAY:
		return true;
	default:
		return false;
	}
}

static const GLenum referenced[GLS_COUNT] = {
	[GLS_COMPUTE] = GL_REFERENCED_BY_COMPUTE_SHADER,
	[GLS_VERTEX] = GL_REFERENCED_BY_VERTEX_SHADER,
	[GLS_FRAGMENT] = GL_REFERENCED_BY_FRAGMENT_SHADER,
};
static const char *const stage_name[GLS_COUNT] = { "compute", "vertex", "fragment" };

/* What the driver reports for a linked program, in the table's terms. */
static void introspect(GLuint prog, bool compute, struct gl_pass *out)
{
	memset(out, 0, sizeof(*out));
	out->max_binding = -1;
	GLint n = 0;
	glGetProgramInterfaceiv(prog, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &n);
	for (GLint i = 0; i < n; i++) {
		GLenum props[4] = { GL_BUFFER_BINDING, referenced[0], referenced[1], referenced[2] };
		GLint v[4] = { 0, 0, 0, 0 };
		glGetProgramResourceiv(prog, GL_SHADER_STORAGE_BLOCK, (GLuint)i, 4, props, 4, NULL, v);
		if (v[0] > out->max_binding)
			out->max_binding = v[0];
		/* Mesa leaves GL_REFERENCED_BY_COMPUTE_SHADER of storage blocks
		 * unset: in a compute program every active block is the shader's */
		if (compute)
			out->use[GLS_COMPUTE].ssbo++;
		else
			for (int s = GLS_VERTEX; s < GLS_COUNT; s++)
				out->use[s].ssbo += v[1 + s] != 0;
	}
	glGetProgramInterfaceiv(prog, GL_UNIFORM_BLOCK, GL_ACTIVE_RESOURCES, &n);
	for (GLint i = 0; i < n; i++) {
		GLenum props[3] = { referenced[0], referenced[1], referenced[2] };
		GLint v[3] = { 0, 0, 0 };
		glGetProgramResourceiv(prog, GL_UNIFORM_BLOCK, (GLuint)i, 3, props, 3, NULL, v);
		for (int s = 0; s < GLS_COUNT; s++)
			out->use[s].ubos += v[s] != 0;
	}
	glGetProgramInterfaceiv(prog, GL_UNIFORM, GL_ACTIVE_RESOURCES, &n);
	for (GLint i = 0; i < n; i++) {
		GLenum props[6] = { GL_TYPE, GL_ARRAY_SIZE, GL_BLOCK_INDEX, referenced[0], referenced[1], referenced[2] };
		GLint v[6] = { 0, 0, 0, 0, 0, 0 };
		glGetProgramResourceiv(prog, GL_UNIFORM, (GLuint)i, 6, props, 6, NULL, v);
		if (v[2] != -1)
			continue; /* a member of a uniform block */
		int comps = type_components((GLenum)v[0]);
		for (int s = 0; s < GLS_COUNT; s++) {
			if (!v[3 + s])
				continue;
			if (comps > 0)
				out->use[s].components += comps * v[1];
			else if (is_image((GLenum)v[0]))
				out->use[s].images += v[1];
			else
				out->use[s].samplers += v[1];
		}
	}
	if (compute) {
		glGetProgramiv(prog, GL_COMPUTE_WORK_GROUP_SIZE, out->local);
	} else {
		glGetProgramInterfaceiv(prog, GL_PROGRAM_INPUT, GL_ACTIVE_RESOURCES, &n);
		for (GLint i = 0; i < n; i++) {
			GLenum prop = GL_LOCATION;
			GLint loc = -1;
			glGetProgramResourceiv(prog, GL_PROGRAM_INPUT, (GLuint)i, 1, &prop, 1, NULL, &loc);
			out->attribs += loc >= 0; /* built-ins (gl_VertexID) have none */
		}
	}
}

static void check_pass(const struct gl_pass *p, bool exact)
{
	char err[1024] = "";
	bool compute = p->cs != NULL;
	GLuint prog = compute ? gpu_compute_program(p->cs, p->defines, err, sizeof(err))
			      : gpu_graphics_program(p->vs, p->fs, p->defines, err, sizeof(err));
	CHECK(prog != 0, "%s: %s", p->name, err);
	if (!prog)
		return;
	struct gl_pass got;
	introspect(prog, compute, &got);
	glDeleteProgram(prog);
	CHECK(gpu_check("introspection") == 0, "%s: GL error", p->name);
	for (int s = 0; s < GLS_COUNT; s++) {
		const struct gl_stage_use *t = &p->use[s], *g = &got.use[s];
		/* a driver may drop what a pass declares but never reads; the table
		 * must never say less than the driver counts */
		CHECK(t->ssbo >= g->ssbo && (!exact || t->ssbo == g->ssbo), "%s %s: table says %d storage blocks, the driver counts %d",
		      p->name, stage_name[s], t->ssbo, g->ssbo);
		CHECK(t->samplers >= g->samplers && (!exact || t->samplers == g->samplers),
		      "%s %s: table says %d samplers, the driver counts %d", p->name, stage_name[s], t->samplers, g->samplers);
		CHECK(t->images >= g->images && (!exact || t->images == g->images),
		      "%s %s: table says %d images, the driver counts %d", p->name, stage_name[s], t->images, g->images);
		CHECK(t->ubos >= g->ubos && (!exact || t->ubos == g->ubos),
		      "%s %s: table says %d uniform blocks, the driver counts %d", p->name, stage_name[s], t->ubos, g->ubos);
		/* which stage a uniform lands in varies with the compiler (Mesa 25
		 * moves some of sky's from the fragment to the vertex stage): the
		 * table holds the largest count seen, the driver's must not exceed it */
		CHECK(t->components >= g->components, "%s %s: table says %d uniform components, the driver counts %d",
		      p->name, stage_name[s], t->components, g->components);
	}
	CHECK(p->max_binding >= got.max_binding && (!exact || p->max_binding == got.max_binding),
	      "%s: table says binding %d at most, the driver reports %d", p->name, p->max_binding, got.max_binding);
	if (compute)
		CHECK(!memcmp(p->local, got.local, sizeof(got.local)), "%s: table says local size %dx%dx%d, the driver %dx%dx%d",
		      p->name, p->local[0], p->local[1], p->local[2], got.local[0], got.local[1], got.local[2]);
	else
		CHECK(p->attribs == got.attribs, "%s: table says %d attributes, the driver %d", p->name, p->attribs,
		      got.attribs);
	printf("  %-34s ssbo %2d/%d/%d  samplers %d/%d/%d  images %d  ubo %d  components %3d/%3d/%3d  local %dx%dx%d  "
	       "binding %2d  attribs %d\n",
	       p->name, got.use[0].ssbo, got.use[1].ssbo, got.use[2].ssbo, got.use[0].samplers, got.use[1].samplers,
	       got.use[2].samplers, got.use[0].images, got.use[0].ubos, got.use[0].components, got.use[1].components,
	       got.use[2].components, got.local[0], got.local[1], got.local[2], got.max_binding, got.attribs);
}

/* One program declares a workgroup-shared variable, of 256 bytes (the
 * table's need of GL_MAX_COMPUTE_SHARED_MEMORY_SIZE): the world pre-pass's
 * "shared float s_red[64];" in block_bound.glsl.  (The density pass packs
 * its sign bits without shared memory.) */
static void check_shared(void)
{
	int found = 0, known_bound = 0;
	for (size_t i = 0; i < embedded_shader_count; i++) {
		const char *t = embedded_shaders[i].text;
		for (const char *line = t; line && *line;) {
			const char *c = line + strspn(line, " \t");
			if (!strncmp(c, "shared float s_red[64];", 23) &&
				 !strcmp(embedded_shaders[i].name, "block_bound.glsl"))
				known_bound++;
			else if (!strncmp(c, "shared ", 7)) {
				found++;
				fprintf(stderr, "%s declares a shared variable: %.40s\n", embedded_shaders[i].name, c);
			}
			line = strchr(line, '\n');
			if (line)
				line++;
		}
	}
	CHECK(found == 0 && known_bound == 1,
	      "%d unexpected shared declarations, %d of s_red: the table's need of "
	      "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is 256 bytes", found, known_bound);
}

static void expect_refusal(const char *override, const char *want1, const char *want2)
{
	char err[1024] = "";
	setenv("ISOTERRA_GL_LIMIT_OVERRIDE", override, 1);
	int rc = gl_limits_check(NULL, err, sizeof(err));
	unsetenv("ISOTERRA_GL_LIMIT_OVERRIDE");
	CHECK(rc < 0, "override '%s' accepted", override);
	CHECK(strstr(err, want1) && (!want2 || strstr(err, want2)), "override '%s': '%s' lacks '%s' / '%s'", override, err,
	      want1, want2 ? want2 : "");
	CHECK(!strchr(err, '\n'), "override '%s': more than one line: '%s'", override, err);
	printf("  %s -> %s\n", override, err);
}

int main(void)
{
	struct platform *plat = fixture_open(); /* gpu_init: the check passes on this driver */
	const char *ren = (const char *)glGetString(GL_RENDERER);
	/* llvmpipe keeps every declared block and uniform it links: the table
	 * must match it exactly (other drivers may count less) */
	bool exact = ren && strstr(ren, "llvmpipe");

	size_t np;
	const struct gl_pass *passes = gl_limits_passes(&np);
	printf("passes, as the driver counts them (compute/vertex/fragment):\n");
	for (size_t i = 0; i < np; i++)
		check_pass(&passes[i], exact);
	check_shared();

	size_t nl;
	const struct gl_limit *lim = gl_limits_list(&nl);
	int64_t have[64];
	char err[1024] = "";
	CHECK(nl <= 64, "%zu limits", nl);
	CHECK(gl_limits_check(have, err, sizeof(err)) == 0, "check on %s: %s", ren, err);
	printf("limits on %s (value / needed / ES 3.1 minimum):\n", ren ? ren : "?");
	for (size_t i = 0; i < nl && i < 64; i++) {
		const char *who;
		int64_t need = gl_limits_need(i, &who);
		char name[96];
		if (lim[i].index >= 0)
			snprintf(name, sizeof(name), "%s[%d]", lim[i].name, lim[i].index);
		else
			snprintf(name, sizeof(name), "%s", lim[i].name);
		/* '!': more than OpenGL ES 3.1 guarantees */
		printf("  %-42s %10" PRId64 " %10" PRId64 " %10" PRId64 " %c %s\n", name, have[i], need, lim[i].es31_min,
		       need > lim[i].es31_min ? '!' : ' ', who);
	}

	/* lowered limits: one line naming the limit, the need and the value */
	expect_refusal("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=4", "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS is 4",
		       "needs 10 (mc_vertices.comp (WITH_AO))");
	expect_refusal("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS=8", "GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS is 8", "needs 15");
	expect_refusal("GL_MAX_COMPUTE_SHARED_MEMORY_SIZE=128", "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is 128", "needs 256");
	expect_refusal("GL_MAX_3D_TEXTURE_SIZE=8,GL_MAX_IMAGE_UNITS=4", "GL_MAX_3D_TEXTURE_SIZE is 8", "needs 16");
	expect_refusal("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCK=4", "names no checked limit", NULL);
	expect_refusal("GL_MAX_IMAGE_UNITS", "not NAME=VALUE", NULL);
	/* exactly the need is enough */
	char ok_spec[128];
	snprintf(ok_spec, sizeof(ok_spec), "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS=%" PRId64, gl_limits_need(0, NULL));
	setenv("ISOTERRA_GL_LIMIT_OVERRIDE", ok_spec, 1);
	CHECK(gl_limits_check(NULL, err, sizeof(err)) == 0, "%s refused: %s", ok_spec, err);
	unsetenv("ISOTERRA_GL_LIMIT_OVERRIDE");

	platform_close(plat);
	return tc_done("test_gl_limits");
}
