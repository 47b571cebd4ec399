/* isoterra — the program binary cache: linked programs kept on disk
 * (glGetProgramBinary / glProgramBinary) so a start does not compile.
 *
 * One file per program in $XDG_CACHE_HOME/isoterra (else ~/.cache/isoterra),
 * named by a 128-bit hash of the driver (GL_RENDERER, GL_VERSION,
 * GL_SHADING_LANGUAGE_VERSION) and of every stage's full source text (the
 * prelude with the parameter declarations, the defines and the expanded
 * #includes).  A file is never trusted: its header must carry this driver's
 * strings and this key, its payload must match the stored length and
 * checksum, and the driver must link it; otherwise it is ignored, the
 * program is compiled and the file rewritten (temp file + rename). */
#include "gpu.h"
#include "gpu_int.h"
#include "core.h"

#include <dirent.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#define MAGIC "ISOTPRG1"
#define MAX_BINARY (64u << 20) /* larger payloads are not cached */
#define MAX_FILES 256          /* the oldest entries go beyond this: a kiosk's disk stays bounded */

struct file_header {
	char magic[8];
	uint64_t key[2];
	uint32_t format, length;
	uint64_t checksum;
	char renderer[128], version[128], glsl[64];
};

static struct {
	bool disabled;
	bool probed;
	bool usable; /* the driver offers a binary format and a dir exists */
	char dir[512];
	char renderer[128], version[128], glsl[64];
	struct gpu_program_cache_stats st;
} C;

void gpu_program_cache_config(bool enabled, const char *dir)
{
	memset(&C, 0, sizeof(C));
	C.disabled = !enabled;
	if (dir && *dir)
		snprintf(C.dir, sizeof(C.dir), "%s", dir);
}

struct gpu_program_cache_stats gpu_program_cache_stats(void)
{
	return C.st;
}

static void copy_gl_string(char *out, size_t n, GLenum name)
{
	const GLubyte *s = glGetString(name);
	snprintf(out, n, "%s", s ? (const char *)s : "");
}

bool gpu_program_cache_default_dir(char *out, size_t n)
{
	const char *x = getenv("XDG_CACHE_HOME");
	const char *home = getenv("HOME");
	int w;
	if (x && x[0] == '/')
		w = snprintf(out, n, "%s/isoterra", x);
	else if (home && home[0] == '/')
		w = snprintf(out, n, "%s/.cache/isoterra", home);
	else
		return false;
	return w > 0 && (size_t)w < n;
}

/* mkdir -p of the cache dir (its parent is made too, as XDG asks) */
static bool make_dir(const char *dir)
{
	char tmp[512];
	snprintf(tmp, sizeof(tmp), "%s", dir);
	for (char *p = tmp + 1; *p; p++) {
		if (*p != '/')
			continue;
		*p = 0;
		if (mkdir(tmp, 0700) < 0 && errno != EEXIST)
			return false;
		*p = '/';
	}
	return mkdir(tmp, 0700) == 0 || errno == EEXIST;
}

static bool probe(void)
{
	if (C.probed)
		return C.usable;
	C.probed = true;
	if (C.disabled)
		return false;
	GLint formats = 0;
	glGetIntegerv(GL_NUM_PROGRAM_BINARY_FORMATS, &formats);
	if (glGetError() != GL_NO_ERROR || formats < 1) {
		log_debug("program cache: the driver offers no program binary format");
		return false;
	}
	if (!C.dir[0] && !gpu_program_cache_default_dir(C.dir, sizeof(C.dir))) {
		log_debug("program cache: neither XDG_CACHE_HOME nor HOME is an absolute path");
		return false;
	}
	if (!make_dir(C.dir)) {
		log_debug("program cache: cannot create '%s': %s", C.dir, strerror(errno));
		return false;
	}
	copy_gl_string(C.renderer, sizeof(C.renderer), GL_RENDERER);
	copy_gl_string(C.version, sizeof(C.version), GL_VERSION);
	copy_gl_string(C.glsl, sizeof(C.glsl), GL_SHADING_LANGUAGE_VERSION);
	C.usable = true;
	return true;
}

/* FNV-1a, 64 bits, from a given basis (two bases give the 128-bit key) */
static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
	const unsigned char *p = data;
	for (size_t i = 0; i < n; i++) {
		h ^= p[i];
		h *= 0x100000001b3ull;
	}
	return h;
}

static uint64_t fnv_str(uint64_t h, const char *s)
{
	return fnv(h, s, strlen(s) + 1); /* with the terminator: "ab"+"c" != "a"+"bc" */
}

static void make_key(const char *const *sources, int n, uint64_t key[2])
{
	const uint64_t basis[2] = { 0xcbf29ce484222325ull, 0x84222325cbf29ce4ull };
	for (int k = 0; k < 2; k++) {
		uint64_t h = basis[k];
		h = fnv_str(h, C.renderer);
		h = fnv_str(h, C.version);
		h = fnv_str(h, C.glsl);
		h = fnv(h, &n, sizeof(n));
		for (int i = 0; i < n; i++)
			h = fnv_str(h, sources[i]);
		key[k] = h;
	}
}

static void key_path(const uint64_t key[2], char *out, size_t n)
{
	snprintf(out, n, "%s/%016llx%016llx.bin", C.dir, (unsigned long long)key[0], (unsigned long long)key[1]);
}

