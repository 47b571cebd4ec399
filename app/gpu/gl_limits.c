/* isoterra — the GL limits the program relies on: read at start, and each
 * program's needs taken from the driver's introspection when it is linked.
 * See gl_limits.h. */
#include "gl_limits.h"
#include "abi.h"
#include "convert.h" /* hal: the V4L2 conversion's defines */

#include <GLES3/gl31.h>
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core.h"

/* The passes, with the #defines that declare the most: HAS_CONTROL_MAP 1
 * (the control map's sampler) and, through carve.glsl, the curves' storage
 * block (HAS_CURVES defaults to 1). */
static const struct gl_pass passes[] = {
	/* the terrain field's programs (app/terrain/terrain.c): the density
	 * pass, and the vertex pass with ambient occlusion (its rays sample
	 * the field: + curves, noise) */
	{ "density.comp", "density.comp", NULL, NULL, "#define FIELD_PASS_DENSITY 1\n#define HAS_CONTROL_MAP 1\n", false, NULL },
	/* with the far samples' cut, and the refine variant (app/extract/pipeline.c
	 * refine_pass) */
	{ "density.comp (DENSITY_CUT)", "density.comp", NULL, NULL,
	  "#define FIELD_PASS_DENSITY 1\n#define DENSITY_CUT 1\n#define HAS_CONTROL_MAP 1\n", false, NULL },
	{ "refine_mark.comp", "refine_mark.comp", NULL, NULL, NULL, false, NULL },
	{ "density.comp (DENSITY_REFINE)", "density.comp", NULL, NULL,
	  "#define FIELD_PASS_DENSITY 1\n#define DENSITY_REFINE 1\n#define HAS_CONTROL_MAP 1\n", false, NULL },
	/* the streaming world's coarse pre-pass (shaders/block_bound.glsl) */
	{ "density.comp (FIELD_PASS_BOUND)", "density.comp", NULL, NULL,
	  "#define FIELD_PASS_BOUND 1\n#define HAS_CONTROL_MAP 1\n", false, NULL },
	{ "mc_debris.comp", "mc_debris.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_debris.comp (DEBRIS_NEAR)", "mc_debris.comp", NULL, NULL, "#define DEBRIS_NEAR 1\n", false, NULL },
	{ "mc_debris_flood.comp", "mc_debris_flood.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_classify.comp", "mc_classify.comp", NULL, NULL, NULL, false, NULL },
	{ "hp_reduce.comp", "hp_reduce.comp", NULL, NULL, NULL, false, NULL },
	{ "hp_downsweep.comp", "hp_downsweep.comp", NULL, NULL, NULL, false, NULL },
	{ "hp_top.comp", "hp_top.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_setup.comp", "mc_setup.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_vertices.comp", "mc_vertices.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_vertices.comp (WITH_AO, WITH_SUN)", "density.comp", NULL, NULL,
	  "#define FIELD_PASS_VERTICES 1\n#define WITH_AO 1\n#define WITH_SUN 1\n#define AO_FAR_OUTSIDE 1\n#define HAS_CONTROL_MAP 1\n",
	  false, NULL },
	{ "mc_indices.comp", "mc_indices.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_atomic.comp", "mc_atomic.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_nocompact.comp", "mc_nocompact.comp", NULL, NULL, NULL, false, NULL },
	{ "mc_finish.comp", "mc_finish.comp", NULL, NULL, NULL, false, NULL },
	/* the curves' displacement map over a heightmap */
	{ "curve_bake.comp (BAKE_HEIGHTMAP)", "curve_bake.comp", NULL, NULL, "#define BAKE_HEIGHTMAP 1\n", false, NULL },
	/* V4L2 output: the frame sampled, the device's layout stored */
	{ "v4l2_convert.comp", "v4l2_convert.comp", NULL, NULL, NULL, false, conv_shader_defines_yuyv },
	{ "render.vert + render.frag", NULL, "render.vert", "render.frag", "#define DETAIL_NORMALS 1\n", false, NULL },
	/* the volume's depth pre-pass on a software rasterizer (render.c) */
	{ "render.vert + depth.frag", NULL, "render.vert", "depth.frag", NULL, false, NULL },
	{ "water.vert + water.frag", NULL, "water.vert", "water.frag", NULL, false, NULL },
	{ "sky.vert + sky.frag", NULL, "sky.vert", "sky.frag", NULL, false, NULL },
	{ "osd.vert + osd.frag", NULL, "osd.vert", "osd.frag", NULL, false, NULL },
	/* a mesh's draw command split into parts on a software rasterizer */
	{ "draw_parts.comp", "draw_parts.comp", NULL, NULL, NULL, false, NULL },
	/* the governor's upscale, and edge smoothing (--antialias fxaa) */
	{ "upscale.vert + upscale.frag", NULL, "upscale.vert", "upscale.frag", NULL, false, NULL },
	{ "upscale.vert + fxaa.frag", NULL, "upscale.vert", "fxaa.frag", NULL, false, NULL },
	/* the attract playlist's crossfade (renderer_fade_kept) */
	{ "upscale.vert + fade.frag", NULL, "upscale.vert", "fade.frag", NULL, false, NULL },
	/* a rotated panel (--rotate: renderer_blit_to_default) */
	{ "upscale.vert + rotate.frag", NULL, "upscale.vert", "rotate.frag", NULL, false, NULL },
	/* the tests' own passes */
	{ "hp_test.comp", "hp_test.comp", NULL, NULL, NULL, true, NULL },
	{ "curve_test.comp", "curve_test.comp", NULL, NULL, NULL, true, NULL },
};

