/* isoterra — between the shader loader (shader.c) and the live-editing
 * watcher (shader_watch.c): what a program is built from, and the note the
 * loader sends for every program it builds.  Private to app/gpu. */
#ifndef ISOTERRA_SHADER_INT_H
#define ISOTERRA_SHADER_INT_H

#include <stdbool.h>
#include <GLES3/gl31.h>

#define SHADER_MAX_DEPS 48

/* A program's sources: one .comp file, or a vertex and a fragment file,
 * and the caller's #defines (NULL: none; borrowed). */
struct shader_desc {
	bool compute;
	char file[2][64];
	const char *defines;
};

/* The files a program was made of (its own and every #include). */
struct shader_deps {
	char names[SHADER_MAX_DEPS][64];
	int n;
};

/* Compiles and links a new program from the files as they are now; deps
 * (or NULL) gets the files.  0 with a file:line message in err. */
GLuint shader_build(const struct shader_desc *d, struct shader_deps *deps, char *err, size_t errlen);
/* The loader built prog from d: the open watcher (if any) records it. */
void shader_watch_note(GLuint prog, const struct shader_desc *d, const struct shader_deps *deps);

#endif
