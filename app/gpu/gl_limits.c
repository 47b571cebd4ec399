/* isoterra — the GL limits the program relies on, checked at start.
 * See gl_limits.h; the numbers per pass are read off shaders/ and verified
 * against the driver's own introspection by tests/test_gl_limits.c. */
#include "gl_limits.h"
#include "abi.h"
#include "noise.h"

#include <GLES3/gl31.h>
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"

#define CS(s, t, i, u, c) { [GLS_COMPUTE] = { s, t, i, u, c } }
#define VF(vs_c, fs_t, fs_c) { [GLS_VERTEX] = { 0, 0, 0, 0, vs_c }, [GLS_FRAGMENT] = { 0, fs_t, 0, 0, fs_c } }

/* Storage blocks per compute pass: common.glsl declares the density (0), or
 * the sign bits (14) for classification and the index pass, and the
 * Marching Cubes tables (3) unless the pass writes the density (then the
 * density and the sign bits); hp.glsl
 * the pyramid's base (1) and levels (2); mc_status.glsl the status block (6);
 * density.glsl, through carve.glsl -> curves.glsl, the curves' four buffers
 * (8..11), and through noise.glsl and heightmap.glsl the noise block, three
 * 3D noise samplers, the heightmap sampler and (with a control map file,
 * counted here: HAS_CONTROL_MAP 1) the control map's.  Uniform components: the
 * largest count seen on llvmpipe (Mesa 22.3 and 25.0 split sky's between
 * the stages differently). */
