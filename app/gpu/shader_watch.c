/* isoterra — live shader editing: the --shader-dir watched with inotify;
 * a saved file rebuilds, between frames, every program made of it (its
 * own file or an #include).  A program is rebuilt as a new one first; only
 * when that compiles and links are its shaders moved into the program
 * name its owner holds (detached, attached, relinked), so owners keep
 * their GLuint and a broken edit leaves the last good program running.
 * The plain uniforms' values are carried over by name (a relink resets
 * them); uniform locations may change with an edit, so owners look them up
 * after glUseProgram rather than once. */
#include "gpu.h"
#include "gpu_int.h"
#include "core.h"
#include "shader_int.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <unistd.h>

struct watched {
	GLuint prog;
	struct shader_desc d;
	char *defines; /* d.defines points here */
	struct shader_deps deps;
};

struct shader_watch {
	int fd, wd;
	struct watched *progs;
	int n, cap;
};

/* The open watcher the loader notes its programs with (as the loader's
 * directory, one per process: programs are built through plain calls). */
static struct shader_watch *current;
/* programs rebuilt in place since the start (gpu_programs_rebuilt) */
static unsigned long rebuilt_total;

unsigned long gpu_programs_rebuilt(void)
{
	return rebuilt_total;
}

struct shader_watch *shader_watch_open(const char *dir, char *err, size_t errlen)
{
	struct shader_watch *w = calloc(1, sizeof(*w));
	if (!w) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	w->fd = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
	if (w->fd < 0) {
		snprintf(err, errlen, "live shader editing: inotify_init1: %s", strerror(errno));
		free(w);
		return NULL;
	}
	/* editors save in place (close after write) or by renaming a new file over the old */
	w->wd = inotify_add_watch(w->fd, dir, IN_CLOSE_WRITE | IN_MOVED_TO);
	if (w->wd < 0) {
		snprintf(err, errlen, "live shader editing: cannot watch '%s': %s", dir, strerror(errno));
		close(w->fd);
		free(w);
		return NULL;
	}
	current = w;
	return w;
}

static void drop(struct shader_watch *w, int i)
{
	free(w->progs[i].defines);
	w->progs[i] = w->progs[--w->n];
}

void shader_watch_close(struct shader_watch *w)
{
	if (!w)
		return;
	if (current == w)
		current = NULL;
	while (w->n > 0)
		drop(w, w->n - 1);
	free(w->progs);
	close(w->fd);
	free(w);
}

void shader_watch_note(GLuint prog, const struct shader_desc *d, const struct shader_deps *deps)
{
	struct shader_watch *w = current;
	if (!w)
		return;
	for (int i = 0; i < w->n; i++)
		if (w->progs[i].prog == prog) /* a deleted program's name used again */
			drop(w, i--);
	if (w->n == w->cap) {
		int cap = w->cap ? 2 * w->cap : 32;
		struct watched *np = realloc(w->progs, sizeof(*np) * (size_t)cap);
		if (!np) {
			log_warn("live shader editing: out of memory; program %u will not be rebuilt", prog);
			return;
		}
		w->progs = np;
		w->cap = cap;
	}
	struct watched *r = &w->progs[w->n];
	memset(r, 0, sizeof(*r));
	r->prog = prog;
	r->d = *d;
	r->defines = d->defines ? strdup(d->defines) : NULL;
	if (d->defines && !r->defines) {
		log_warn("live shader editing: out of memory; program %u will not be rebuilt", prog);
		return;
	}
	r->d.defines = r->defines;
	r->deps = *deps;
	w->n++;
}

/* The values of a program's plain uniforms (not arrays or blocks), kept by
 * name across a relink: owners set some once, at creation. */
#define KEEP_MAX 96
struct kept {
	char name[64];
	GLenum type;
	union {
		GLfloat f[16];
		GLint i[4];
		GLuint u[4];
	} v;
};

static int keep_uniforms(GLuint prog, struct kept *k)
{
	GLint n = 0, nk = 0;
	glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &n);
	for (GLuint i = 0; i < (GLuint)n && nk < KEEP_MAX; i++) {
		GLint size = 0;
		GLenum type = 0;
		glGetActiveUniform(prog, i, sizeof(k[nk].name), NULL, &size, &type, k[nk].name);
		GLint loc = glGetUniformLocation(prog, k[nk].name);
		if (size != 1 || loc < 0)
			continue;
		k[nk].type = type;
		if (type == GL_FLOAT || type == GL_FLOAT_VEC2 || type == GL_FLOAT_VEC3 || type == GL_FLOAT_VEC4 ||
		    type == GL_FLOAT_MAT4)
			glGetUniformfv(prog, loc, k[nk].v.f);
		else if (type == GL_INT || type == GL_INT_VEC2 || type == GL_INT_VEC3 || type == GL_BOOL)
			glGetUniformiv(prog, loc, k[nk].v.i);
		else if (type == GL_UNSIGNED_INT)
			glGetUniformuiv(prog, loc, k[nk].v.u);
		else
			continue; /* samplers and images: their binding is in the source */
		nk++;
	}
	return nk;
}

static GLenum active_type(GLuint prog, const char *name)
{
	GLint n = 0;
	glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &n);
	for (GLuint i = 0; i < (GLuint)n; i++) {
		char nm[64];
		GLint size = 0;
		GLenum type = 0;
		glGetActiveUniform(prog, i, sizeof(nm), NULL, &size, &type, nm);
		if (!strcmp(nm, name))
			return size == 1 ? type : 0;
	}
	return 0;
}

