/* isoterra — GL helpers and the shader loader.
 *
 * Shaders live in shaders/ (GLSL ES 3.10), embedded into the binary at build
 * time; shader_set_dir() makes the loader read them from disk instead (live
 * editing).  The host expands  #include "file"  and prefixes every program
 * with the #version line, the parameter uniforms (params_glsl_decls) and the
 * caller's #defines.  Compile errors are reported as file:line. */
#ifndef ISOTERRA_GPU_H
#define ISOTERRA_GPU_H

#include <stdbool.h>
#include <stddef.h>
#include <GLES3/gl31.h>

#include "params.h"
#include "abi.h" /* binding points, units, status words: shared with the shaders */

struct embedded_file {
	const char *name;
	const char *text;
};
extern const struct embedded_file embedded_shaders[];
extern const size_t embedded_shader_count;

void shader_set_dir(const char *dir); /* NULL or "" = embedded */
/* Raw text of one shader file (malloc'd), or NULL with err. */
char *shader_read(const char *name, char *err, size_t errlen);
/* Compute program from one .comp file.  defines: extra "#define X Y\n" lines
 * or NULL.  Returns 0 with a file:line message in err on failure. */
GLuint gpu_compute_program(const char *file, const char *defines, char *err, size_t errlen);
GLuint gpu_graphics_program(const char *vs_file, const char *fs_file, const char *defines, char *err, size_t errlen);
/* Issues the compile and link of a program that gpu_compute_program /
 * gpu_graphics_program will be asked for with the same arguments, and
 * returns at once: with KHR_parallel_shader_compile the driver builds the
 * programs issued together on its threads.  Errors show when the program
 * is asked for.  gpu_prefetch_drop deletes the ones never asked for. */
void gpu_prefetch_compute(const char *file, const char *defines);
void gpu_prefetch_graphics(const char *vs_file, const char *fs_file, const char *defines);
void gpu_prefetch_drop(void);
/* The program binary cache (program_cache.c): on unless disabled; dir NULL
 * or "" = $XDG_CACHE_HOME/isoterra (else ~/.cache/isoterra).  Call before
 * the first program is made; it also resets the counters. */
void gpu_program_cache_config(bool enabled, const char *dir);
/* The cache's directory when none is configured: $XDG_CACHE_HOME/isoterra,
 * else $HOME/.cache/isoterra; false when neither is an absolute path. */
bool gpu_program_cache_default_dir(char *out, size_t n);
struct gpu_program_cache_stats {
	unsigned hits, misses;  /* programs loaded from the cache / compiled */
	unsigned rejected;      /* files ignored: foreign, truncated, corrupt or refused by the driver */
	unsigned writes, write_errors;
};
struct gpu_program_cache_stats gpu_program_cache_stats(void);
/* Live editing (shader_watch.c): watches dir (the --shader-dir) with
 * inotify; every program the loader builds from then on is recorded.
 * Open it before building programs.  NULL with err. */
struct shader_watch;
struct shader_watch *shader_watch_open(const char *dir, char *err, size_t errlen);
void shader_watch_close(struct shader_watch *w); /* NULL is fine */
/* Between frames, with the programs' context current: the files saved
 * since the last call rebuild every program made of them (in place: the
 * same GLuint); a program whose rebuild fails keeps its last good version.
 * The number rebuilt, or -1 with the first failure's "file:line: message"
 * in msg (the others still rebuilt).  NULL w: 0. */
int shader_watch_poll(struct shader_watch *w, char *msg, size_t msglen);
/* Programs rebuilt in place so far (shader_watch_poll): what was made with
 * them before is stale once this changes. */
unsigned long gpu_programs_rebuilt(void);
/* Sets every u_<name> uniform the program uses from the parameter table. */
void gpu_set_param_uniforms(GLuint prog, const struct params *p);
/* glGetUniformLocation, looked up once per program (app/gpu/uniform_cache.c):
 * name must be a string that outlives the program (a literal). */
GLint gpu_uniform(GLuint prog, const char *name);

/* Capabilities and checks. */
struct gpu_caps {
	int max_ssbo_size;          /* GL_MAX_SHADER_STORAGE_BLOCK_SIZE */
	int max_group_count[3];     /* GL_MAX_COMPUTE_WORK_GROUP_COUNT */
	bool khr_debug;
	char renderer[128], version[128];
};
/* Checks GLES >= 3.1 with compute; fills caps.  0 or -1 with err. */
int gpu_init(struct gpu_caps *caps, bool debug, char *err, size_t errlen);
/* Reads size bytes at off of a buffer object back into out (after the
 * shader-storage and buffer-update barriers).  Tests, export and reports
 * only: never in the frame loop.  0, or -1 (a GL error is logged). */
/* Immutable storage for the bound GL_TEXTURE_2D: one level of fmt, w x h,
 * the filter both ways, clamped at the edges. */
void gpu_texture_2d_storage(GLenum fmt, int w, int h, GLint filter);
int gpu_read_buffer(GLuint buf, GLintptr off, GLsizeiptr size, void *out);
/* A fenced read-back, for results a frame asked for frames ago: when
 * *fence has signalled (with wait: flushed, and waited for up to 10 s) it
 * is deleted (*fence = 0) and size bytes at the start of buf are copied
 * into out.  1 read, 0 not signalled yet (nothing changed), -1 signalled
 * but the buffer could not be mapped (out untouched). */
int gpu_fence_read(GLsync *fence, GLuint buf, GLsizeiptr size, void *out, bool wait);
/* glGetError() != GL_NO_ERROR -> logs "what: GL error 0x..." and returns -1. */
int gpu_check(const char *what);
/* The current context renders on the CPU (its EGL device has
 * EGL_MESA_device_software: llvmpipe, softpipe, lavapipe under zink): work a
 * GPU does in fixed function (multisampling) costs as much as shading
 * there.  A capability of the display, not a renderer name. */
bool gpu_software_rasterizer(void);

/* the GL limits against each program's use (gl_limits.c), which the probe
 * reports */
#include "gl_limits.h"

#endif