static const struct gl_pass passes[] = {
	/* name, cs, vs, fs, defines, tests_only,
	 *     { ssbo, samplers, images, ubos, uniform components }, local size, max binding, attribs */
	/* the terrain field's programs (app/terrain/terrain.c): the density
	 * pass, and the vertex pass with ambient occlusion (its rays sample
	 * the field: + curves, noise) */
	{ "density.comp", "density.comp", NULL, NULL, "#define FIELD_PASS_DENSITY 1\n#define HAS_CONTROL_MAP 1\n", false,
	  CS(6, 5, 0, 1, 90), { 64, 1, 1 }, BIND_SIGNS, 0 },
	/* the streaming world's coarse pre-pass (shaders/block_bound.glsl):
	 * the candidate boxes and verdicts (12, 13), the field's resources */
	{ "density.comp (FIELD_PASS_BOUND)", "density.comp", NULL, NULL, "#define FIELD_PASS_BOUND 1\n#define HAS_CONTROL_MAP 1\n",
	  false, CS(6, 4, 0, 1, 90), { 64, 1, 1 }, BIND_AUX_B, 0 },
	/* the debris filter: the raw sign bits (12) into the filtered (14); the
	 * densities and tables of common.glsl are declared, not read */
	{ "mc_debris.comp", "mc_debris.comp", NULL, NULL, NULL, false,
	  CS(4, 0, 0, 0, 5), { 64, 1, 1 }, BIND_SIGNS, 0 },
	{ "mc_classify.comp", "mc_classify.comp", NULL, NULL, NULL, false,
	  CS(4, 0, 0, 0, 11), { 64, 1, 1 }, BIND_SIGNS, 0 },
	{ "hp_reduce.comp", "hp_reduce.comp", NULL, NULL, NULL, false,
	  CS(4, 0, 0, 0, 19), { 64, 1, 1 }, BIND_MC_TABLES, 0 },
	{ "hp_downsweep.comp", "hp_downsweep.comp", NULL, NULL, NULL, false,
	  CS(4, 0, 0, 0, 19), { 64, 1, 1 }, BIND_MC_TABLES, 0 },
	{ "mc_setup.comp", "mc_setup.comp", NULL, NULL, NULL, false,
	  CS(5, 0, 0, 0, 22), { 1, 1, 1 }, BIND_STATUS, 0 },
	{ "mc_vertices.comp", "mc_vertices.comp", NULL, NULL, NULL, false,
	  CS(6, 0, 0, 0, 29), { 64, 1, 1 }, BIND_STATUS, 0 },
	{ "mc_vertices.comp (WITH_AO)", "density.comp", NULL, NULL,
	  "#define FIELD_PASS_VERTICES 1\n#define WITH_AO 1\n#define AO_FAR_OUTSIDE 1\n#define HAS_CONTROL_MAP 1\n",
	  false,
	  CS(10, 5, 0, 1, 109), { 64, 1, 1 }, BIND_CURVE_PRM, 0 },
	{ "mc_indices.comp", "mc_indices.comp", NULL, NULL, NULL, false,
	  CS(6, 0, 0, 0, 23), { 64, 1, 1 }, BIND_SIGNS, 0 },
	{ "mc_atomic.comp", "mc_atomic.comp", NULL, NULL, NULL, false,
	  CS(4, 0, 0, 0, 13), { 64, 1, 1 }, BIND_STATUS, 0 },
	{ "mc_nocompact.comp", "mc_nocompact.comp", NULL, NULL, NULL, false,
	  CS(4, 0, 0, 0, 12), { 64, 1, 1 }, BIND_STATUS, 0 },
	{ "mc_finish.comp", "mc_finish.comp", NULL, NULL, NULL, false,
	  CS(3, 0, 0, 0, 9), { 1, 1, 1 }, BIND_STATUS, 0 },
	/* the curves' displacement map over a heightmap (tiles: binding 13) */
	{ "curve_bake.comp (BAKE_HEIGHTMAP)", "curve_bake.comp", NULL, NULL, "#define BAKE_HEIGHTMAP 1\n", false,
	  CS(6, 1, 0, 0, 27), { 8, 8, 1 }, BIND_AUX_B, 0 },
	/* V4L2 output: the frame sampled, the device's layout stored */
	{ "v4l2_convert.comp", "v4l2_convert.comp", NULL, NULL, "#define FMT 0u\n", false,
	  CS(0, 1, 1, 0, 9), { 64, 1, 1 }, -1, 0 },
	{ "render.vert + render.frag", NULL, "render.vert", "render.frag", "#define DETAIL_NORMALS 1\n", false,
	  VF(17, 1, 23), { 0, 0, 0 }, -1, 2 },
	/* the volume's depth pre-pass on a software rasterizer (render.c) */
	{ "render.vert + depth.frag", NULL, "render.vert", "depth.frag", NULL, false,
	  VF(17, 0, 0), { 0, 0, 0 }, -1, 2 },
	{ "water.vert + water.frag", NULL, "water.vert", "water.frag", NULL, false,
	  VF(25, 0, 20), { 0, 0, 0 }, -1, 0 },
	{ "sky.vert + sky.frag", NULL, "sky.vert", "sky.frag", NULL, false,
	  VF(19, 0, 7), { 0, 0, 0 }, -1, 0 },
	{ "osd.vert + osd.frag", NULL, "osd.vert", "osd.frag", NULL, false,
	  VF(6, 1, 89), { 0, 0, 0 }, -1, 0 },
	/* a mesh's draw command split into parts on a software rasterizer
	 * (app/render/parts.c): the status block (6) into the parts (12) */
	{ "draw_parts.comp", "draw_parts.comp", NULL, NULL, NULL, false,
	  CS(2, 0, 0, 0, 4), { 64, 1, 1 }, BIND_AUX_A, 0 },
	/* the governor's upscale (app/render/upscale.c) */
	{ "upscale.vert + upscale.frag", NULL, "upscale.vert", "upscale.frag", NULL, false,
	  VF(2, 1, 4), { 0, 0, 0 }, -1, 0 },
	/* edge smoothing over the finished frame (--antialias fxaa) */
	{ "upscale.vert + fxaa.frag", NULL, "upscale.vert", "fxaa.frag", NULL, false,
	  VF(2, 1, 4), { 0, 0, 0 }, -1, 0 },
	/* the tests' own passes */
	{ "hp_test.comp", "hp_test.comp", NULL, NULL, NULL, true,
	  CS(5, 0, 0, 0, 22), { 64, 1, 1 }, BIND_TEST_OUT, 0 },
	{ "curve_test.comp", "curve_test.comp", NULL, NULL, NULL, true,
	  CS(6, 1, 0, 1, 24), { 64, 1, 1 }, BIND_AUX_B, 0 },
};

const struct gl_pass *gl_limits_passes(size_t *count)
{
	*count = sizeof(passes) / sizeof(passes[0]);
	return passes;
}

enum need_kind {
	N_STAGE_SSBO, N_COMBINED_SSBO, N_BINDINGS, N_STAGE_SAMPLERS, N_STAGE_IMAGES, N_STAGE_UBOS,
	N_STAGE_COMPONENTS, N_INVOCATIONS, N_LOCAL, N_ATTRIBS, N_CONST,
};

struct limit_def {
	struct gl_limit l;
	enum need_kind kind;
	int arg;            /* stage or axis */
	int64_t value;      /* N_CONST */
	const char *why;    /* N_CONST: where the number comes from */
};

