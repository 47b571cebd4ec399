/* isoterra — GL side of the terrain edits: the curve hash in one SSBO of
 * four sections (BIND_CURVES: pivot, index, ctrl, prm), the heightmap as an R32F texture
 * (TEX_HEIGHTMAP), the control map likewise (TEX_CONTROL), the
 * displacement-map bake, the road map (the same bake, BAKE_MATERIAL) and
 * the shader test hook.
 * The GL objects belong to one edit state (struct edits_gl). */
#include "edits.h"
#include "core.h"
#include "gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct edits_gl {
	bool ready;
	GLuint buf;              /* the curve hash: sections pivot, index, ctrl, prm */
	GLsizeiptr cap;          /* its explicit capacity (bytes) */
	int32_t sect[4];         /* the sections' starts, in 16-byte units (curves.glsl u_curve_sect) */
	unsigned curves_gen;
	GLuint hm_tex, control_tex;
	unsigned hm_gen, control_gen;
	bool hm_ready, control_ready;
	GLuint p_bake[8], p_test;     /* bake: [iterative | dense << 1 | heightmap << 2] */
	GLuint p_material, road_tex;  /* the road map's bake and texture */
	struct road_map road;
	unsigned road_gen;
	bool road_ready;
	GLuint b_bake, b_zero, b_tiles, b_in, b_out;
	GLsizeiptr bake_cap, zero_cap, tiles_cap, in_cap, out_cap;
};

/* The edit state's GL side, made on first use; NULL when out of memory. */
static struct edits_gl *gl_of(struct edits *ed, char *err, size_t errlen)
{
	if (!ed->gl && !(ed->gl = calloc(1, sizeof(*ed->gl))))
		snprintf(err, errlen, "out of memory");
	return ed->gl;
}

void edits_gl_release(struct edits *ed)
{
	struct edits_gl *G = ed->gl;
	if (!G)
		return;
	if (G->ready)
		glDeleteBuffers(1, &G->buf);
	if (G->hm_tex)
		glDeleteTextures(1, &G->hm_tex);
	if (G->control_tex)
		glDeleteTextures(1, &G->control_tex);
	for (int i = 0; i < 8; i++)
		if (G->p_bake[i])
			glDeleteProgram(G->p_bake[i]);
	if (G->p_test)
		glDeleteProgram(G->p_test);
	if (G->p_material)
		glDeleteProgram(G->p_material);
	if (G->road_tex)
		glDeleteTextures(1, &G->road_tex);
	GLuint bufs[5] = { G->b_bake, G->b_zero, G->b_tiles, G->b_in, G->b_out };
	for (int i = 0; i < 5; i++)
		if (bufs[i])
			glDeleteBuffers(1, &bufs[i]);
	free(G);
	ed->gl = NULL;
}

/* The curve hash into one buffer: its four sections (pivot, index, ctrl,
 * prm) each start on 16 bytes; the buffer is reallocated when it must grow
 * or would waste three quarters. */
