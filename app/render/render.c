/* isoterra — offscreen rendering: colour+depth FBO (multisampled, or
 * smoothed after the frame: --antialias), lit draw of the mesh with the
 * pipeline's indirect command, resolve and read-back. */
#include "render.h"
#include "render_int.h"
#include "gpu.h"
#include "core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* the terrain program's specialization (params_glsl_specialization) */
#define RENDER_KEY_MAX 2048

/* a terrain program and its per-frame uniforms */
struct terrain_prog {
	GLuint prog;
	bool failed; /* did not build for the key: not tried again until the key changes */
	GLint l_viewproj, l_eye, l_fog, l_sink;
};

/* the terrain's three variants: with the detail normals at both scales
 * (meshes that come within DETAIL_FINE_SHARE * DETAIL_RANGE of the eye),
 * at the coarser scale only (those within DETAIL_RANGE; the finer has
 * faded out there), and without (the rest: the detail has faded out
 * there).  A software rasterizer would still pay for the taps of a detail
 * faded out in every pixel, both sides of a branch being run.  PROG_FAR,
 * the shortest, is the base: made with the key (a program that does not
 * build fails the frame), the others when a mesh first asks for one (the
 * no-flag picture, seen from beyond DETAIL_RANGE, compiles no other). */
enum { PROG_NEAR, PROG_NEAR1, PROG_FAR, PROG_COUNT };

struct renderer {
	int w, h, samples;
	int aa;       /* ANTIALIAS_MSAA (samples > 0), _FXAA (fx) or _OFF */
	GLuint fbo_ms, rb_color_ms, rb_depth;
	GLuint fbo, rb_color;
	GLuint vao, sky, water;
	/* the depth pre-pass (a software rasterizer's: its fragment shading
	 * costs CPU time for every layer drawn over a pixel) */
	enum { PREPASS_OFF, PREPASS_ON, PREPASS_BY_SIZE } prepass; /* by size: renderer_draw */
	GLuint depth_prog;
	/* renderer_draw's mesh in parts of at least this many triangles, each
	 * finished before the next is binned (a software rasterizer's: its
	 * bins hold a whole draw); 0 = one draw */
	uint32_t part_tris;
	struct draw_parts pt;
	struct terrain_prog tp[PROG_COUNT]; /* the terrain's, for key (all but PROG_FAR made when first needed) */
	int cur;                            /* the variant in use this frame */
	char key[RENDER_KEY_MAX];
	bool draw_sky;
	bool sky_due;     /* the sky of the frame begun, not drawn yet (sky_pass) */
	bool smooth_off;  /* the governor turned the filter after the frame off */
	int detail;       /* ... and the close-up detail's scales: 2, 1 (every near mesh drawn with
			   * PROG_NEAR1), 0 (every mesh with PROG_FAR) */
	struct camera cam;       /* this frame's, for a variant made mid-frame */
	const struct params *par; /* this frame's parameters (renderer_begin's) */
	float clear[3];
	GLuint surface;
	GLuint road_tex;          /* renderer_set_road_map */
	const float (*lakes)[5];  /* renderer_set_lakes (borrowed) */
	int nlakes;
	float road[6];            /* origin x z, 1 / size x z, y0, tol */
	float scale;  /* the governor's render scale: the frame is drawn at */
	int sw, sh;   /* sw x sh in the lower-left corner, then upscaled */
	struct upscale up;
	struct upscale fx; /* --antialias fxaa: the pass at full size */
	struct upscale kept; /* a frame kept for a crossfade (fade.frag), made on first use */
	int quarter;         /* --rotate: quarter turns clockwise onto the output */
	struct upscale rot;  /* its pass to a display (rotate.frag), made on first use */
};

static const char *fbo_status(GLenum s)
{
	switch (s) {
	case GL_FRAMEBUFFER_COMPLETE: return "complete";
	case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "incomplete attachment";
	case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "missing attachment";
	case GL_FRAMEBUFFER_UNSUPPORTED: return "unsupported";
	case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "incomplete multisample";
	default: return "unknown status";
	}
}

