/* isoterra — the GL limits against the driver: every pass is compiled as
 * the program compiles it, and what the driver's program introspection
 * reports (storage blocks, uniform blocks, samplers, images, uniform
 * components, local size, binding points, attributes) is what the program
 * checks (gl_limits_check_program runs on every link): the test proves it
 * by lowering each per-program limit to one below the largest count the
 * driver reported, and the pass with that count is then refused, naming
 * the limit, the count and the pass; at the count itself it builds.  The
 * passes must keep to the design's budget on any driver (app/gpu/abi.h:
 * binding points below BIND_POINTS, five storage blocks a pass, where
 * Mali's Panfrost gives 8; without curves the OpenGL ES 3.1 minimums, 4
 * blocks and binding points 0..3).  Then the fixed needs: a lowered one
 * (ISOTERRA_GL_LIMIT_OVERRIDE) fails with one line naming the limit, the
 * value needed and the value found.  Prints the driver's values
 * (docs/PLATFORMS.md quotes them). */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "abi.h"
#include "gpu_fixture.h"
#include "gl_limits.h"
#include "tcheck.h"

/* A pass's #defines: the table's, or those its library makes. */
static const char *pass_defines(const struct gl_pass *p, char *buf, size_t len)
{
	if (!p->make_defines)
		return p->defines ? p->defines : "";
	p->make_defines(buf, len);
	return buf;
}

static GLuint build(const struct gl_pass *p, char *err, size_t errlen)
{
	char made[1024];
	const char *defines = pass_defines(p, made, sizeof(made));
	return p->cs ? gpu_compute_program(p->cs, defines, err, errlen)
		     : gpu_graphics_program(p->vs, p->fs, defines, err, errlen);
}

/* The largest count of any pass, and which pass. */
struct most {
	int ssbo, binding, comp_components, comp_samplers, ubo_binding;
	const struct gl_pass *by_ssbo, *by_binding, *by_components, *by_samplers;
};