static int upload_curves(struct edits_gl *G, const struct edits *e, char *err, size_t errlen)
{
	if (!G->ready) {
		glGenBuffers(1, &G->buf);
		G->cap = 0;
		G->ready = true;
		G->curves_gen = e->curves_gen - 1;
	}
	if (G->curves_gen == e->curves_gen)
		return 0;
	const struct curve_hash *h = &e->hash;
	const struct curve_quads *q = &e->quads;
	bool any = q->nquads > 0 && h->pivot;
	const void *data[4] = { h->pivot, h->index, q->ctrl, q->prm };
	GLsizeiptr bytes[4] = { 0, 0, 0, 0 };
	if (any) {
		bytes[0] = (GLsizeiptr)h->dim * h->dim * 8;
		bytes[1] = (GLsizeiptr)(h->nindex + h->nall) * 4;
		bytes[2] = bytes[3] = (GLsizeiptr)q->nctrl * 16;
	}
	GLsizeiptr want = 0;
	for (int i = 0; i < 4; i++) {
		G->sect[i] = (int32_t)(want / 16);
		want += (bytes[i] + 15) / 16 * 16;
	}
	want = want > 16 ? want : 16;
	GLint max_ssbo = 0;
	glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_ssbo);
	if ((max_ssbo > 0 && want > max_ssbo) || want / 16 > INT32_MAX) {
		snprintf(err, errlen, "curves: the hash's %lld bytes exceed the GL storage block limit (%d)",
			 (long long)want, max_ssbo);
		return -1;
	}
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, G->buf);
	if (want > G->cap || want < G->cap / 4) {
		glBufferData(GL_SHADER_STORAGE_BUFFER, want, NULL, GL_STATIC_DRAW);
		G->cap = want;
	}
	for (int i = 0; i < 4; i++)
		if (bytes[i] > 0)
			glBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)G->sect[i] * 16, bytes[i], data[i]);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	if (gpu_check("curve hash") < 0) {
		snprintf(err, errlen, "curves: uploading the hash's %lld bytes failed", (long long)want);
		return -1;
	}
	G->curves_gen = e->curves_gen;
	return 0;
}

/* *tex made again: a w x h texture of one level of fmt on unit `unit`,
 * clamped at its edges, filtered by `filter`, left bound there for its
 * upload.  Returns the active texture unit before, for the caller to
 * restore. */
static GLint new_texture(GLuint *tex, int unit, GLenum fmt, int w, int h, GLint filter)
{
	if (*tex)
		glDeleteTextures(1, tex);
	glGenTextures(1, tex);
	GLint prev = 0;
	glGetIntegerv(GL_ACTIVE_TEXTURE, &prev);
	glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
	glBindTexture(GL_TEXTURE_2D, *tex);
	gpu_texture_2d_storage(fmt, w, h, filter);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
	return prev;
}

/* A map of samples (heightmap, control map) as an R32F texture on unit
 * `unit` (a 1x1 zero texture when there is none). */
static int upload_map(GLuint *tex, const struct heightmap *m, int unit, const char *what, char *err, size_t errlen)
{
	int w = m->w ? m->w : 1, hh = m->w ? m->h : 1;
	GLint max_tex = 0;
	glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
	if (max_tex > 0 && (w > max_tex || hh > max_tex)) {
		snprintf(err, errlen, "%s of %dx%d samples exceeds the GL texture limit (%d)", what, w, hh, max_tex);
		return -1;
	}
	static const float zero = 0.0f;
	/* R32F is not filterable in ES: texelFetch only, and NEAREST keeps the
	 * texture complete */
	GLint prev = new_texture(tex, unit, GL_R32F, w, hh, GL_NEAREST);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, hh, GL_RED, GL_FLOAT, m->w ? (const void *)m->v : &zero);
	glActiveTexture((GLenum)prev);
	return gpu_check(what);
}

static int upload_heightmap(struct edits_gl *G, const struct edits *e, char *err, size_t errlen)
{
	if (!(G->hm_ready && G->hm_gen == e->hm_gen)) {
		if (upload_map(&G->hm_tex, &e->hm, TEX_HEIGHTMAP, "heightmap", err, errlen) < 0)
			return -1;
		G->hm_gen = e->hm_gen;
		G->hm_ready = true;
	}
	if (!(G->control_ready && G->control_gen == e->control_gen)) {
		if (upload_map(&G->control_tex, &e->control, TEX_CONTROL, "control map", err, errlen) < 0)
			return -1;
		G->control_gen = e->control_gen;
		G->control_ready = true;
	}
	return 0;
}

