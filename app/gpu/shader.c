/* isoterra — shader loader: embedded or on-disk sources, host-side
 * #include expansion, file:line error reports; every program it builds is
 * noted with the live-editing watcher (shader_watch.c) when one is open. */
#include "gpu.h"
#include "gpu_int.h"
#include "gl_limits.h"
#include "core.h"
#include "shader_int.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char shader_dir[PARAM_STR_MAX];

void shader_set_dir(const char *dir)
{
	snprintf(shader_dir, sizeof(shader_dir), "%s", dir ? dir : "");
}

static const char *embedded_text(const char *name)
{
	for (size_t i = 0; i < embedded_shader_count; i++)
		if (!strcmp(embedded_shaders[i].name, name))
			return embedded_shaders[i].text;
	return NULL;
}

char *shader_read(const char *name, char *err, size_t errlen)
{
	if (!shader_dir[0]) {
		const char *text = embedded_text(name);
		if (text)
			return strdup(text);
		snprintf(err, errlen, "shader '%s' is not embedded in this binary", name);
		return NULL;
	}
	char path[PARAM_STR_MAX * 2];
	snprintf(path, sizeof(path), "%s/%s", shader_dir, name);
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "cannot open shader '%s': %s", path, strerror(errno));
		return NULL;
	}
	if (fseek(f, 0, SEEK_END) != 0) {
		fclose(f);
		snprintf(err, errlen, "cannot read shader '%s'", path);
		return NULL;
	}
	long n = ftell(f);
	if (n < 0 || n > (1 << 22) || fseek(f, 0, SEEK_SET) != 0) {
		fclose(f);
		snprintf(err, errlen, "cannot read shader '%s' (size)", path);
		return NULL;
	}
	char *buf = malloc((size_t)n + 1);
	if (!buf || fread(buf, 1, (size_t)n, f) != (size_t)n) {
		free(buf);
		fclose(f);
		snprintf(err, errlen, "cannot read shader '%s'", path);
		return NULL;
	}
	fclose(f);
	buf[n] = 0;
	return buf;
}

/* ---- source assembly ------------------------------------------------ */

#define MAX_FILES 32

struct srcbuf {
	char *s;
	size_t len, cap;
	int nfiles;
	char names[MAX_FILES][64]; /* source-string number (the "#line N id" of each file) -> file name */
};

static int sb_add(struct srcbuf *b, const char *s, size_t n)
{
	if (b->len + n + 1 > b->cap) {
		size_t nc = b->cap ? b->cap : 16384;
		while (nc < b->len + n + 1)
			nc *= 2;
		char *ns = realloc(b->s, nc);
		if (!ns)
			return -1;
		b->s = ns;
		b->cap = nc;
	}
	memcpy(b->s + b->len, s, n);
	b->len += n;
	b->s[b->len] = 0;
	return 0;
}

static int sb_printf(struct srcbuf *b, const char *fmt, int a, int c)
{
	char tmp[64];
	int n = snprintf(tmp, sizeof(tmp), fmt, a, c);
	return sb_add(b, tmp, (size_t)n);
}