static void check_pass(const struct gl_pass *p, struct most *m)
{
	char err[1024] = "";
	bool compute = p->cs != NULL;
	/* the name first: a driver whose compiler takes long shows which */
	printf("  %-34s ", p->name);
	fflush(stdout);
	struct timespec t0, t1;
	clock_gettime(CLOCK_MONOTONIC, &t0);
	GLuint prog = build(p, err, sizeof(err));
	clock_gettime(CLOCK_MONOTONIC, &t1);
	double ms = (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6;
	CHECK(prog != 0, "%s: %s", p->name, err);
	if (!prog) {
		printf("\n");
		return;
	}
	struct gl_use got;
	gl_limits_introspect(prog, compute, &got);
	glDeleteProgram(prog);
	CHECK(gpu_check("introspection") == 0, "%s: GL error", p->name);
	/* the design's budget, as this driver counts it */
	CHECK(got.max_binding < BIND_POINTS, "%s: storage binding %d, abi.h gives 0..%d", p->name, got.max_binding,
	      BIND_POINTS - 1);
	CHECK(got.use[GLS_COMPUTE].ssbo <= 5 && got.ssbo_total <= 5, "%s: %d storage blocks, the budget is 5 a pass",
	      p->name, got.ssbo_total);
	CHECK(got.max_ubo_binding <= UBIND_MC_TABLES, "%s: uniform block binding %d past abi.h's", p->name,
	      got.max_ubo_binding);
	CHECK(got.max_unit <= TEX_SURFACE, "%s: texture unit %d past abi.h's", p->name, got.max_unit);
	CHECK(!compute || (got.local[0] > 0 && got.local[1] > 0 && got.local[2] > 0), "%s: local size %dx%dx%d",
	      p->name, got.local[0], got.local[1], got.local[2]);
	if (got.ssbo_total > m->ssbo) {
		m->ssbo = got.ssbo_total;
		m->by_ssbo = p;
	}
	if (got.max_binding + 1 > m->binding) {
		m->binding = got.max_binding + 1;
		m->by_binding = p;
	}
	if (got.use[GLS_COMPUTE].components > m->comp_components) {
		m->comp_components = got.use[GLS_COMPUTE].components;
		m->by_components = p;
	}
	if (got.use[GLS_COMPUTE].samplers > m->comp_samplers) {
		m->comp_samplers = got.use[GLS_COMPUTE].samplers;
		m->by_samplers = p;
	}
	if (got.max_ubo_binding + 1 > m->ubo_binding)
		m->ubo_binding = got.max_ubo_binding + 1;
	printf("ssbo %2d/%d/%d  samplers %d/%d/%d  images %d  ubo %d  components %3d/%3d/%3d  local %dx%dx%d  "
	       "binding %2d  attribs %d  built in %.0f ms\n",
	       got.use[0].ssbo, got.use[1].ssbo, got.use[2].ssbo, got.use[0].samplers, got.use[1].samplers,
	       got.use[2].samplers, got.use[0].images, got.use[0].ubos, got.use[0].components, got.use[1].components,
	       got.use[2].components, got.local[0], got.local[1], got.local[2], got.max_binding, got.attribs, ms);
}

/* Without curves (HAS_CURVES 0: the default volume and the world) a pass
 * fits the OpenGL ES 3.1 minimums: 4 storage blocks, binding points 0..3. */
static void check_es31_minimum(const struct gl_pass *p)
{
	if (p->tests_only || !p->cs || !strncmp(p->cs, "curve_", 6))
		return; /* the curves' own passes carve by definition */
	char defines[1536], made[1024], err[1024] = "";
	snprintf(defines, sizeof(defines), "#define HAS_CURVES 0\n#define HAS_TUNNELS 0\n%s",
		 pass_defines(p, made, sizeof(made)));
	GLuint prog = gpu_compute_program(p->cs, defines, err, sizeof(err));
	CHECK(prog != 0, "%s without curves: %s", p->name, err);
	if (!prog)
		return;
	struct gl_use got;
	gl_limits_introspect(prog, true, &got);
	glDeleteProgram(prog);
	CHECK(got.ssbo_total <= 4 && got.max_binding < 4,
	      "%s without curves: %d storage blocks, binding %d: over the ES 3.1 minimums (4, 0..3)", p->name,
	      got.ssbo_total, got.max_binding);
}

/* With LIMIT lowered to need - 1 the pass that needs it is refused with one
 * line naming the limit, the count and the pass; at need it builds. */
static void prove_need(const char *limit, int need, const struct gl_pass *p)
{
	if (!p || need <= 0) {
		printf("  %s: no pass uses it on this driver\n", limit);
		return;
	}
	char spec[128], err[1024] = "", want[256];
	snprintf(spec, sizeof(spec), "%s=%d", limit, need - 1);
	setenv("ISOTERRA_GL_LIMIT_OVERRIDE", spec, 1);
	CHECK(gl_limits_check(NULL, err, sizeof(err)) == 0, "%s: the start check refused: %s", spec, err);
	GLuint prog = build(p, err, sizeof(err));
	CHECK(prog == 0, "%s: %s built", spec, p->name);
	if (prog)
		glDeleteProgram(prog);
	snprintf(want, sizeof(want), "%s is %d on ", limit, need - 1);
	char tail[128];
	snprintf(tail, sizeof(tail), ", isoterra needs %d (", need);
	CHECK(strstr(err, want) && strstr(err, tail) && !strchr(err, '\n'), "%s: '%s' lacks '%s' / '%s'", spec, err,
	      want, tail);
	printf("  %s -> %s\n", spec, err);
	snprintf(spec, sizeof(spec), "%s=%d", limit, need);
	setenv("ISOTERRA_GL_LIMIT_OVERRIDE", spec, 1);
	CHECK(gl_limits_check(NULL, err, sizeof(err)) == 0, "%s: the start check refused: %s", spec, err);
	prog = build(p, err, sizeof(err));
	CHECK(prog != 0, "%s: %s refused at its need: %s", spec, p->name, err);
	if (prog)
		glDeleteProgram(prog);
	unsetenv("ISOTERRA_GL_LIMIT_OVERRIDE");
	CHECK(gl_limits_check(NULL, err, sizeof(err)) == 0, "the driver's own limits: %s", err);
}

/* One program declares a workgroup-shared variable, of WG_SIZE floats (the
 * table's need of GL_MAX_COMPUTE_SHARED_MEMORY_SIZE): the world pre-pass's
 * "shared float s_red[WG_SIZE];" in block_bound.glsl.  (The density pass packs
 * its sign bits without shared memory.) */
static void check_shared(void)
{
	int found = 0, known_bound = 0;
	for (size_t i = 0; i < embedded_shader_count; i++) {
		const char *t = embedded_shaders[i].text;
		for (const char *line = t; line && *line;) {
			const char *c = line + strspn(line, " \t");
			if (!strncmp(c, "shared float s_red[WG_SIZE];", 28) &&
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
	      "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is WG_SIZE * 4 = %d bytes", found, known_bound, WG_SIZE * 4);
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
	struct platform *plat = fixture_open(); /* gpu_init: the start check passes on this driver */
	const char *ren = (const char *)glGetString(GL_RENDERER);

	size_t np;
	const struct gl_pass *passes = gl_limits_passes(&np);
	struct most m;
	memset(&m, 0, sizeof(m));
	printf("passes, as the driver counts them (compute/vertex/fragment):\n");
	for (size_t i = 0; i < np; i++)
		check_pass(&passes[i], &m);
	for (size_t i = 0; i < np; i++)
		check_es31_minimum(&passes[i]);
	check_shared();
	printf("the most: %d storage blocks (%s), binding points 0..%d (%s), %d compute uniform components (%s)\n",
	       m.ssbo, m.by_ssbo ? m.by_ssbo->name : "-", m.binding - 1, m.by_binding ? m.by_binding->name : "-",
	       m.comp_components, m.by_components ? m.by_components->name : "-");
	/* Panfrost (Mali): 8 storage blocks a stage and combined, 8 binding points */
	CHECK(m.ssbo <= 8 && m.binding <= 8, "Panfrost's 8 blocks / 8 bindings: %d / %d", m.ssbo, m.binding);

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
		CHECK(need <= have[i], "%s: need %" PRId64 " over the driver's %" PRId64, name, need, have[i]);
	}
	/* the program's recorded needs are the driver's counts */
	CHECK(gl_limits_need(0, NULL) == m.ssbo, "GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS: recorded need %" PRId64
	      ", the driver counts %d", gl_limits_need(0, NULL), m.ssbo);

	/* each per-program limit lowered below the driver's count refuses the pass */
	printf("lowered to one below the driver's count:\n");
	prove_need("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS", m.ssbo, m.by_ssbo);
	prove_need("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS", m.binding, m.by_binding);
	prove_need("GL_MAX_COMPUTE_UNIFORM_COMPONENTS", m.comp_components, m.by_components);
	prove_need("GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS", m.comp_samplers, m.by_samplers);

	/* the fixed needs: one line naming the limit, the need and the value */
	expect_refusal("GL_MAX_COMPUTE_SHARED_MEMORY_SIZE=128", "GL_MAX_COMPUTE_SHARED_MEMORY_SIZE is 128", "needs 256");
	expect_refusal("GL_MAX_3D_TEXTURE_SIZE=8,GL_MAX_IMAGE_UNITS=4", "GL_MAX_3D_TEXTURE_SIZE is 8", "needs 16");
	expect_refusal("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCK=4", "names no checked limit", NULL);
	expect_refusal("GL_MAX_IMAGE_UNITS", "not NAME=VALUE", NULL);

	platform_close(plat);
	return tc_done("test_gl_limits");
}