static void set_uniforms(GLuint prog, const struct edits *e, const int32_t sect[4])
{
	const struct curve_hash *h = &e->hash;
	bool any = e->quads.nquads > 0 && h->pivot;
	GLint l;
	if ((l = gpu_uniform(prog, "u_curve_sect")) >= 0)
		glProgramUniform4i(prog, l, sect[0], sect[1], sect[2], sect[3]);
	if ((l = gpu_uniform(prog, "u_curve_count")) >= 0)
		glProgramUniform1i(prog, l, any ? e->quads.nquads : 0);
	if ((l = gpu_uniform(prog, "u_curve_all_offset")) >= 0)
		glProgramUniform1i(prog, l, any ? h->all_offset : 0);
	if ((l = gpu_uniform(prog, "u_curve_hash_dim")) >= 0)
		glProgramUniform2i(prog, l, any ? h->dim : 1, any ? h->dim : 1);
	if ((l = gpu_uniform(prog, "u_curve_hash_origin")) >= 0)
		glProgramUniform2f(prog, l, h->origin[0], h->origin[1]);
	if ((l = gpu_uniform(prog, "u_curve_hash_size")) >= 0)
		glProgramUniform2f(prog, l, h->size[0], h->size[1]);
	if ((l = gpu_uniform(prog, "u_curve_hash_cell")) >= 0)
		glProgramUniform2f(prog, l, any ? h->cell[0] : 1.0f, any ? h->cell[1] : 1.0f);
	if ((l = gpu_uniform(prog, "u_heightmap_size")) >= 0)
		glProgramUniform2i(prog, l, e->hm.w, e->hm.h);
	if ((l = gpu_uniform(prog, "u_control_size")) >= 0)
		glProgramUniform2i(prog, l, e->control.w, e->control.h);
}

int edits_gl_bind(struct edits *ed, GLuint prog, const struct params *p, char *err, size_t errlen)
{
	if (edits_load(ed, p, err, errlen) < 0)
		return -1;
	struct edits_gl *G = gl_of(ed, err, errlen);
	if (!G || upload_curves(G, ed, err, errlen) < 0 || upload_heightmap(G, ed, err, errlen) < 0)
		return -1;
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_CURVES, G->buf);
	GLint prev = 0;
	glGetIntegerv(GL_ACTIVE_TEXTURE, &prev);
	glActiveTexture(GL_TEXTURE0 + TEX_HEIGHTMAP);
	glBindTexture(GL_TEXTURE_2D, G->hm_tex);
	glActiveTexture(GL_TEXTURE0 + TEX_CONTROL);
	glBindTexture(GL_TEXTURE_2D, G->control_tex);
	glActiveTexture((GLenum)prev);
	set_uniforms(prog, ed, G->sect);
	return gpu_check("curve/heightmap bind");
}

static int ensure(GLuint *b, GLsizeiptr *cap, GLsizeiptr size)
{
	if (!*b)
		glGenBuffers(1, b);
	if (size <= *cap)
		return 0;
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, *b);
	glBufferData(GL_SHADER_STORAGE_BUFFER, size, NULL, GL_DYNAMIC_COPY);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	if (gpu_check("curve scratch buffer") < 0)
		return -1;
	*cap = size;
	return 0;
}

/* The 8x8 tiles of the map that some quadratic can reach, as (tx | ty <<
 * 16): a tile inside a quadratic's padded box is taken when its centre is
 * within w/2 + λ + the tile's half diagonal + one texel (+ a rounding
 * margin) of the curve (CPU closed form, carve_ref_closest).  A texel no
 * curve reaches has Θ = 0 everywhere, so the zeroed map is already right
 * there.  Returns the count or -1. */
