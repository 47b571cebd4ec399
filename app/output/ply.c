/* isoterra — binary little-endian PLY (x y z nx ny nz float; uchar/uint
 * triangle lists).  Bytes are encoded explicitly, so big-endian hosts write
 * the same file. */
#include "ply.h"
#include "core.h"

#include <errno.h>
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>


#define PLY_VERTEX_BYTES 24u /* 6 float32 */
#define FACE_BYTES 13u   /* uchar 3 + 3 uint32 */
#define HEADER_MAX 4096
#define CHUNK 1024u      /* vertices or faces per fwrite/fread */

/* ---- little-endian encoding ---------------------------------------------- */

static void put_u32(uint8_t *b, uint32_t v)
{
	b[0] = (uint8_t)v;
	b[1] = (uint8_t)(v >> 8);
	b[2] = (uint8_t)(v >> 16);
	b[3] = (uint8_t)(v >> 24);
}

static void put_f32(uint8_t *b, float f)
{
	uint32_t v;
	memcpy(&v, &f, 4);
	put_u32(b, v);
}

static uint32_t get_u32(const uint8_t *b)
{
	return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static float get_f32(const uint8_t *b)
{
	uint32_t v = get_u32(b);
	float f;
	memcpy(&f, &v, 4);
	return f;
}

/* ---- write --------------------------------------------------------------- */

int ply_write_staged(const struct mesh *m, const char *path, struct atomic_file *af, char *err, size_t errlen)
{
	af->f = NULL;
	af->tmp = NULL;
	if ((m->nverts && (!m->pos || !m->nrm)) || (m->ntris && !m->idx)) {
		snprintf(err, errlen, "cannot write '%s': mesh has no data", path);
		return -1;
	}
	for (uint32_t t = 0; t < m->ntris; t++)
		for (int k = 0; k < 3; k++)
			if (m->idx[3 * (size_t)t + k] >= m->nverts) {
				snprintf(err, errlen, "cannot write '%s': triangle %" PRIu32 " references vertex %" PRIu32
				         " of %" PRIu32, path, t, m->idx[3 * (size_t)t + k], m->nverts);
				return -1;
			}

	if (atomic_open(af, path, err, errlen) < 0)
		return -1;
	bool ok = fprintf(af->f,
	                  "ply\n"
	                  "format binary_little_endian 1.0\n"
	                  "comment isoterra\n"
	                  "element vertex %" PRIu32 "\n"
	                  "property float x\n"
	                  "property float y\n"
	                  "property float z\n"
	                  "property float nx\n"
	                  "property float ny\n"
	                  "property float nz\n"
	                  "element face %" PRIu32 "\n"
	                  "property list uchar uint vertex_indices\n"
	                  "end_header\n",
	                  m->nverts, m->ntris) > 0;

	uint8_t buf[CHUNK * PLY_VERTEX_BYTES];
	size_t used = 0;
	for (uint32_t v = 0; ok && v < m->nverts; v++) {
		for (int k = 0; k < 3; k++) {
			put_f32(buf + used + 4 * k, m->pos[3 * (size_t)v + k]);
			put_f32(buf + used + 12 + 4 * k, m->nrm[3 * (size_t)v + k]);
		}
		used += PLY_VERTEX_BYTES;
		if (used + PLY_VERTEX_BYTES > sizeof(buf)) {
			ok = fwrite(buf, 1, used, af->f) == used;
			used = 0;
		}
	}
	for (uint32_t t = 0; ok && t < m->ntris; t++) {
		buf[used] = 3;
		for (int k = 0; k < 3; k++)
			put_u32(buf + used + 1 + 4 * k, m->idx[3 * (size_t)t + k]);
		used += FACE_BYTES;
		if (used + FACE_BYTES > sizeof(buf)) {
			ok = fwrite(buf, 1, used, af->f) == used;
			used = 0;
		}
	}
	if (ok && used)
		ok = fwrite(buf, 1, used, af->f) == used;
	if (!ok) {
		snprintf(err, errlen, "cannot write '%s': %s", path, strerror(errno ? errno : EIO));
		atomic_abort(af);
		return -1;
	}
	return atomic_close(af, path, err, errlen);
}

int ply_write(const struct mesh *m, const char *path, char *err, size_t errlen)
{
	struct atomic_file af;
	if (ply_write_staged(m, path, &af, err, errlen) < 0)
		return -1;
	return atomic_commit(&af, path, err, errlen);
}

/* ---- read ---------------------------------------------------------------- */

/* Next header line (without '\n') into line; 0, or -1 at EOF / overlong. */
static int header_line(FILE *f, char *line, size_t len, size_t *total)
{
	size_t n = 0;
	for (;;) {
		int c = fgetc(f);
		if (c == EOF)
			return -1;
		if (++*total > HEADER_MAX)
			return -1;
		if (c == '\n')
			break;
		if (n + 1 >= len)
			return -1;
		line[n++] = (char)c;
	}
	if (n && line[n - 1] == '\r')
		n--;
	line[n] = 0;
	return 0;
}

static int parse_count(const char *s, uint32_t *out)
{
	char *end;
	errno = 0;
	if (*s < '0' || *s > '9')
		return -1;
	unsigned long long v = strtoull(s, &end, 10);
	if (errno || *end || v > UINT32_MAX)
		return -1;
	*out = (uint32_t)v;
	return 0;
}

/* line is "kw" or starts with "kw ". */
static bool is_keyword(const char *line, const char *kw)
{
	size_t n = strlen(kw);
	return strncmp(line, kw, n) == 0 && (line[n] == ' ' || line[n] == 0);
}

/* The header ply_write produces; comments / obj_info may appear anywhere. */
static const char *const expected[] = {
	"ply",
	"format binary_little_endian 1.0",
	"element vertex %",
	"property float x",
	"property float y",
	"property float z",
	"property float nx",
	"property float ny",
	"property float nz",
	"element face %",
	"property list uchar uint vertex_indices",
	"end_header",
};

static int read_header(FILE *f, const char *path, uint32_t *nv, uint32_t *nf, char *err, size_t errlen)
{
	char line[256];
	size_t total = 0;
	for (size_t i = 0; i < ARRAY_SIZE(expected);) {
		if (header_line(f, line, sizeof(line), &total) < 0) {
			if (i == 0)
				snprintf(err, errlen, "'%s' is not a PLY file", path);
			else
				snprintf(err, errlen, "'%s': truncated or malformed PLY header", path);
			return -1;
		}
		if (i == 0 && strcmp(line, "ply") != 0) {
			snprintf(err, errlen, "'%s' is not a PLY file", path);
			return -1;
		}
		if (i > 0 && (is_keyword(line, "comment") || is_keyword(line, "obj_info")))
			continue;
		const char *e = expected[i];
		const char *pct = strchr(e, '%');
		bool match;
		if (pct) {
			size_t pre = (size_t)(pct - e);
			match = strncmp(line, e, pre) == 0 &&
			        parse_count(line + pre, i == 2 ? nv : nf) == 0;
		} else {
			match = strcmp(line, e) == 0;
		}
		if (!match) {
			if (i == 1 && strncmp(line, "format ", 7) == 0)
				snprintf(err, errlen, "'%s': PLY %s not supported (only binary_little_endian 1.0)",
				         path, line);
			else
				snprintf(err, errlen, "'%s': unsupported PLY header line '%s' (expected '%s')", path,
				         line, e);
			return -1;
		}
		i++;
	}
	return 0;
}

/* The nf triangles of the body into m->idx: 0, -1 on a short read, -2 (with
 * err) on a face that is not a triangle or names a vertex past nv. */
static int read_faces(FILE *f, struct mesh *m, uint32_t nv, uint32_t nf, const char *path, char *err, size_t errlen)
{
	uint8_t buf[CHUNK * FACE_BYTES];
	int rc = 0;
	for (uint32_t t = 0; t < nf && rc == 0;) {
		uint32_t chunk = nf - t < CHUNK ? nf - t : CHUNK;
		if (fread(buf, FACE_BYTES, chunk, f) != chunk) {
			rc = -1;
			break;
		}
		for (uint32_t i = 0; i < chunk; i++, t++) {
			const uint8_t *b = buf + i * FACE_BYTES;
			if (b[0] != 3) {
				snprintf(err, errlen, "'%s': face %" PRIu32 " has %u vertices (only triangles supported)",
				         path, t, (unsigned)b[0]);
				rc = -2;
				break;
			}
			for (int k = 0; k < 3; k++) {
				uint32_t idx = get_u32(b + 1 + 4 * k);
				if (idx >= nv) {
					snprintf(err, errlen, "'%s': face %" PRIu32 " references vertex %" PRIu32
					         " of %" PRIu32, path, t, idx, nv);
					rc = -2;
					break;
				}
				m->idx[3 * (size_t)t + k] = idx;
			}
			if (rc)
				break;
		}
	}
	return rc;
}

int ply_read(struct mesh *m, const char *path, char *err, size_t errlen)
{
	memset(m, 0, sizeof(*m));
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "cannot open '%s': %s", path, strerror(errno));
		return -1;
	}
	uint32_t nv = 0, nf = 0;
	if (read_header(f, path, &nv, &nf, err, errlen) < 0) {
		fclose(f);
		return -1;
	}
	/* The body must be exactly nv vertices and nf triangles. */
	long start = ftell(f);
	struct stat st;
	if (start < 0 || fstat(fileno(f), &st) < 0) {
		snprintf(err, errlen, "cannot read '%s': %s", path, strerror(errno));
		fclose(f);
		return -1;
	}
	uint64_t want = (uint64_t)nv * PLY_VERTEX_BYTES + (uint64_t)nf * FACE_BYTES;
	uint64_t have = (uint64_t)st.st_size - (uint64_t)start;
	if (have != want) {
		snprintf(err, errlen, "'%s': %s PLY body (%" PRIu64 " bytes, %" PRIu32 " vertices and %" PRIu32
		         " faces need %" PRIu64 ")", path, have < want ? "truncated" : "oversized", have, nv, nf, want);
		fclose(f);
		return -1;
	}
	if (mesh_alloc(m, nv, nf) < 0) {
		snprintf(err, errlen, "out of memory reading '%s'", path);
		fclose(f);
		return -1;
	}
	uint8_t buf[CHUNK * PLY_VERTEX_BYTES];
	int rc = 0;
	for (uint32_t v = 0; v < nv && rc == 0;) {
		uint32_t chunk = nv - v < CHUNK ? nv - v : CHUNK;
		if (fread(buf, PLY_VERTEX_BYTES, chunk, f) != chunk) {
			rc = -1;
			break;
		}
		for (uint32_t i = 0; i < chunk; i++, v++)
			for (int k = 0; k < 3; k++) {
				m->pos[3 * (size_t)v + k] = get_f32(buf + i * PLY_VERTEX_BYTES + 4 * k);
				m->nrm[3 * (size_t)v + k] = get_f32(buf + i * PLY_VERTEX_BYTES + 12 + 4 * k);
			}
	}
	if (rc == 0)
		rc = read_faces(f, m, nv, nf, path, err, errlen);
	if (rc == -1)
		snprintf(err, errlen, "cannot read '%s': %s", path, ferror(f) ? strerror(errno) : "unexpected end of file");
	fclose(f);
	if (rc) {
		mesh_free(m);
		return -1;
	}
	return 0;
}