static void restore_uniforms(GLuint prog, const struct kept *k, int nk)
{
	for (int j = 0; j < nk; j++) {
		GLint loc = glGetUniformLocation(prog, k[j].name);
		if (loc < 0 || active_type(prog, k[j].name) != k[j].type)
			continue; /* no longer used, or changed by the edit */
		const struct kept *e = &k[j];
		switch (e->type) {
		case GL_FLOAT: glProgramUniform1fv(prog, loc, 1, e->v.f); break;
		case GL_FLOAT_VEC2: glProgramUniform2fv(prog, loc, 1, e->v.f); break;
		case GL_FLOAT_VEC3: glProgramUniform3fv(prog, loc, 1, e->v.f); break;
		case GL_FLOAT_VEC4: glProgramUniform4fv(prog, loc, 1, e->v.f); break;
		case GL_FLOAT_MAT4: glProgramUniformMatrix4fv(prog, loc, 1, GL_FALSE, e->v.f); break;
		case GL_INT: case GL_BOOL: glProgramUniform1iv(prog, loc, 1, e->v.i); break;
		case GL_INT_VEC2: glProgramUniform2iv(prog, loc, 1, e->v.i); break;
		case GL_INT_VEC3: glProgramUniform3iv(prog, loc, 1, e->v.i); break;
		case GL_UNSIGNED_INT: glProgramUniform1uiv(prog, loc, 1, e->v.u); break;
		default: break;
		}
	}
}

/* Program r rebuilt from the files as they are now, moved into r->prog.
 * 0, or -1 with "file:line: message" in msg. */
static int rebuild(struct watched *r, char *msg, size_t msglen)
{
	struct shader_deps deps;
	GLuint tmp = shader_build(&r->d, &deps, msg, msglen);
	if (!tmp)
		return -1;
	GLuint sh[2], old[2];
	GLsizei n = 0, nold = 0;
	glGetAttachedShaders(tmp, 2, &n, sh);
	glGetAttachedShaders(r->prog, 2, &nold, old);
	static struct kept k[KEEP_MAX]; /* between frames, one rebuild at a time */
	int nk = keep_uniforms(r->prog, k);
	for (GLsizei i = 0; i < nold; i++)
		glDetachShader(r->prog, old[i]);
	for (GLsizei i = 0; i < n; i++)
		glAttachShader(r->prog, sh[i]);
	glLinkProgram(r->prog);
	uniform_cache_forget(r->prog); /* its uniforms may have moved */
	glDeleteProgram(tmp); /* its shaders live on in r->prog */
	GLint ok = 0;
	glGetProgramiv(r->prog, GL_LINK_STATUS, &ok);
	if (!ok || gpu_check("live shader rebuild") < 0) {
		snprintf(msg, msglen, "%s: relinking the rebuilt program failed", r->d.file[0]);
		return -1;
	}
	restore_uniforms(r->prog, k, nk);
	r->deps = deps;
	return 0;
}

static bool made_of(const struct watched *r, const char *name)
{
	for (int i = 0; i < r->deps.n; i++)
		if (!strcmp(r->deps.names[i], name))
			return true;
	return false;
}

/* The names of the files saved since the last call, '\n'-separated. */
static int saved_files(struct shader_watch *w, char *names, size_t len)
{
	size_t used = 0;
	names[0] = 0;
	char buf[4096] __attribute__((aligned(__alignof__(struct inotify_event))));
	for (;;) {
		ssize_t got = read(w->fd, buf, sizeof(buf));
		if (got < 0 && errno == EINTR)
			continue;
		if (got < 0 && errno == EAGAIN)
			return 0;
		if (got <= 0) {
			log_warn("live shader editing: reading inotify events: %s", got < 0 ? strerror(errno) : "end of file");
			return -1;
		}
		for (char *p = buf; p < buf + got;) {
			const struct inotify_event *ev = (const struct inotify_event *)(void *)p;
			if (ev->len && ev->name[0]) {
				int k = snprintf(names + used, len - used, "%s\n", ev->name);
				if (k > 0 && (size_t)k < len - used)
					used += (size_t)k;
			}
			p += sizeof(struct inotify_event) + ev->len;
		}
	}
}

int shader_watch_poll(struct shader_watch *w, char *msg, size_t msglen)
{
	msg[0] = 0;
	if (!w)
		return 0;
	char names[4096];
	if (saved_files(w, names, sizeof(names)) < 0 || !names[0])
		return 0;
	int rebuilt = 0, failed = 0;
	for (int i = 0; i < w->n; i++) {
		struct watched *r = &w->progs[i];
		bool hit = false;
		for (char *s = names, *nl; !hit && (nl = strchr(s, '\n')); s = nl + 1) {
			*nl = 0;
			hit = made_of(r, s);
			*nl = '\n';
		}
		if (!hit)
			continue;
		if (!glIsProgram(r->prog)) { /* deleted by its owner */
			drop(w, i--);
			continue;
		}
		char e[1024];
		if (rebuild(r, e, sizeof(e)) < 0) {
			if (!failed++)
				snprintf(msg, msglen, "%s", e);
			continue;
		}
		rebuilt++;
	}
	rebuilt_total += (unsigned long)rebuilt;
	if (rebuilt)
		log_info("live shader editing: %d program(s) rebuilt", rebuilt);
	return failed ? -1 : rebuilt;
}