static int bake_tiles(const struct curve_quads *q, const struct bake_opts *o, uint32_t **out)
{
	int tx = (o->res[0] + 7) / 8, tz = (o->res[1] + 7) / 8;
	uint8_t *mark = calloc((size_t)tx * (size_t)tz, 1);
	if (!mark)
		return -1;
	float tw = o->size[0] / (float)o->res[0], th = o->size[1] / (float)o->res[1];
	int n = 0;
	for (int k = 0; k < q->nquads; k++) {
		float box[4];
		curve_hash_padded_box(q, k, box);
		if (box[2] < o->origin[0] || box[0] > o->origin[0] + o->size[0] || box[3] < o->origin[1] ||
		    box[1] > o->origin[1] + o->size[1])
			continue;
		float i0f = floorf((box[0] - o->origin[0]) / tw) - 1, i1f = ceilf((box[2] - o->origin[0]) / tw) + 1;
		float j0f = floorf((box[1] - o->origin[1]) / th) - 1, j1f = ceilf((box[3] - o->origin[1]) / th) + 1;
		int i0 = i0f < 0 ? 0 : (int)i0f, j0 = j0f < 0 ? 0 : (int)j0f;
		int i1 = i1f > (float)o->res[0] ? o->res[0] : (int)i1f;
		int j1 = j1f > (float)o->res[1] ? o->res[1] : (int)j1f;
		float c[3][4];
		curve_quads_get(q, k, c);
		float span = fmaxf(fmaxf(fabsf(box[0]), fabsf(box[2])), fmaxf(fabsf(box[1]), fabsf(box[3])));
		float reach = q->prm[q->first[k]][0] + q->prm[q->first[k]][1] + 4.0f * hypotf(tw, th) + 1e-4f * span;
		for (int j = j0 / 8; j1 > j0 && j <= (j1 - 1) / 8; j++)
			for (int i = i0 / 8; i1 > i0 && i <= (i1 - 1) / 8; i++) {
				if (mark[(size_t)j * (size_t)tx + (size_t)i])
					continue;
				float ctr[2] = { o->origin[0] + ((float)i * 8.0f + 4.0f) * tw,
						 o->origin[1] + ((float)j * 8.0f + 4.0f) * th };
				float cl[4];
				carve_ref_closest(c, ctr, cl);
				if (fabsf(cl[0]) > reach + hypotf(tw, th))
					continue;
				mark[(size_t)j * (size_t)tx + (size_t)i] = 1;
				n++;
			}
	}
	*out = malloc(sizeof(uint32_t) * (size_t)(n ? n : 1));
	if (!*out) {
		free(mark);
		return -1;
	}
	int k = 0;
	for (int j = 0; j < tz; j++)
		for (int i = 0; i < tx; i++)
			if (mark[(size_t)j * (size_t)tx + (size_t)i])
				(*out)[k++] = (uint32_t)i | ((uint32_t)j << 16);
	free(mark);
	return n;
}

/* The bake program for these options (compiled on first use). */
static GLuint bake_program(struct edits_gl *G, const struct bake_opts *o, bool hm, char *err, size_t errlen)
{
	bool dense = o->dense || o->iterative;
	GLuint *prog = &G->p_bake[(o->iterative ? 1 : 0) | (dense ? 2 : 0) | (hm ? 4 : 0)];
	if (!*prog) {
		char defs[128];
		snprintf(defs, sizeof(defs), "%s%s%s", o->iterative ? "#define CURVE_ITERATIVE 1\n" : "",
			 dense ? "#define BAKE_DENSE 1\n" : "", hm ? "#define BAKE_HEIGHTMAP 1\n" : "");
		*prog = gpu_compute_program("curve_bake.comp", defs, err, errlen);
	}
	return *prog;
}

/* Zeroes the first bytes of the map (a GPU copy from a zero buffer). */
static int bake_zero(struct edits_gl *G, GLsizeiptr bytes, char *err, size_t errlen)
{
	if (G->zero_cap < bytes) {
		void *z = calloc(1, (size_t)bytes);
		if (!z) {
			snprintf(err, errlen, "out of memory");
			return -1;
		}
		if (!G->b_zero)
			glGenBuffers(1, &G->b_zero);
		glBindBuffer(GL_COPY_READ_BUFFER, G->b_zero);
		glBufferData(GL_COPY_READ_BUFFER, bytes, z, GL_STATIC_DRAW);
		glBindBuffer(GL_COPY_READ_BUFFER, 0);
		free(z);
		G->zero_cap = bytes;
	}
	glBindBuffer(GL_COPY_READ_BUFFER, G->b_zero);
	glBindBuffer(GL_COPY_WRITE_BUFFER, G->b_bake);
	glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, bytes);
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
	return 0;
}