#define LIM(n, idx, min) { #n, n, idx, min }
static const struct limit_def defs[] = {
	{ LIM(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, -1, 4), N_STAGE_SSBO, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, -1, 0), N_STAGE_SSBO, GLS_VERTEX, 0, NULL },
	{ LIM(GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS, -1, 0), N_STAGE_SSBO, GLS_FRAGMENT, 0, NULL },
	{ LIM(GL_MAX_COMBINED_SHADER_STORAGE_BLOCKS, -1, 4), N_COMBINED_SSBO, 0, 0, NULL },
	{ LIM(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, -1, 4), N_BINDINGS, 0, 0, NULL },
	/* buffer sizes follow --grid; pipeline.c and curves_gl.c check each one
	 * against the real value when they allocate it */
	{ LIM(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, -1, 1 << 27), N_CONST, 0, 1 << 27,
	  "the ES 3.1 minimum (each buffer is also checked when allocated)" },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, -1, 128), N_INVOCATIONS, 0, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 0, 128), N_LOCAL, 0, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 1, 128), N_LOCAL, 1, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 2, 64), N_LOCAL, 2, 0, NULL },
	/* the one 'shared' variable, 256 bytes: the world pre-pass's float
	 * s_red[64] (tests/test_gl_limits.c checks there is no other) */
	{ LIM(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, -1, 16384), N_CONST, 0, 64 * 4, "block_bound.glsl s_red (the pre-pass's reductions)" },
	{ LIM(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, -1, 16), N_STAGE_SAMPLERS, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_VERTEX_TEXTURE_IMAGE_UNITS, -1, 16), N_STAGE_SAMPLERS, GLS_VERTEX, 0, NULL },
	{ LIM(GL_MAX_TEXTURE_IMAGE_UNITS, -1, 16), N_STAGE_SAMPLERS, GLS_FRAGMENT, 0, NULL },
	/* glActiveTexture(GL_TEXTURE0 + unit) and layout(binding = unit) */
	{ LIM(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, -1, 48), N_CONST, 0, TEX_SURFACE + 1, "abi.h TEX_SURFACE" },
	{ LIM(GL_MAX_3D_TEXTURE_SIZE, -1, 256), N_CONST, 0, NOISE_TEX_SIZE, "the 3D noise textures (noise.h)" },
	{ LIM(GL_MAX_COMPUTE_IMAGE_UNIFORMS, -1, 4), N_STAGE_IMAGES, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_IMAGE_UNITS, -1, 4), N_CONST, 0, IMG_CONVERT_OUT + 1, "abi.h IMG_CONVERT_OUT" },
	{ LIM(GL_MAX_COMPUTE_UNIFORM_BLOCKS, -1, 12), N_STAGE_UBOS, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_UNIFORM_BUFFER_BINDINGS, -1, 36), N_CONST, 0, UBIND_NOISE + 1, "abi.h UBIND_NOISE" },
	/* noise.glsl's NoiseTables: ivec4[64] + vec4[12] + ivec4, std140 */
	{ LIM(GL_MAX_UNIFORM_BLOCK_SIZE, -1, 16384), N_CONST, 0, (64 + 12 + 1) * 16, "noise.glsl NoiseTables" },
	{ LIM(GL_MAX_COMPUTE_UNIFORM_COMPONENTS, -1, 512), N_STAGE_COMPONENTS, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_VERTEX_UNIFORM_COMPONENTS, -1, 1024), N_STAGE_COMPONENTS, GLS_VERTEX, 0, NULL },
	{ LIM(GL_MAX_FRAGMENT_UNIFORM_COMPONENTS, -1, 1024), N_STAGE_COMPONENTS, GLS_FRAGMENT, 0, NULL },
	{ LIM(GL_MAX_VERTEX_ATTRIBS, -1, 16), N_ATTRIBS, 0, 0, NULL },
};
#define NDEFS (sizeof(defs) / sizeof(defs[0]))

const struct gl_limit *gl_limits_list(size_t *count)
{
	static struct gl_limit list[NDEFS];
	for (size_t i = 0; i < NDEFS; i++)
		list[i] = defs[i].l;
	*count = NDEFS;
	return list;
}