struct renderer *renderer_create(int width, int height, int antialias, char *err, size_t errlen)
{
	struct renderer *r = calloc(1, sizeof(*r));
	if (!r) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	r->w = r->sw = width;
	r->h = r->sh = height;
	r->detail = 2;
	r->scale = 1.0f;
	r->clear[0] = 0.62f;
	r->clear[1] = 0.74f;
	r->clear[2] = 0.88f;
	GLint max_samples = 0, max_rb = 0;
	glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
	glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_rb);
	if (width > max_rb || height > max_rb) {
		snprintf(err, errlen, "--size %dx%d exceeds the GL renderbuffer limit %d", width, height, max_rb);
		free(r);
		return NULL;
	}
	/* auto: 4x multisampling where a GPU does it in hardware; a software
	 * rasterizer pays for it per sample (llvmpipe: 2.5 times the world's
	 * whole frame at 640x480), so the filter after the frame there; a
	 * driver without 4 samples gets the filter too */
	r->aa = antialias;
	if (r->aa == ANTIALIAS_AUTO)
		r->aa = gpu_software_rasterizer() ? ANTIALIAS_FXAA : ANTIALIAS_MSAA;
	r->prepass = gpu_software_rasterizer() ? PREPASS_BY_SIZE : PREPASS_OFF;
	r->part_tris = gpu_software_rasterizer() ? RENDER_PART_TRIANGLES : 0;
	if (r->aa == ANTIALIAS_MSAA && max_samples < 4)
		r->aa = ANTIALIAS_FXAA;
	r->samples = r->aa == ANTIALIAS_MSAA ? 4 : 0;

	glGenRenderbuffers(1, &r->rb_color);
	glBindRenderbuffer(GL_RENDERBUFFER, r->rb_color);
	glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
	glGenFramebuffers(1, &r->fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->rb_color);

	glGenRenderbuffers(1, &r->rb_depth);
	glBindRenderbuffer(GL_RENDERBUFFER, r->rb_depth);
	if (r->samples) {
		glGenRenderbuffers(1, &r->rb_color_ms);
		glBindRenderbuffer(GL_RENDERBUFFER, r->rb_color_ms);
		glRenderbufferStorageMultisample(GL_RENDERBUFFER, r->samples, GL_RGBA8, width, height);
		glBindRenderbuffer(GL_RENDERBUFFER, r->rb_depth);
		glRenderbufferStorageMultisample(GL_RENDERBUFFER, r->samples, GL_DEPTH_COMPONENT24, width, height);
		glGenFramebuffers(1, &r->fbo_ms);
		glBindFramebuffer(GL_FRAMEBUFFER, r->fbo_ms);
		glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->rb_color_ms);
	} else {
		glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
	}
	glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->rb_depth);
	GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
	if (st != GL_FRAMEBUFFER_COMPLETE || gpu_check("framebuffer setup") < 0) {
		snprintf(err, errlen, "cannot create a %dx%d render target: framebuffer %s", width, height, fbo_status(st));
		renderer_destroy(r);
		return NULL;
	}
	r->draw_sky = true;
	/* issued together (a driver with parallel compilation builds them side
	 * by side); the terrain's program is made for the parameters at the
	 * first frame */
	gpu_prefetch_graphics("sky.vert", "sky.frag", NULL);
	gpu_prefetch_graphics("water.vert", "water.frag", NULL);
	if (r->aa == ANTIALIAS_FXAA)
		gpu_prefetch_graphics("upscale.vert", "fxaa.frag", NULL);
	r->sky = gpu_graphics_program("sky.vert", "sky.frag", NULL, err, errlen);
	if (r->sky)
		r->water = gpu_graphics_program("water.vert", "water.frag", NULL, err, errlen);
	if (!r->sky || !r->water ||
	    (r->aa == ANTIALIAS_FXAA && upscale_init(&r->fx, "fxaa.frag", width, height, err, errlen) < 0)) {
		renderer_destroy(r);
		return NULL;
	}
	glGenVertexArrays(1, &r->vao);
	r->surface = surface_texture_create();
	if (!r->surface) {
		snprintf(err, errlen, "cannot create the surface texture");
		renderer_destroy(r);
		return NULL;
	}
	return r;
}

int renderer_antialias(const struct renderer *r)
{
	return r->aa;
}