static int expand(struct srcbuf *b, const char *name, int depth, char *err, size_t errlen)
{
	if (depth > 8) {
		snprintf(err, errlen, "%s: #include nested too deeply", name);
		return -1;
	}
	for (int i = 1; i < b->nfiles; i++)
		if (!strcmp(b->names[i], name))
			return 0; /* each file once per program */
	if (b->nfiles >= MAX_FILES) {
		snprintf(err, errlen, "%s: too many #include files", name);
		return -1;
	}
	int id = b->nfiles++;
	snprintf(b->names[id], sizeof(b->names[id]), "%s", name);
	char *text = shader_read(name, err, errlen);
	if (!text)
		return -1;
	/* the file's lines count from id * SHADER_LINE_BASE (shader_int.h) */
	int base = id * SHADER_LINE_BASE;
	int rc = sb_printf(b, "#line %d %d\n", base + 1, id);
	int lineno = 0;
	for (char *line = text; rc == 0 && line && *line;) {
		char *nl = strchr(line, '\n');
		size_t n = nl ? (size_t)(nl - line) + 1 : strlen(line);
		if (++lineno >= SHADER_LINE_BASE) {
			snprintf(err, errlen, "%s: more than %d lines", name, SHADER_LINE_BASE - 1);
			free(text);
			return -1;
		}
		char *p = line;
		while (*p == ' ' || *p == '\t')
			p++;
		if (!strncmp(p, "#include", 8)) {
			char *q1 = strchr(p, '"');
			char *q2 = q1 ? strchr(q1 + 1, '"') : NULL;
			if (!q1 || !q2 || (nl && q2 > nl) || q2 - q1 - 1 >= 63) {
				snprintf(err, errlen, "%s:%d: malformed #include (use #include \"file\")", name, lineno);
				free(text);
				return -1;
			}
			char inc[64];
			snprintf(inc, sizeof(inc), "%.*s", (int)(q2 - q1 - 1), q1 + 1);
			char e2[512];
			if (expand(b, inc, depth + 1, e2, sizeof(e2)) < 0) {
				snprintf(err, errlen, "%s:%d: %s", name, lineno, e2);
				free(text);
				return -1;
			}
			rc = sb_printf(b, "#line %d %d\n", base + lineno + 1, id);
		} else {
			rc = sb_add(b, line, n);
			if (rc == 0 && !nl)
				rc = sb_add(b, "\n", 1);
		}
		line = nl ? nl + 1 : NULL;
	}
	free(text);
	if (rc < 0)
		snprintf(err, errlen, "%s: out of memory", name);
	return rc;
}

static int assemble(struct srcbuf *b, const char *stage_define, const char *file, const char *defines, char *err,
		    size_t errlen)
{
	memset(b, 0, sizeof(*b));
	snprintf(b->names[0], sizeof(b->names[0]), "<prelude>");
	b->nfiles = 1;
	enum { DECLS_MAX = 16384 };
	char *decls = malloc(DECLS_MAX);
	if (!decls || params_glsl_decls(decls, DECLS_MAX) < 0) {
		snprintf(err, errlen, decls ? "parameter declarations too long" : "out of memory");
		free(decls);
		return -1;
	}
	const char *head = "#version 310 es\n"
			   "precision highp float;\nprecision highp int;\n"
			   "precision highp sampler3D;\nprecision highp usampler3D;\n"
			   "precision highp image3D;\n";
	/* the host/shader contract (app/gpu/abi.h) always comes from the copy
	 * this binary was compiled with, even with --shader-dir */
	const char *abi = embedded_text("abi.h");
	if (!abi) {
		snprintf(err, errlen, "abi.h is not embedded in this binary");
		free(decls);
		return -1;
	}
	/* the caller's defines come first: they may specialize parameters */
	int rc = sb_add(b, head, strlen(head)) || sb_add(b, abi, strlen(abi)) ||
		 sb_add(b, stage_define, strlen(stage_define)) || (defines && sb_add(b, defines, strlen(defines))) ||
		 sb_add(b, decls, strlen(decls));
	free(decls);
	if (rc) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	return expand(b, file, 0, err, errlen);
}

/* The compile log's line worth reporting, as "file:line: message" against
 * the program's file table (shader_log.c reads every vendor's format). */
static void format_log(const struct srcbuf *b, const char *log, const char *fallback, char *err, size_t errlen)
{
	const char *files[MAX_FILES];
	for (int i = 0; i < b->nfiles; i++)
		files[i] = b->names[i];
	shader_log_format(log, log ? strlen(log) : 0, files, b->nfiles, fallback, err, errlen);
}