static bool header_ok(const struct file_header *h, const uint64_t key[2], long file_size)
{
	return !memcmp(h->magic, MAGIC, 8) && h->key[0] == key[0] && h->key[1] == key[1] &&
	       h->length > 0 && h->length <= MAX_BINARY &&
	       (long)(sizeof(*h) + h->length) == file_size && !strncmp(h->renderer, C.renderer, sizeof(h->renderer)) &&
	       !strncmp(h->version, C.version, sizeof(h->version)) && !strncmp(h->glsl, C.glsl, sizeof(h->glsl));
}

/* The file's payload, or NULL (missing, foreign, truncated or corrupt). */
static void *read_entry(const char *path, const uint64_t key[2], struct file_header *h)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	void *data = NULL;
	long size = -1;
	if (fseek(f, 0, SEEK_END) == 0)
		size = ftell(f);
	if (size > 0 && fseek(f, 0, SEEK_SET) == 0 && fread(h, sizeof(*h), 1, f) == 1 && header_ok(h, key, size)) {
		data = malloc(h->length);
		if (data && (fread(data, 1, h->length, f) != h->length ||
			     fnv(0xcbf29ce484222325ull, data, h->length) != h->checksum)) {
			free(data);
			data = NULL;
		}
	}
	fclose(f);
	if (!data)
		C.st.rejected++;
	return data;
}

static bool is_entry(const char *name)
{
	size_t n = strlen(name);
	return n == 36 && !strcmp(name + 32, ".bin") && strspn(name, "0123456789abcdef") == 32;
}

/* Removes the least recently written entries beyond MAX_FILES. */
static void trim(void)
{
	DIR *d = opendir(C.dir);
	if (!d)
		return;
	unsigned count = 0;
	char oldest[64] = "";
	time_t oldest_t = 0;
	struct dirent *e;
	while ((e = readdir(d))) {
		if (!is_entry(e->d_name))
			continue;
		count++;
		char path[640];
		struct stat sb;
		snprintf(path, sizeof(path), "%.511s/%.63s", C.dir, e->d_name);
		if (stat(path, &sb) == 0 && (!oldest[0] || sb.st_mtime < oldest_t)) {
			oldest_t = sb.st_mtime;
			snprintf(oldest, sizeof(oldest), "%.63s", e->d_name);
		}
	}
	closedir(d);
	if (count > MAX_FILES && oldest[0]) {
		char path[640];
		snprintf(path, sizeof(path), "%.511s/%.63s", C.dir, oldest);
		if (unlink(path) < 0)
			log_debug("program cache: cannot remove '%s': %s", path, strerror(errno));
	}
}

GLuint program_cache_load(const char *const *sources, int n, uint64_t key_out[2])
{
	if (!probe())
		return 0;
	make_key(sources, n, key_out);
	char path[640];
	key_path(key_out, path, sizeof(path));
	if (access(path, F_OK) != 0) {
		C.st.misses++;
		return 0;
	}
	struct file_header h;
	void *data = read_entry(path, key_out, &h);
	if (!data) {
		C.st.misses++;
		return 0;
	}
	GLuint prog = glCreateProgram();
	GLint ok = 0;
	if (prog) {
		glProgramBinary(prog, h.format, data, (GLsizei)h.length);
		glGetProgramiv(prog, GL_LINK_STATUS, &ok);
	}
	free(data);
	while (glGetError() != GL_NO_ERROR) {
		ok = 0; /* the driver refused the binary: not an error of the run */
	}
	if (!ok) {
		if (prog)
			glDeleteProgram(prog);
		C.st.rejected++;
		C.st.misses++;
		return 0;
	}
	C.st.hits++;
	return prog;
}

void program_cache_store(GLuint prog, const uint64_t key[2])
{
	if (!C.usable)
		return;
	GLint len = 0;
	glGetProgramiv(prog, GL_PROGRAM_BINARY_LENGTH, &len);
	if (glGetError() != GL_NO_ERROR || len <= 0 || (uint32_t)len > MAX_BINARY)
		return;
	struct file_header h;
	memset(&h, 0, sizeof(h));
	void *data = malloc((size_t)len);
	GLsizei got = 0;
	GLenum format = 0;
	if (data)
		glGetProgramBinary(prog, len, &got, &format, data);
	if (!data || glGetError() != GL_NO_ERROR || got <= 0) {
		free(data);
		return;
	}
	memcpy(h.magic, MAGIC, 8);
	h.key[0] = key[0];
	h.key[1] = key[1];
	h.format = format;
	h.length = (uint32_t)got;
	h.checksum = fnv(0xcbf29ce484222325ull, data, (size_t)got);
	snprintf(h.renderer, sizeof(h.renderer), "%s", C.renderer);
	snprintf(h.version, sizeof(h.version), "%s", C.version);
	snprintf(h.glsl, sizeof(h.glsl), "%s", C.glsl);
	char path[640], err[768] = "";
	key_path(key, path, sizeof(path));
	struct atomic_file af;
	if (atomic_open(&af, path, err, sizeof(err)) == 0) {
		if (fwrite(&h, sizeof(h), 1, af.f) == 1 && fwrite(data, 1, (size_t)got, af.f) == (size_t)got &&
		    atomic_commit(&af, path, err, sizeof(err)) == 0) {
			C.st.writes++;
			free(data);
			trim(); /* one out per one in keeps the bound */
			return;
		}
		if (af.f)
			atomic_abort(&af);
	}
	if (C.st.write_errors++ == 0) /* once: a read-only cache costs speed, nothing else */
		log_info("program cache: %s", err[0] ? err : "write failed");
	free(data);
}