/* The tiled bake: the map zeroed, then one work group per listed tile. */
static int bake_tiled(struct edits_gl *G, const struct edits *e, GLuint prog, const struct bake_opts *o,
		      GLsizeiptr bytes, char *err, size_t errlen)
{
	if (bake_zero(G, bytes, err, errlen) < 0)
		return -1;
	uint32_t *tiles = NULL;
	int nt = bake_tiles(&e->quads, o, &tiles);
	if (nt < 0) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	if (nt > 0) {
		if (ensure(&G->b_tiles, &G->tiles_cap, (GLsizeiptr)nt * 4) < 0) {
			free(tiles);
			snprintf(err, errlen, "cannot allocate the tile list");
			return -1;
		}
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, G->b_tiles);
		glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)nt * 4, tiles);
		glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
		int gx = nt < 65535 ? nt : 65535, gy = (nt + gx - 1) / gx;
		glProgramUniform1i(prog, gpu_uniform(prog, "u_bake_ntiles"), nt);
		glProgramUniform1i(prog, gpu_uniform(prog, "u_bake_groups_x"), gx);
		glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_IN, G->b_tiles);
		glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
		glDispatchCompute((GLuint)gx, (GLuint)gy, 1);
	}
	free(tiles);
	return 0;
}

/* Room for the map: bytes within the GL limit, the buffer allocated. */
static int bake_room(struct edits_gl *G, const struct bake_opts *o, GLsizeiptr bytes, char *err, size_t errlen)
{
	GLint max_ssbo = 0;
	glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_ssbo);
	if (max_ssbo > 0 && bytes > max_ssbo) {
		snprintf(err, errlen, "a %dx%d displacement map exceeds the GL storage block limit", o->res[0], o->res[1]);
		return -1;
	}
	if (ensure(&G->b_bake, &G->bake_cap, bytes) < 0) {
		snprintf(err, errlen, "cannot allocate the displacement map");
		return -1;
	}
	return 0;
}

int curves_bake(struct edits *ed, const struct params *p, const struct bake_opts *o, float *out, char *err,
		size_t errlen)
{
	if (errlen)
		err[0] = '\0';
	if (o->res[0] < 1 || o->res[1] < 1 || o->res[0] > 16384 || o->res[1] > 16384) {
		snprintf(err, errlen, "bake resolution %dx%d out of range", o->res[0], o->res[1]);
		return -1;
	}
	if (edits_load(ed, p, err, errlen) < 0)
		return -1;
	struct edits_gl *G = gl_of(ed, err, errlen);
	GLuint prog = G ? bake_program(G, o, ed->hm.w > 0, err, errlen) : 0;
	GLsizeiptr bytes = (GLsizeiptr)o->res[0] * o->res[1] * 4;
	if (!prog || bake_room(G, o, bytes, err, errlen) < 0)
		return -1;
	if (edits_gl_bind(ed, prog, p, err, errlen) < 0) {
		if (!err[0])
			snprintf(err, errlen, "curves/heightmap could not be bound (see the log)");
		return -1;
	}
	gpu_set_param_uniforms(prog, p);
	glProgramUniform2i(prog, gpu_uniform(prog, "u_bake_res"), o->res[0], o->res[1]);
	glProgramUniform2f(prog, gpu_uniform(prog, "u_bake_origin"), o->origin[0], o->origin[1]);
	glProgramUniform2f(prog, gpu_uniform(prog, "u_bake_texel"), o->size[0] / (float)o->res[0],
			   o->size[1] / (float)o->res[1]);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, G->b_bake);
	glUseProgram(prog);
	if (o->dense || o->iterative) {
		glDispatchCompute((GLuint)(o->res[0] + 7) / 8, (GLuint)(o->res[1] + 7) / 8, 1);
	} else if (bake_tiled(G, ed, prog, o, bytes, err, errlen) < 0) {
		glUseProgram(0);
		return -1;
	}
	glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
	glUseProgram(0);
	if (gpu_check("curve bake") < 0) {
		snprintf(err, errlen, "the displacement-map bake failed (GL error)");
		return -1;
	}
	if (out && gpu_read_buffer(G->b_bake, 0, bytes, out) < 0) {
		snprintf(err, errlen, "reading the displacement map back failed");
		return -1;
	}
	return 0;
}