const struct gl_pass *gl_limits_passes(size_t *count)
{
	*count = sizeof(passes) / sizeof(passes[0]);
	return passes;
}

enum need_kind {
	N_STAGE_SSBO, N_COMBINED_SSBO, N_BINDINGS, N_STAGE_SAMPLERS, N_STAGE_IMAGES, N_STAGE_UBOS,
	N_STAGE_COMPONENTS, N_INVOCATIONS, N_LOCAL, N_ATTRIBS, N_UNITS, N_IMAGE_UNITS, N_UBO_BINDINGS, N_UBO_BYTES,
	N_CONST,
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
	/* every program's bindings are below BIND_POINTS (tests/test_gl_limits.c) */
	{ LIM(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, -1, 4), N_BINDINGS, 0, 0, NULL },
	/* buffer sizes follow --grid; pipeline.c and curves_gl.c check each one
	 * against the real value when they allocate it */
	{ LIM(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, -1, 1 << 27), N_CONST, 0, 1 << 27,
	  "the ES 3.1 minimum (each buffer is also checked when allocated)" },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS, -1, 128), N_INVOCATIONS, 0, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 0, 128), N_LOCAL, 0, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 1, 128), N_LOCAL, 1, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_WORK_GROUP_SIZE, 2, 64), N_LOCAL, 2, 0, NULL },
	/* the one 'shared' variable, WG_SIZE floats: the world pre-pass's
	 * s_red (tests/test_gl_limits.c checks there is no other) */
	{ LIM(GL_MAX_COMPUTE_SHARED_MEMORY_SIZE, -1, 16384), N_CONST, 0, WG_SIZE * 4, "block_bound.glsl s_red (the pre-pass's reductions)" },
	{ LIM(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, -1, 16), N_STAGE_SAMPLERS, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_VERTEX_TEXTURE_IMAGE_UNITS, -1, 16), N_STAGE_SAMPLERS, GLS_VERTEX, 0, NULL },
	{ LIM(GL_MAX_TEXTURE_IMAGE_UNITS, -1, 16), N_STAGE_SAMPLERS, GLS_FRAGMENT, 0, NULL },
	/* glActiveTexture(GL_TEXTURE0 + unit) and layout(binding = unit) */
	{ LIM(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, -1, 48), N_UNITS, 0, 0, NULL },
	{ LIM(GL_MAX_3D_TEXTURE_SIZE, -1, 256), N_CONST, 0, NOISE_TEX_SIZE, "the 3D noise textures (abi.h NOISE_TEX_SIZE)" },
	{ LIM(GL_MAX_COMPUTE_IMAGE_UNIFORMS, -1, 4), N_STAGE_IMAGES, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_IMAGE_UNITS, -1, 4), N_IMAGE_UNITS, 0, 0, NULL },
	{ LIM(GL_MAX_COMPUTE_UNIFORM_BLOCKS, -1, 12), N_STAGE_UBOS, GLS_COMPUTE, 0, NULL },
	{ LIM(GL_MAX_UNIFORM_BUFFER_BINDINGS, -1, 36), N_UBO_BINDINGS, 0, 0, NULL },
	{ LIM(GL_MAX_UNIFORM_BLOCK_SIZE, -1, 16384), N_UBO_BYTES, 0, 0, NULL },
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