void renderer_destroy(struct renderer *r)
{
	if (!r)
		return;
	for (int i = 0; i < PROG_COUNT; i++)
		if (r->tp[i].prog)
			glDeleteProgram(r->tp[i].prog);
	if (r->depth_prog)
		glDeleteProgram(r->depth_prog);
	if (r->sky)
		glDeleteProgram(r->sky);
	if (r->water)
		glDeleteProgram(r->water);
	if (r->vao)
		glDeleteVertexArrays(1, &r->vao);
	if (r->surface)
		glDeleteTextures(1, &r->surface);
	upscale_free(&r->up);
	upscale_free(&r->fx);
	upscale_free(&r->kept);
	upscale_free(&r->rot);
	parts_free(&r->pt);
	GLuint fb[2] = { r->fbo, r->fbo_ms };
	glDeleteFramebuffers(2, fb);
	GLuint rb[3] = { r->rb_color, r->rb_color_ms, r->rb_depth };
	glDeleteRenderbuffers(3, rb);
	free(r);
}

/* One variant of the terrain's program for key: 0 (logged) when it does
 * not build. */
static GLuint terrain_variant(const char *key, int variant)
{
	char full[RENDER_KEY_MAX + 64], err[512];
	snprintf(full, sizeof(full), "%s#define DETAIL_NORMALS %d\n", key,
		 variant == PROG_NEAR ? 2 : variant == PROG_NEAR1 ? 1 : 0);
	GLuint prog = gpu_graphics_program("render.vert", "render.frag", full, err, sizeof(err));
	if (!prog)
		log_error("terrain program: %s", err);
	return prog;
}

/* The parameters' uniforms of a program that shades (shade.glsl), and the
 * sun's direction worked out once here rather than in every pixel (a
 * software rasterizer would run its four sines and cosines per fragment). */
static void shading_uniforms(GLuint prog, const struct params *p)
{
	gpu_set_param_uniforms(prog, p);
	float el = p->light_el * (float)M_PI / 180.0f, az = p->light_az * (float)M_PI / 180.0f;
	glProgramUniform3f(prog, gpu_uniform(prog, "u_sun_dir"), cosf(el) * cosf(az), sinf(el),
			   cosf(el) * sinf(az));
}

/* The frame's uniforms of one terrain program. */
static void terrain_uniforms(struct terrain_prog *t, const struct camera *c, const struct params *p)
{
	glUseProgram(t->prog);
	/* looked up per frame: a live shader edit may move them */
	t->l_viewproj = gpu_uniform(t->prog, "u_viewproj");
	t->l_eye = gpu_uniform(t->prog, "u_eye");
	t->l_fog = gpu_uniform(t->prog, "u_fog_density");
	t->l_sink = gpu_uniform(t->prog, "u_sink");
	shading_uniforms(t->prog, p);
	glUniformMatrix4fv(t->l_viewproj, 1, GL_FALSE, c->viewproj);
	glUniform3fv(t->l_eye, 1, c->eye);
	float fog_range = p->scene == SCENE_WORLD ? p->view_distance * 0.6f : p->vol_size * p->cam_dist * 2.0f;
	glUniform1f(t->l_fog, 0.35f / fog_range);
	glUniform1f(t->l_sink, 0.0f);
}

void renderer_set_road_map(struct renderer *r, GLuint tex, const float origin[2], const float size[2], float y0,
			   float tol)
{
	r->road_tex = tex;
	if (tex) {
		float v[6] = { origin[0], origin[1], 1.0f / size[0], 1.0f / size[1], y0, tol };
		memcpy(r->road, v, sizeof(v));
	}
}

/* The terrain's program for p: specialized (params_glsl_specialization:
 * the shape's and soil's branches folded, the marble colour compiled only
 * when on; a software rasterizer runs a uniform branch's both sides),
 * made again when a live knob changes the key, the old ones deleted (the
 * program binary cache keeps switching back cheap).  The base variant
 * (PROG_FAR) is made here, the others when a mesh first asks for one.
 * 0, or -1 (logged). */
static int terrain_program(struct renderer *r, const struct params *p)
{
	char key[RENDER_KEY_MAX];
	if (params_glsl_specialization(p, key, sizeof(key)) < 0 ||
	    (r->road_tex && strlen(key) + 24 >= sizeof(key))) {
		log_error("terrain program: specialization key too long");
		return -1;
	}
	if (r->road_tex)
		strcat(key, "#define ROAD_MAP 1\n");
	if (r->tp[PROG_FAR].prog && !strcmp(key, r->key))
		return 0;
	GLuint prog = terrain_variant(key, PROG_FAR);
	if (!prog)
		return -1;
	for (int i = 0; i < PROG_COUNT; i++)
		if (r->tp[i].prog)
			glDeleteProgram(r->tp[i].prog);
	memset(r->tp, 0, sizeof(r->tp));
	r->tp[PROG_FAR].prog = prog;
	snprintf(r->key, sizeof(r->key), "%s", key);
	return 0;
}