static int64_t pass_need(const struct limit_def *d, const struct gl_pass *p)
{
	switch (d->kind) {
	case N_STAGE_SSBO: return p->use[d->arg].ssbo;
	case N_COMBINED_SSBO: return p->use[GLS_COMPUTE].ssbo + p->use[GLS_VERTEX].ssbo + p->use[GLS_FRAGMENT].ssbo;
	case N_BINDINGS: return p->max_binding + 1;
	case N_STAGE_SAMPLERS: return p->use[d->arg].samplers;
	case N_STAGE_IMAGES: return p->use[d->arg].images;
	case N_STAGE_UBOS: return p->use[d->arg].ubos;
	case N_STAGE_COMPONENTS: return p->use[d->arg].components;
	case N_INVOCATIONS: return p->cs ? (int64_t)p->local[0] * p->local[1] * p->local[2] : 0;
	case N_LOCAL: return p->cs ? p->local[d->arg] : 0;
	case N_ATTRIBS: return p->attribs;
	case N_CONST: break;
	}
	return 0;
}

int64_t gl_limits_need(size_t i, const char **who)
{
	const struct limit_def *d = &defs[i];
	if (d->kind == N_CONST) {
		if (who)
			*who = d->why;
		return d->value;
	}
	int64_t need = 0;
	const char *by = "no pass";
	for (size_t k = 0; k < sizeof(passes) / sizeof(passes[0]); k++) {
		if (passes[k].tests_only)
			continue;
		int64_t n = pass_need(d, &passes[k]);
		if (n > need) {
			need = n;
			by = passes[k].name;
		}
	}
	if (who)
		*who = by;
	return need;
}

/* "NAME=VALUE[,NAME=VALUE...]" over have[]; -1 with a message on a typo. */
static int apply_override(const char *spec, int64_t *have, char *err, size_t errlen)
{
	const char *s = spec;
	while (*s) {
		size_t n = strcspn(s, ",");
		const char *eq = memchr(s, '=', n);
		if (!eq) {
			snprintf(err, errlen, "ISOTERRA_GL_LIMIT_OVERRIDE: '%.*s' is not NAME=VALUE", (int)n, s);
			return -1;
		}
		size_t k = 0;
		for (; k < NDEFS; k++) {
			char full[96];
			if (defs[k].l.index >= 0)
				snprintf(full, sizeof(full), "%s[%d]", defs[k].l.name, defs[k].l.index);
			else
				snprintf(full, sizeof(full), "%s", defs[k].l.name);
			if (strlen(full) == (size_t)(eq - s) && !strncmp(full, s, (size_t)(eq - s)))
				break;
		}
		char *end;
		errno = 0;
		long long v = strtoll(eq + 1, &end, 10);
		if (k == NDEFS || end != s + n || end == eq + 1 || errno) {
			snprintf(err, errlen, "ISOTERRA_GL_LIMIT_OVERRIDE: '%.*s' names no checked limit or has no number",
				 (int)n, s);
			return -1;
		}
		have[k] = v;
		s += n;
		if (*s == ',')
			s++;
	}
	return 0;
}

int gl_limits_check(int64_t *have_out, char *err, size_t errlen)
{
	int64_t have[NDEFS];
	while (glGetError() != GL_NO_ERROR)
		;
	for (size_t i = 0; i < NDEFS; i++) {
		GLint64 v = -1;
		if (defs[i].l.index >= 0)
			glGetInteger64i_v(defs[i].l.pname, (GLuint)defs[i].l.index, &v);
		else
			glGetInteger64v(defs[i].l.pname, &v);
		GLenum e = glGetError();
		if (e != GL_NO_ERROR) {
			snprintf(err, errlen, "querying %s failed (GL error 0x%04x): not an OpenGL ES 3.1 driver?",
				 defs[i].l.name, e);
			return -1;
		}
		have[i] = v;
	}
	const char *ov = getenv("ISOTERRA_GL_LIMIT_OVERRIDE");
	if (ov && *ov && apply_override(ov, have, err, errlen) < 0)
		return -1;
	if (have_out)
		memcpy(have_out, have, sizeof(have));
	const char *ren = (const char *)glGetString(GL_RENDERER);
	for (size_t i = 0; i < NDEFS; i++) {
		const char *who;
		int64_t need = gl_limits_need(i, &who);
		char name[96];
		if (defs[i].l.index >= 0)
			snprintf(name, sizeof(name), "%s[%d]", defs[i].l.name, defs[i].l.index);
		else
			snprintf(name, sizeof(name), "%s", defs[i].l.name);
		log_debug("GL limit %s = %" PRId64 ", needed %" PRId64 " (%s)", name, have[i], need, who);
		if (have[i] < need) {
			snprintf(err, errlen, "%s is %" PRId64 " on %s, isoterra needs %" PRId64 " (%s)", name, have[i],
				 ren ? ren : "this driver", need, who);
			return -1;
		}
	}
	return 0;
}