static GLuint compile(GLenum type, const struct srcbuf *b, const char *file, char *err, size_t errlen)
{
	GLuint sh = glCreateShader(type);
	if (!sh) {
		snprintf(err, errlen, "%s: glCreateShader failed (0x%x)", file, glGetError());
		return 0;
	}
	const char *src = b->s;
	glShaderSource(sh, 1, &src, NULL);
	glCompileShader(sh);
	GLint ok = 0;
	glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
	if (!ok) {
		GLint len = 0;
		glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
		char *log = calloc(1, (size_t)(len > 0 ? len : 1) + 1);
		if (log)
			glGetShaderInfoLog(sh, len, NULL, log);
		format_log(b, log ? log : "(no log)", file, err, errlen);
		if (log && log_get_level() >= LOG_DEBUG)
			log_debug("full compile log of %s:\n%s", file, log);
		free(log);
		glDeleteShader(sh);
		sh = 0;
	}
	return sh;
}

static GLuint link(GLuint *shaders, int n, const char *what, char *err, size_t errlen)
{
	GLuint prog = glCreateProgram();
	if (!prog) {
		snprintf(err, errlen, "%s: glCreateProgram failed", what);
		for (int i = 0; i < n; i++)
			glDeleteShader(shaders[i]);
		return 0;
	}
	for (int i = 0; i < n; i++)
		glAttachShader(prog, shaders[i]);
	glProgramParameteri(prog, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
	glLinkProgram(prog);
	for (int i = 0; i < n; i++)
		glDeleteShader(shaders[i]);
	GLint ok = 0;
	glGetProgramiv(prog, GL_LINK_STATUS, &ok);
	if (!ok) {
		char log[1024] = "";
		glGetProgramInfoLog(prog, sizeof(log), NULL, log);
		char *nl = strchr(log, '\n');
		if (nl && nl[1] == 0)
			*nl = 0;
		snprintf(err, errlen, "%s: link failed: %s", what, log);
		glDeleteProgram(prog);
		return 0;
	}
	return prog;
}

/* ---- programs issued ahead ----------------------------------------------
 * gpu_prefetch_*() issues a program's compile and link and returns at once;
 * build() later takes it by its sources.  A driver with
 * KHR_parallel_shader_compile (gpu.c turns its threads on) builds the
 * issued programs on its own threads meanwhile, so a scene's programs
 * compile side by side instead of one after another; elsewhere the work
 * is the same as building each when asked.  Nothing is checked at issue:
 * a program that fails is built again by build(), which reports it. */
#define PREFETCH_MAX 32
struct prefetched {
	uint64_t src_key;  /* the assembled sources' hash */
	GLuint prog;
	bool from_cache;   /* loaded from the binary cache: linked already */
	uint64_t cache_key[2];
};
static struct prefetched prefetch_tab[PREFETCH_MAX];
static int prefetch_n;

static uint64_t src_hash(const char *const *src, int n)
{
	uint64_t h = 0xcbf29ce484222325ull;
	for (int i = 0; i < n; i++) {
		for (const unsigned char *c = (const unsigned char *)src[i]; *c; c++)
			h = (h ^ *c) * 0x100000001b3ull;
		h = (h ^ 0xff) * 0x100000001b3ull; /* stage separator */
	}
	return h;
}

/* The issued program of these sources (taken out of the table), or NULL. */
static bool prefetch_take(uint64_t key, struct prefetched *out)
{
	for (int i = 0; i < prefetch_n; i++)
		if (prefetch_tab[i].src_key == key) {
			*out = prefetch_tab[i];
			prefetch_tab[i] = prefetch_tab[--prefetch_n];
			return true;
		}
	return false;
}

/* The program's use, as the driver counts it, against the GL limits
 * (gl_limits.h); messages name it by its files and its switches (the
 * #defines set to 1 that are no parameter term), e.g. "density.comp
 * (FIELD_PASS_VERTICES WITH_AO)". */
static int check_limits(GLuint prog, const struct shader_desc *d, char *err, size_t errlen)
{
	char what[192];
	int n = snprintf(what, sizeof(what), "%s%s%s", d->file[0], d->compute ? "" : " + ", d->compute ? "" : d->file[1]);
	const char *s = d->defines;
	bool open = false;
	while (s && *s && n > 0 && (size_t)n < sizeof(what) - 40) {
		const char *eol = strchr(s, '\n');
		size_t len = eol ? (size_t)(eol - s) : strlen(s);
		char name[64];
		if (sscanf(s, "#define %63s 1", name) == 1 && len > 10 && !strncmp(s + len - 2, " 1", 2) &&
		    strncmp(name, "TERM_", 5) && strncmp(name, "HAS_", 4)) {
			n += snprintf(what + n, sizeof(what) - (size_t)n, "%s%s", open ? " " : " (", name);
			open = true;
		}
		s = eol ? eol + 1 : s + len;
	}
	if (open && n > 0 && (size_t)n < sizeof(what) - 1)
		snprintf(what + n, sizeof(what) - (size_t)n, ")");
	return gl_limits_check_program(prog, d->compute, what, err, errlen);
}

/* A program from d's stages: sources assembled (deps, if not NULL, gets
 * the files), then, with use_cache, the binary cache tried, else the
 * driver compiles and links (and the cache keeps the result). */
static GLuint build(const struct shader_desc *d, struct shader_deps *deps, bool use_cache, char *err, size_t errlen)
{
	static const GLenum types[3] = { GL_COMPUTE_SHADER, GL_VERTEX_SHADER, GL_FRAGMENT_SHADER };
	static const char *const stages[3] = { "#define STAGE_COMPUTE 1\n", "#define STAGE_VERTEX 1\n",
					       "#define STAGE_FRAGMENT 1\n" };
	int n = d->compute ? 1 : 2, first = d->compute ? 0 : 1;
	struct srcbuf b[2];
	memset(b, 0, sizeof(b));
	GLuint prog = 0;
	int made = 0;
	if (deps)
		deps->n = 0;
	for (; made < n; made++) {
		if (assemble(&b[made], stages[first + made], d->file[made], d->defines, err, errlen) < 0)
			goto out;
		for (int i = 1; deps && i < b[made].nfiles && deps->n < SHADER_MAX_DEPS; i++)
			snprintf(deps->names[deps->n++], sizeof(deps->names[0]), "%s", b[made].names[i]);
	}
	const char *src[2] = { b[0].s, n > 1 ? b[1].s : NULL };
	uint64_t key[2] = { 0, 0 };
	struct prefetched pf;
	if (use_cache && prefetch_take(src_hash(src, n), &pf)) {
		GLint ok = pf.from_cache;
		if (!ok)
			glGetProgramiv(pf.prog, GL_LINK_STATUS, &ok); /* waits for the driver's thread */
		if (ok) {
			prog = pf.prog;
			if (!pf.from_cache)
				program_cache_store(prog, pf.cache_key);
			goto out;
		}
		glDeleteProgram(pf.prog); /* built again below, for its message */
	}
	if (use_cache && (prog = program_cache_load(src, n, key)) != 0)
		goto out;
	GLuint sh[2] = { 0, 0 };
	for (int i = 0; i < n; i++) {
		sh[i] = compile(types[first + i], &b[i], d->file[i], err, errlen);
		if (!sh[i]) {
			while (i-- > 0)
				glDeleteShader(sh[i]);
			goto out;
		}
	}
	prog = link(sh, n, d->file[0], err, errlen);
	if (prog && use_cache)
		program_cache_store(prog, key);
out:
	if (prog)
		uniform_cache_forget(prog); /* a new program, perhaps a deleted one's name */
	if (prog && check_limits(prog, d, err, errlen) < 0) {
		glDeleteProgram(prog);
		prog = 0;
	}
	for (int i = 0; i < n && i <= made; i++)
		free(b[i].s);
	return prog;
}

/* The watcher's rebuilds need the program's shaders attached: never from
 * the binary cache. */
GLuint shader_build(const struct shader_desc *d, struct shader_deps *deps, char *err, size_t errlen)
{
	return build(d, deps, false, err, errlen);
}

/* Builds the program (through the binary cache) and notes it with the
 * watcher (live editing). */
static GLuint build_noted(const struct shader_desc *d, char *err, size_t errlen)
{
	struct shader_deps deps;
	GLuint prog = build(d, &deps, true, err, errlen);
	if (prog)
		shader_watch_note(prog, d, &deps);
	return prog;
}

GLuint gpu_compute_program(const char *file, const char *defines, char *err, size_t errlen)
{
	struct shader_desc d = { .compute = true, .defines = defines };
	snprintf(d.file[0], sizeof(d.file[0]), "%s", file);
	return build_noted(&d, err, errlen);
}

GLuint gpu_graphics_program(const char *vs_file, const char *fs_file, const char *defines, char *err, size_t errlen)
{
	struct shader_desc d = { .compute = false, .defines = defines };
	snprintf(d.file[0], sizeof(d.file[0]), "%s", vs_file);
	snprintf(d.file[1], sizeof(d.file[1]), "%s", fs_file);
	return build_noted(&d, err, errlen);
}

/* Issues d's program (see "programs issued ahead" above). */
static void prefetch(const struct shader_desc *d)
{
	static const GLenum types[3] = { GL_COMPUTE_SHADER, GL_VERTEX_SHADER, GL_FRAGMENT_SHADER };
	static const char *const stages[3] = { "#define STAGE_COMPUTE 1\n", "#define STAGE_VERTEX 1\n",
					       "#define STAGE_FRAGMENT 1\n" };
	if (prefetch_n >= PREFETCH_MAX)
		return;
	int n = d->compute ? 1 : 2, first = d->compute ? 0 : 1, made = 0;
	struct srcbuf b[2];
	memset(b, 0, sizeof(b));
	char err[256];
	for (; made < n; made++)
		if (assemble(&b[made], stages[first + made], d->file[made], d->defines, err, sizeof(err)) < 0)
			goto out; /* build() reports it */
	const char *src[2] = { b[0].s, n > 1 ? b[1].s : NULL };
	struct prefetched pf = { .src_key = src_hash(src, n) };
	for (int i = 0; i < prefetch_n; i++)
		if (prefetch_tab[i].src_key == pf.src_key)
			goto out; /* issued already */
	pf.prog = program_cache_load(src, n, pf.cache_key);
	pf.from_cache = pf.prog != 0;
	if (!pf.prog && (pf.prog = glCreateProgram()) != 0) {
		for (int i = 0; i < n; i++) {
			GLuint sh = glCreateShader(types[first + i]);
			if (!sh)
				continue;
			glShaderSource(sh, 1, &src[i], NULL);
			glCompileShader(sh);
			glAttachShader(pf.prog, sh);
			glDeleteShader(sh); /* freed with the program */
		}
		glProgramParameteri(pf.prog, GL_PROGRAM_BINARY_RETRIEVABLE_HINT, GL_TRUE);
		glLinkProgram(pf.prog); /* no status asked: the driver may go on in the background */
	}
	if (pf.prog)
		prefetch_tab[prefetch_n++] = pf;
out:
	for (int i = 0; i < n && i <= made && i < 2; i++)
		free(b[i].s);
}

void gpu_prefetch_compute(const char *file, const char *defines)
{
	struct shader_desc d = { .compute = true, .defines = defines };
	snprintf(d.file[0], sizeof(d.file[0]), "%s", file);
	prefetch(&d);
}

void gpu_prefetch_graphics(const char *vs_file, const char *fs_file, const char *defines)
{
	struct shader_desc d = { .compute = false, .defines = defines };
	snprintf(d.file[0], sizeof(d.file[0]), "%s", vs_file);
	snprintf(d.file[1], sizeof(d.file[1]), "%s", fs_file);
	prefetch(&d);
}

void gpu_prefetch_drop(void)
{
	for (int i = 0; i < prefetch_n; i++)
		glDeleteProgram(prefetch_tab[i].prog);
	prefetch_n = 0;
}