/* The limits as read (and overridden) by gl_limits_check, and the largest
 * need of each seen so far, with the program behind it. */
static struct {
	bool have_set;
	int64_t have[NDEFS];
	int64_t need[NDEFS];
	char who[NDEFS][96];
} st;

static int64_t use_need(const struct limit_def *d, const struct gl_use *u, bool compute)
{
	switch (d->kind) {
	case N_STAGE_SSBO: return u->use[d->arg].ssbo;
	case N_COMBINED_SSBO: return u->ssbo_total;
	case N_BINDINGS: return u->max_binding + 1;
	case N_STAGE_SAMPLERS: return u->use[d->arg].samplers;
	case N_STAGE_IMAGES: return u->use[d->arg].images;
	case N_STAGE_UBOS: return u->use[d->arg].ubos;
	case N_STAGE_COMPONENTS: return u->use[d->arg].components;
	case N_INVOCATIONS: return compute ? (int64_t)u->local[0] * u->local[1] * u->local[2] : 0;
	case N_LOCAL: return compute ? u->local[d->arg] : 0;
	case N_ATTRIBS: return u->attribs;
	case N_UNITS: return u->max_unit + 1;
	case N_IMAGE_UNITS: return u->max_image_unit + 1;
	case N_UBO_BINDINGS: return u->max_ubo_binding + 1;
	case N_UBO_BYTES: return u->ubo_bytes;
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
	if (who)
		*who = st.need[i] > 0 ? st.who[i] : "no program checked";
	return st.need[i];
}

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

void gl_limits_introspect(unsigned prog, bool compute, struct gl_use *out)
{
	memset(out, 0, sizeof(*out));
	out->max_binding = out->max_ubo_binding = out->max_unit = out->max_image_unit = -1;
	GLint n = 0;
	glGetProgramInterfaceiv(prog, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &n);
	for (GLint i = 0; i < n; i++) {
		GLenum props[4] = { GL_BUFFER_BINDING, referenced[0], referenced[1], referenced[2] };
		GLint v[4] = { 0, 0, 0, 0 };
		glGetProgramResourceiv(prog, GL_SHADER_STORAGE_BLOCK, (GLuint)i, 4, props, 4, NULL, v);
		if (v[0] > out->max_binding)
			out->max_binding = v[0];
		out->ssbo_total++;
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
		GLenum props[5] = { GL_BUFFER_BINDING, GL_BUFFER_DATA_SIZE, referenced[0], referenced[1], referenced[2] };
		GLint v[5] = { 0, 0, 0, 0, 0 };
		glGetProgramResourceiv(prog, GL_UNIFORM_BLOCK, (GLuint)i, 5, props, 5, NULL, v);
		if (v[0] > out->max_ubo_binding)
			out->max_ubo_binding = v[0];
		if (v[1] > out->ubo_bytes)
			out->ubo_bytes = v[1];
		if (compute)
			out->use[GLS_COMPUTE].ubos++;
		else
			for (int s = GLS_VERTEX; s < GLS_COUNT; s++)
				out->use[s].ubos += v[2 + s] != 0;
	}
	glGetProgramInterfaceiv(prog, GL_UNIFORM, GL_ACTIVE_RESOURCES, &n);
	for (GLint i = 0; i < n; i++) {
		GLenum props[7] = { GL_TYPE, GL_ARRAY_SIZE, GL_BLOCK_INDEX, GL_LOCATION,
				    referenced[0], referenced[1], referenced[2] };
		GLint v[7] = { 0, 0, 0, -1, 0, 0, 0 };
		glGetProgramResourceiv(prog, GL_UNIFORM, (GLuint)i, 7, props, 7, NULL, v);
		if (v[2] != -1)
			continue; /* a member of a uniform block */
		int comps = type_components((GLenum)v[0]);
		if (comps <= 0 && v[3] >= 0) { /* the unit an opaque uniform is set to (layout(binding)) */
			for (GLint k = 0; k < v[1]; k++) {
				GLint unit = -1;
				glGetUniformiv(prog, v[3] + k, &unit);
				int *mx = is_image((GLenum)v[0]) ? &out->max_image_unit : &out->max_unit;
				if (unit > *mx)
					*mx = unit;
			}
		}
		for (int s = 0; s < GLS_COUNT; s++) {
			/* a compute program's uniforms are the compute shader's */
			if (compute ? s != GLS_COMPUTE : (s == GLS_COMPUTE || !v[4 + s]))
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

static void limit_name(size_t i, char *name, size_t len)
{
	if (defs[i].l.index >= 0)
		snprintf(name, len, "%s[%d]", defs[i].l.name, defs[i].l.index);
	else
		snprintf(name, len, "%s", defs[i].l.name);
}

int gl_limits_check_program(unsigned prog, bool compute, const char *what, char *err, size_t errlen)
{
	struct gl_use u;
	gl_limits_introspect(prog, compute, &u);
	GLenum e = glGetError();
	if (e != GL_NO_ERROR) {
		snprintf(err, errlen, "%s: program introspection failed (GL error 0x%04x)", what, e);
		return -1;
	}
	log_debug("%s uses: %d storage blocks (highest binding %d), %d/%d/%d samplers, %d images, %d/%d/%d uniform "
		  "blocks, %d/%d/%d uniform components, local size %dx%dx%d, %d attributes",
		  what, u.ssbo_total, u.max_binding, u.use[0].samplers, u.use[1].samplers, u.use[2].samplers,
		  u.use[0].images, u.use[0].ubos, u.use[1].ubos, u.use[2].ubos, u.use[0].components,
		  u.use[1].components, u.use[2].components, u.local[0], u.local[1], u.local[2], u.attribs);
	for (size_t i = 0; i < NDEFS; i++) {
		if (defs[i].kind == N_CONST)
			continue;
		int64_t need = use_need(&defs[i], &u, compute);
		if (need > st.need[i]) {
			st.need[i] = need;
			snprintf(st.who[i], sizeof(st.who[i]), "%s", what);
		}
		if (st.have_set && st.have[i] < need) {
			char name[96];
			limit_name(i, name, sizeof(name));
			const char *ren = (const char *)glGetString(GL_RENDERER);
			snprintf(err, errlen, "%s is %" PRId64 " on %s, isoterra needs %" PRId64 " (%s)", name, st.have[i],
				 ren ? ren : "this driver", need, what);
			return -1;
		}
	}
	return 0;
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
	memcpy(st.have, have, sizeof(have));
	st.have_set = true;
	const char *ren = (const char *)glGetString(GL_RENDERER);
	for (size_t i = 0; i < NDEFS; i++) {
		char name[96];
		limit_name(i, name, sizeof(name));
		if (defs[i].kind != N_CONST) {
			log_debug("GL limit %s = %" PRId64 " (each program's need is checked when it is linked)", name,
				  have[i]);
			continue;
		}
		log_debug("GL limit %s = %" PRId64 ", needed %" PRId64 " (%s)", name, have[i], defs[i].value, defs[i].why);
		if (have[i] < defs[i].value) {
			snprintf(err, errlen, "%s is %" PRId64 " on %s, isoterra needs %" PRId64 " (%s)", name, have[i],
				 ren ? ren : "this driver", defs[i].value, defs[i].why);
			return -1;
		}
	}
	return 0;
}