/* The frame's uniforms of variant i (renderer_begin's camera and
 * parameters): also of one made mid-frame, when a mesh first asks for it. */
static void variant_uniforms(struct renderer *r, int i)
{
	terrain_uniforms(&r->tp[i], &r->cam, r->par);
	if (r->road_tex) {
		GLuint pr = r->tp[i].prog;
		glProgramUniform4f(pr, gpu_uniform(pr, "u_road_rect"), r->road[0], r->road[1], r->road[2], r->road[3]);
		glProgramUniform2f(pr, gpu_uniform(pr, "u_road_y"), r->road[4], r->road[5]);
	}
}

int renderer_prepare(struct renderer *r, const struct params *p)
{
	if (terrain_program(r, p) < 0)
		return -1;
	/* the variant with the most in it too: a frame would make it later */
	if (!r->tp[PROG_NEAR].prog && !(r->tp[PROG_NEAR].prog = terrain_variant(r->key, PROG_NEAR)))
		return -1;
	return 0;
}

int renderer_begin(struct renderer *r, const struct camera *c, const struct params *p)
{
	if (terrain_program(r, p) < 0)
		return -1;
	glBindFramebuffer(GL_FRAMEBUFFER, r->samples ? r->fbo_ms : r->fbo);
	glViewport(0, 0, r->sw, r->sh);
	/* sky colour (linear -> the shader's fog colour matches it) */
	glClearColor(r->clear[0], r->clear[1], r->clear[2], 1.0f);
	glClearDepthf(1.0f);
	glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
	glBindVertexArray(r->vao);
	r->sky_due = r->draw_sky; /* drawn after the terrain: sky_pass */
	glEnable(GL_DEPTH_TEST);
	glDepthFunc(GL_LESS);
	/* Back faces show only where a cut opens the rock: the sides of a
	 * volume that is not closed.  The world is seen from the air (the
	 * autopilot never enters rock) and a closed volume from outside, so
	 * there every back face is hidden: culled before llvmpipe bins it
	 * (about a fifth of the world's frame time, and its bins' memory).
	 * Marching cubes winds every triangle counter-clockwise seen from
	 * the air. */
	if (p->scene == SCENE_WORLD || p->closed) {
		glEnable(GL_CULL_FACE);
		glCullFace(GL_BACK);
		glFrontFace(GL_CCW);
	} else {
		glDisable(GL_CULL_FACE);
	}

	r->cam = *c;
	r->par = p;
	/* a variant made on an earlier frame gets its uniforms too */
	for (int i = 0; i < PROG_COUNT; i++)
		if (r->tp[i].prog)
			variant_uniforms(r, i);
	r->cur = PROG_FAR;
	glUseProgram(r->tp[PROG_FAR].prog);
	glActiveTexture(GL_TEXTURE0 + TEX_SURFACE);
	glBindTexture(GL_TEXTURE_2D, r->surface);
	if (r->road_tex) {
		glActiveTexture(GL_TEXTURE0 + TEX_ROADS);
		glBindTexture(GL_TEXTURE_2D, r->road_tex);
	}
	glActiveTexture(GL_TEXTURE0);
	glBindVertexArray(r->vao);
	return 0;
}

void renderer_set_prepass(struct renderer *r, bool on)
{
	r->prepass = on ? PREPASS_ON : PREPASS_OFF;
}

bool renderer_prepass(const struct renderer *r)
{
	return r->prepass != PREPASS_OFF;
}

void renderer_set_parts(struct renderer *r, uint32_t triangles)
{
	r->part_tris = triangles;
}

uint32_t renderer_parts(const struct renderer *r)
{
	return r->part_tris;
}

static void draw_indirect(GLuint vbo, GLuint ibo, GLuint indirect, GLintptr offset)
{
	glBindBuffer(GL_ARRAY_BUFFER, vbo);
	glEnableVertexAttribArray(0);
	glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, VERTEX_BYTES, (const void *)0);
	glEnableVertexAttribArray(1);
	glVertexAttribIPointer(1, 1, GL_UNSIGNED_INT, VERTEX_BYTES, (const void *)12); /* vertex.glsl */
	glBindBuffer(GL_DRAW_INDIRECT_BUFFER, indirect);
	if (ibo) {
		glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
		glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, (const void *)offset);
	} else {
		glDrawArraysIndirect(GL_TRIANGLES, (const void *)offset);
	}
}