/* The most texels of the road map: 8 MB of half floats, and as much again
 * in the bake's buffer while it is made. */
#define ROAD_MAP_MAX_TEXELS (1L << 20)

int edits_road_map(struct edits *ed, const struct params *p, struct road_map *out, char *err, size_t errlen)
{
	memset(out, 0, sizeof(*out));
	if (errlen)
		err[0] = '\0';
	struct edits_gl *G = gl_of(ed, err, errlen);
	if (!G)
		return -1;
	if (G->road_ready && G->road_gen == ed->curves_gen) {
		*out = G->road;
		return 0;
	}
	const struct curve_quads *q = &ed->quads;
	float hw_min = INFINITY;
	double ysum = 0.0;
	int nsurf = 0;
	for (int k = 0; k < q->nquads; k++) {
		const float *prm = q->prm[q->first[k]];
		if (prm[3] == 0.0f)
			continue;
		hw_min = fminf(hw_min, prm[0]);
		ysum += q->ctrl[q->first[k]][1];
		nsurf++;
	}
	G->road_ready = true;
	G->road_gen = ed->curves_gen;
	memset(&G->road, 0, sizeof(G->road));
	if (nsurf == 0 || !ed->hash.pivot)
		return 0;
	/* over the hash's rectangle (every padded box), a texel a third of the
	 * narrowest half width, coarser when that would exceed the texel
	 * budget or the GL's texture size */
	GLint max_tex = 2048;
	glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
	const float *size = ed->hash.size;
	double texel = fmax(hw_min / 3.0, sqrt((double)size[0] * size[1] / (double)ROAD_MAP_MAX_TEXELS));
	texel = fmax(texel, fmax(size[0], size[1]) / (double)max_tex);
	int w = (int)ceil(size[0] / texel), h = (int)ceil(size[1] / texel);
	w = w < 1 ? 1 : w > max_tex ? max_tex : w;
	h = h < 1 ? 1 : h > max_tex ? max_tex : h;
	struct bake_opts o = { { w, h }, { ed->hash.origin[0], ed->hash.origin[1] }, { size[0], size[1] }, false, false };
	if (!G->p_material &&
	    !(G->p_material = gpu_compute_program("curve_bake.comp", "#define BAKE_MATERIAL 1\n", err, errlen)))
		return -1;
	GLuint prog = G->p_material;
	GLsizeiptr bytes = (GLsizeiptr)w * h * 8;
	if (bake_room(G, &o, bytes, err, errlen) < 0)
		return -1;
	if (edits_gl_bind(ed, prog, p, err, errlen) < 0) {
		if (!err[0])
			snprintf(err, errlen, "curves could not be bound for the road map (see the log)");
		return -1;
	}
	float y0 = (float)(ysum / nsurf);
	double t0 = clock_ms();
	gpu_set_param_uniforms(prog, p);
	glProgramUniform2i(prog, gpu_uniform(prog, "u_bake_res"), w, h);
	glProgramUniform2f(prog, gpu_uniform(prog, "u_bake_origin"), o.origin[0], o.origin[1]);
	glProgramUniform2f(prog, gpu_uniform(prog, "u_bake_texel"), size[0] / (float)w, size[1] / (float)h);
	glProgramUniform1f(prog, gpu_uniform(prog, "u_bake_y0"), y0);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, G->b_bake);
	glUseProgram(prog);
	if (bake_tiled(G, ed, prog, &o, bytes, err, errlen) < 0) {
		glUseProgram(0);
		return -1;
	}
	glUseProgram(0);
	glMemoryBarrier(GL_PIXEL_BUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
	GLint prev = new_texture(&G->road_tex, TEX_ROADS, GL_RGBA16F, w, h, GL_LINEAR);
	glBindBuffer(GL_PIXEL_UNPACK_BUFFER, G->b_bake);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_HALF_FLOAT, (const void *)0);
	glBindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
	glActiveTexture((GLenum)prev);
	/* the bake's map and its zeros (as large as the texture) are not kept:
	 * boards share their memory with the CPU (the GL keeps them until the
	 * copy is done) */
	GLuint scratch[2] = { G->b_bake, G->b_zero };
	glDeleteBuffers(2, scratch);
	G->b_bake = G->b_zero = 0;
	G->bake_cap = G->zero_cap = 0;
	if (gpu_check("road map") < 0) {
		snprintf(err, errlen, "the %dx%d road map could not be made (GL error)", w, h);
		return -1;
	}
	G->road = (struct road_map){ G->road_tex, { o.origin[0], o.origin[1] }, { size[0], size[1] }, y0,
				     (float)fmax(0.75, 1.5 * texel) };
	glFinish(); /* once per change of the curves: the time is the log's */
	log_info("road map: %dx%d texels of %.3g world units over %d curve pieces with a surface, baked in %.1f ms", w,
		 h, texel, nsurf, clock_ms() - t0);
	*out = G->road;
	return 0;
}