/* renderer_draw's mesh: one draw of its indirect command, or its parts
 * (render_int.h), each rasterized before the next is binned; shaded by
 * the terrain's program, or by the program in use (the depth pre-pass). */
static void draw_mesh(struct renderer *r, const struct pipeline_draw *d, uint32_t parts, bool shaded, float dist)
{
	GLuint ibo = d->indexed ? d->ibo : 0;
	GLuint cmd = parts ? r->pt.buf : d->indirect;
	for (uint32_t i = 0; i < (parts ? parts : 1); i++) {
		GLintptr at = parts ? (GLintptr)i * PART_BYTES : d->indirect_offset;
		if (shaded)
			renderer_draw_mesh(r, d->vbo, ibo, cmd, at, 0.0f, dist);
		else
			draw_indirect(d->vbo, ibo, cmd, at);
		if (parts)
			glFinish();
	}
}

/* The depth pre-pass (render.h): the mesh's depth laid down, rasterized
 * before the shading pass is binned (the software rasterizer frees the
 * depth pass's bins first, so the two do not hold memory at once: the
 * no-flag run's peak 153 -> 139.5 MB, its time the same); the shading pass
 * then tests GL_LEQUAL.  0, or -1 (logged: no depth program). */
static int depth_pass(struct renderer *r, const struct pipeline_draw *d, uint32_t parts, const struct camera *c)
{
	if (!r->depth_prog) {
		char err[512];
		r->depth_prog = gpu_graphics_program("render.vert", "depth.frag", NULL, err, sizeof(err));
		if (!r->depth_prog) {
			log_error("depth pre-pass: %s", err);
			return -1;
		}
	}
	glUseProgram(r->depth_prog);
	/* cached per program; a live shader edit's relink forgets them (gpu_uniform) */
	glUniformMatrix4fv(gpu_uniform(r->depth_prog, "u_viewproj"), 1, GL_FALSE, c->viewproj);
	glUniform1f(gpu_uniform(r->depth_prog, "u_sink"), 0.0f);
	glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
	draw_mesh(r, d, parts, false, 0.0f);
	glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
	if (!parts) /* parts are finished one by one */
		glFinish();
	glDepthFunc(GL_LEQUAL); /* the surfaces laid down pass again, once */
	glUseProgram(r->tp[r->cur].prog);
	return 0;
}

void renderer_draw_mesh(struct renderer *r, GLuint vbo, GLuint ibo, GLuint indirect, GLintptr offset, float sink,
			float dist)
{
	int want = dist >= DETAIL_RANGE || r->detail <= 0		      ? PROG_FAR
		   : dist >= DETAIL_FINE_SHARE * DETAIL_RANGE || r->detail == 1 ? PROG_NEAR1
										 : PROG_NEAR;
	if (!r->tp[want].prog && !r->tp[want].failed) {
		r->tp[want].prog = terrain_variant(r->key, want);
		r->tp[want].failed = !r->tp[want].prog;
		if (r->tp[want].prog)
			variant_uniforms(r, want);
	}
	if (!r->tp[want].prog) /* logged: the base one draws it, without the detail */
		want = PROG_FAR;
	if (want != r->cur) {
		glUseProgram(r->tp[want].prog);
		r->cur = want;
	}
	glUniform1f(r->tp[want].l_sink, sink);
	draw_indirect(vbo, ibo, indirect, offset);
}

void renderer_set_clear(struct renderer *r, float red, float green, float blue)
{
	r->draw_sky = false;
	r->clear[0] = red;
	r->clear[1] = green;
	r->clear[2] = blue;
}

/* The sky of the frame begun, once, after the opaque terrain and before
 * the water (which blends over it): a full-screen triangle at the far
 * plane, depth-tested against the terrain, so that only the pixels the
 * terrain left shade it (a software rasterizer tests depth before the
 * shader: the sky costs the sky's share of the frame, not all of it).
 * The triangle winds counter-clockwise, so back-face culling keeps it;
 * its callers (the water, the frame's end) set their own program and
 * culling next. */
static void sky_pass(struct renderer *r)
{
	if (!r->sky_due)
		return;
	r->sky_due = false;
	float inv[16];
	if (mat4_invert(inv, r->cam.viewproj) != 0)
		return;
	glEnable(GL_DEPTH_TEST);
	glDepthFunc(GL_LEQUAL); /* the cleared depth, 1: where nothing was drawn */
	glDepthMask(GL_FALSE);
	glUseProgram(r->sky);
	shading_uniforms(r->sky, r->par);
	glUniformMatrix4fv(gpu_uniform(r->sky, "u_inv_viewproj"), 1, GL_FALSE, inv);
	glUniform3fv(gpu_uniform(r->sky, "u_eye"), 1, r->cam.eye);
	glDrawArrays(GL_TRIANGLES, 0, 3);
	glDepthMask(GL_TRUE);
	glDepthFunc(GL_LESS);
}

/* water.vert's sphere: 96 x 48 quads of two triangles */
#define WATER_SPHERE_VERTICES (96 * 48 * 6)

/* Water at `level` over rect: the sea (renderer_water) or a lake. */
static void water_pass(struct renderer *r, const struct camera *c, const struct params *p, const float rect[4],
		       float level)
{
	/* a planet's sea is a sphere water_level above planet_radius (a flat
	 * plane would cut through the planet); water.vert makes it */
	sky_pass(r); /* under the water */
	bool sphere = p->shape == SHAPE_PLANET;
	float radius = p->planet_radius + level;
	if (sphere && radius <= 0.0f)
		return;
	glDisable(GL_CULL_FACE); /* the plane is seen from both sides */
	glUseProgram(r->water);
	glUniform1f(gpu_uniform(r->water, "u_water_sphere"), sphere ? radius : 0.0f);
	glUniform3f(gpu_uniform(r->water, "u_water_centre"), 0.0f, -p->planet_radius, 0.0f);
	shading_uniforms(r->water, p);
	glUniform1f(gpu_uniform(r->water, "u_water_level"), level); /* over the parameter's */
	glUniformMatrix4fv(gpu_uniform(r->water, "u_viewproj"), 1, GL_FALSE, c->viewproj);
	glUniform3fv(gpu_uniform(r->water, "u_eye"), 1, c->eye);
	glUniform4fv(gpu_uniform(r->water, "u_water_rect"), 1, rect);
	float fog_range = p->scene == SCENE_WORLD ? p->view_distance * 0.6f : p->vol_size * p->cam_dist * 2.0f;
	glUniform1f(gpu_uniform(r->water, "u_fog_density"), 0.35f / fog_range);
	glEnable(GL_BLEND);
	/* the frame stays opaque: a compositor (Wayland) would show the desktop through the water */
	glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
	glDepthMask(GL_FALSE);
	if (sphere) { /* the near half only: the far half lies behind it */
		glEnable(GL_CULL_FACE);
		glCullFace(GL_BACK);
		glFrontFace(GL_CCW);
		glDrawArrays(GL_TRIANGLES, 0, WATER_SPHERE_VERTICES);
		glDisable(GL_CULL_FACE);
	} else {
		glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
	}
	glDepthMask(GL_TRUE);
	glDisable(GL_BLEND);
	glUseProgram(r->tp[r->cur].prog);
}

void renderer_water(struct renderer *r, const struct camera *c, const struct params *p, const float rect[4])
{
	if (p->water)
		water_pass(r, c, p, rect, p->water_level);
}

void renderer_set_lakes(struct renderer *r, const float (*lakes)[5], int n)
{
	r->lakes = lakes;
	r->nlakes = lakes ? n : 0;
}

void renderer_lakes(struct renderer *r, const struct camera *c, const struct params *p, const float rect[4])
{
	if (p->shape == SHAPE_PLANET)
		return;
	for (int i = 0; i < r->nlakes; i++) {
		const float *l = r->lakes[i];
		float q[4] = { fmaxf(l[0], rect[0]), fmaxf(l[1], rect[1]), fminf(l[2], rect[2]), fminf(l[3], rect[3]) };
		/* the sea at the same height already covers it */
		if (q[0] >= q[2] || q[1] >= q[3] || (p->water && fabsf(l[4] - p->water_level) < 1e-3f))
			continue;
		water_pass(r, c, p, q, l[4]);
	}
}