int curves_gpu_test(struct edits *ed, const struct params *p, int mode, const float *in, int n, float *out, char *err,
		    size_t errlen)
{
	if (errlen)
		err[0] = '\0';
	struct edits_gl *G = gl_of(ed, err, errlen);
	if (!G)
		return -1;
	if (!G->p_test) {
		G->p_test = gpu_compute_program("curve_test.comp", NULL, err, errlen);
		if (!G->p_test)
			return -1;
	}
	if (n <= 0)
		return 0;
	GLsizeiptr in_bytes = (GLsizeiptr)n * (mode == 0 ? 64 : 16), out_bytes = (GLsizeiptr)n * 16;
	if (ensure(&G->b_in, &G->in_cap, in_bytes) < 0 || ensure(&G->b_out, &G->out_cap, out_bytes) < 0) {
		snprintf(err, errlen, "cannot allocate test buffers");
		return -1;
	}
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, G->b_in);
	glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, in_bytes, in);
	glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
	if (edits_gl_bind(ed, G->p_test, p, err, errlen) < 0) {
		if (!err[0])
			snprintf(err, errlen, "curves/heightmap could not be bound (see the log)");
		return -1;
	}
	gpu_set_param_uniforms(G->p_test, p);
	glProgramUniform1i(G->p_test, gpu_uniform(G->p_test, "u_test_mode"), mode);
	glProgramUniform1i(G->p_test, gpu_uniform(G->p_test, "u_test_n"), n);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_IN, G->b_in);
	glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_AUX_OUT, G->b_out);
	glUseProgram(G->p_test);
	glDispatchCompute((GLuint)(n + WG_SIZE - 1) / WG_SIZE, 1, 1);
	glUseProgram(0);
	if (gpu_check("curve test") < 0 || gpu_read_buffer(G->b_out, 0, out_bytes, out) < 0) {
		snprintf(err, errlen, "curve test dispatch failed");
		return -1;
	}
	return 0;
}