int renderer_end(struct renderer *r)
{
	sky_pass(r); /* a frame without water */
	glDisable(GL_CULL_FACE); /* the passes after the frame draw whatever their winding */
	glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
	int rc = gpu_check("draw");
	if (rc == 0 && (r->sw != r->w || r->sh != r->h)) {
		rc = upscale_run(&r->up, r->samples ? r->fbo_ms : r->fbo, r->sw, r->sh);
		glViewport(0, 0, r->w, r->h);
	} else if (rc == 0 && r->aa == ANTIALIAS_FXAA && !r->smooth_off) {
		rc = upscale_run(&r->fx, r->fbo, r->w, r->h);
	}
	glBindVertexArray(0);
	glUseProgram(0);
	return rc;
}

void renderer_set_smoothing(struct renderer *r, bool on)
{
	r->smooth_off = !on;
}

void renderer_set_detail(struct renderer *r, int scales)
{
	r->detail = scales < 0 ? 0 : scales > 2 ? 2 : scales;
}

int renderer_set_scale(struct renderer *r, float scale, char *err, size_t errlen)
{
	scale = scale < 0.5f ? 0.5f : scale > 1.0f ? 1.0f : scale;
	if (scale < 1.0f && !r->up.prog && upscale_init(&r->up, "upscale.frag", r->w, r->h, err, errlen) < 0)
		return -1;
	r->scale = scale;
	r->sw = (int)(r->w * scale + 0.5f);
	r->sh = (int)(r->h * scale + 0.5f);
	if (r->sw < 1)
		r->sw = 1;
	if (r->sh < 1)
		r->sh = 1;
	return 0;
}

int renderer_keep_frame(struct renderer *r, char *err, size_t errlen)
{
	if (!r->kept.prog && upscale_init(&r->kept, "fade.frag", r->w, r->h, err, errlen) < 0)
		return -1;
	upscale_grab(&r->kept, r->samples ? r->fbo_ms : r->fbo, r->w, r->h);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	if (gpu_check("keeping the frame") < 0) {
		snprintf(err, errlen, "the frame could not be kept");
		return -1;
	}
	return 0;
}

int renderer_fade_kept(struct renderer *r, float alpha)
{
	if (!r->kept.prog)
		return 0;
	return upscale_draw(&r->kept, r->samples ? r->fbo_ms : r->fbo, r->w, r->h, alpha);
}

void renderer_target(const struct renderer *r, unsigned *fbo, int *w, int *h)
{
	*fbo = r->samples ? r->fbo_ms : r->fbo;
	*w = r->w;
	*h = r->h;
}

int renderer_draw(struct renderer *r, const struct pipeline_draw *d, const struct camera *c, const struct params *p)
{
	/* the parts' commands first: a compute pass, before the frame's state */
	uint32_t parts = 0, per = 0;
	if (r->part_tris) {
		parts = parts_plan(d->capacity, r->part_tris, &per);
		if (parts_split(&r->pt, d->indirect, d->indirect_offset, d->indexed, parts, per) < 0)
			return -1;
	}
	if (renderer_begin(r, c, p) < 0)
		return -1;
	/* the pre-pass bins every triangle once more, which pays where the
	 * picture has about as many pixels as the mesh has triangles or more
	 * (the same-field run's 88 114 at --grid 128, draw p50 medians: 8.5 ms
	 * less at 640x480, 0.7 more at 320x240, 6.6 more at 160x120, 8.2 more
	 * at 64x48); the count is the GPU's, the capacity (16 triangles a cell
	 * of the grid's largest face, or --max-triangles) about three times a
	 * terrain's */
	bool pre = r->prepass == PREPASS_ON ||
		   (r->prepass == PREPASS_BY_SIZE && (uint64_t)r->w * (uint64_t)r->h * 3 >= d->capacity);
	if (pre && depth_pass(r, d, parts, c) < 0)
		return -1;
	/* the mesh lies in the grid's box: from afar it is shaded by the
	 * variant for its distance (the default picture's eye is 40 units
	 * from it: no detail normals, which have faded out there) */
	struct grid g;
	float lo[3], hi[3];
	grid_from_params(&g, p);
	grid_box(&g, lo, hi);
	draw_mesh(r, d, parts, true, camera_box_distance(c, lo, hi));
	/* water inside the volume only, below its top: on the procedural
	 * terrain and on heightmaps (a georeferenced one's sea level, set by
	 * heightmap_fit) */
	float rect[4] = { lo[0], lo[2], hi[0], hi[2] };
	if ((p->field == FIELD_TERRAIN || p->field == FIELD_HEIGHTMAP) &&
	    ((p->field == FIELD_TERRAIN && p->shape == SHAPE_PLANET) ||
	     (p->water_level > lo[1] && p->water_level < hi[1])))
		renderer_water(r, c, p, rect);
	renderer_lakes(r, c, p, rect);
	return renderer_end(r);
}

/* The upright picture (top row first) turned q quarter turns clockwise, in
 * place of img.  0, or -1 (out of memory; img freed). */
static int rotate_image(struct image *img, int q)
{
	int w = img->width, h = img->height, ow = q & 1 ? h : w, oh = q & 1 ? w : h;
	uint32_t *out = malloc((size_t)w * h * 4), *in = (uint32_t *)img->rgba;
	if (!out) {
		free(img->rgba);
		img->rgba = NULL;
		return -1;
	}
	for (int y = 0; y < oh; y++)
		for (int x = 0; x < ow; x++) {
			int sx = q == 1 ? y : q == 2 ? w - 1 - x : w - 1 - y;
			int sy = q == 1 ? h - 1 - x : q == 2 ? h - 1 - y : x;
			out[(size_t)y * ow + x] = in[(size_t)sy * w + sx];
		}
	free(img->rgba);
	img->rgba = (uint8_t *)out;
	img->width = ow;
	img->height = oh;
	return 0;
}

void renderer_set_rotation(struct renderer *r, int quarter)
{
	r->quarter = quarter & 3;
}

struct renderer *renderer_create_turned(int w, int h, int quarter, int antialias, char *err, size_t errlen)
{
	struct renderer *r = renderer_create(quarter & 1 ? h : w, quarter & 1 ? w : h, antialias, err, errlen);
	if (r)
		renderer_set_rotation(r, quarter);
	return r;
}

int renderer_rotation(const struct renderer *r)
{
	return r->quarter;
}

int renderer_read(struct renderer *r, struct image *img)
{
	if (r->samples) {
		glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo_ms);
		glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->fbo);
		glBlitFramebuffer(0, 0, r->w, r->h, 0, 0, r->w, r->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
	}
	glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
	img->width = r->w;
	img->height = r->h;
	img->rgba = malloc((size_t)r->w * r->h * 4);
	if (!img->rgba)
		return -1;
	glPixelStorei(GL_PACK_ALIGNMENT, 1);
	glReadPixels(0, 0, r->w, r->h, GL_RGBA, GL_UNSIGNED_BYTE, img->rgba);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	if (gpu_check("read pixels") < 0) {
		free(img->rgba);
		img->rgba = NULL;
		return -1;
	}
	/* GL's first row is the bottom one */
	size_t row = (size_t)r->w * 4;
	uint8_t *tmp = malloc(row);
	if (!tmp) {
		free(img->rgba);
		img->rgba = NULL;
		return -1;
	}
	for (int y = 0; y < r->h / 2; y++) {
		uint8_t *a = img->rgba + row * y, *b = img->rgba + row * (r->h - 1 - y);
		memcpy(tmp, a, row);
		memcpy(a, b, row);
		memcpy(b, tmp, row);
	}
	free(tmp);
	return r->quarter ? rotate_image(img, r->quarter) : 0;
}

/* ---- display platforms: the frame to the window -------------------------- */
int renderer_blit_to_default(struct renderer *r, int w, int h)
{
	if (r->samples) {
		glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo_ms);
		glBindFramebuffer(GL_DRAW_FRAMEBUFFER, r->fbo);
		glBlitFramebuffer(0, 0, r->w, r->h, 0, 0, r->w, r->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
	}
	if (r->quarter) { /* a rotated panel: the frame through rotate.frag */
		char err[256];
		if (!r->rot.prog && upscale_init(&r->rot, "rotate.frag", r->w, r->h, err, sizeof(err)) < 0) {
			log_error("%s", err);
			return -1;
		}
		upscale_grab(&r->rot, r->fbo, r->w, r->h);
		return upscale_draw_rotated(&r->rot, 0, w, h, r->quarter);
	}
	/* both are bottom-up: no flip */
	glBindFramebuffer(GL_READ_FRAMEBUFFER, r->fbo);
	glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
	glBlitFramebuffer(0, 0, r->w, r->h, 0, 0, w, h, GL_COLOR_BUFFER_BIT,
	                  w == r->w && h == r->h ? GL_NEAREST : GL_LINEAR);
	glBindFramebuffer(GL_FRAMEBUFFER, 0);
	return gpu_check("blit to the window");
}
