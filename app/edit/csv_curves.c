/* isoterra — curve input, CSV: a header line naming the columns
 * path,x,y,z[,kind,width,falloff,inclination,smoothing,surface] (any order, any
 * case), then one point a row, y up; a path's rows are consecutive, its
 * properties may be given on any of them but must not change.  Blank lines
 * and lines starting with '#' are skipped.  Errors name file:line. */
#include "curves.h"
#include "curves_internal.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

enum { COL_PATH, COL_X, COL_Y, COL_Z, COL_KIND, COL_WIDTH, COL_FALLOFF, COL_INCL, COL_SMOOTH, COL_SURFACE, NCOL };
static const char *const col_names[NCOL] = { "path", "x", "y", "z", "kind", "width", "falloff", "inclination",
					     "smoothing", "surface" };
#define MAX_FIELDS 32
#define MAX_ID 64

struct csv {
	const char *fname;
	char *err;
	size_t errlen;
	struct curve_set *s;
	int lineno;
	int col[NCOL];             /* field of each column, -1 when absent */
	bool surface_set;          /* the path's surface came from a cell */
	int nhead;                 /* fields in the header */
	bool have_header;
	struct curve_path cur;     /* the path being read */
	int cap;                   /* points cur.pts holds */
	int cur_line;              /* where it started */
	char cur_id[MAX_ID];
	bool set_prop[CURVE_NPARAMS]; /* parameters given on one of its rows */
	char (*ids)[MAX_ID];       /* every path id so far */
	int nids, ids_cap;
	int *slot;                 /* open-addressing table over ids: index + 1, 0 empty */
	size_t nslot;              /* a power of two, at least twice nids */
};

static int cfail(struct csv *c, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static int cfail(struct csv *c, int line, const char *fmt, ...)
{
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	snprintf(c->err, c->errlen, "%s:%d: %s", c->fname, line, msg);
	return -1;
}

static char *trim(char *s)
{
	while (*s == ' ' || *s == '\t')
		s++;
	char *e = s + strlen(s);
	while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r'))
		*--e = 0;
	return s;
}

static int split(char *line, char **f)
{
	int n = 0;
	for (char *p = line;; ) {
		char *c = strchr(p, ',');
		if (n >= MAX_FIELDS)
			return -1;
		if (c)
			*c = 0;
		f[n++] = trim(p);
		if (!c)
			break;
		p = c + 1;
	}
	return n;
}

static bool parse_num(const char *s, double *v)
{
	char *end;
	errno = 0;
	*v = strtod(s, &end);
	return *s && !*end && !errno && isfinite(*v);
}

static int csv_header(struct csv *c, char **f, int nf)
{
	for (int i = 0; i < nf; i++) {
		int col = -1;
		for (int k = 0; k < NCOL; k++)
			if (!strcasecmp(f[i], col_names[k]))
				col = k;
		if (col < 0)
			return cfail(c, c->lineno, "unknown column '%s' in the header (path,x,y,z[,kind,width,falloff,"
				     "inclination,smoothing])", f[i]);
		if (c->col[col] >= 0)
			return cfail(c, c->lineno, "column '%s' appears twice in the header", f[i]);
		c->col[col] = i;
	}
	for (int k = 0; k <= COL_Z; k++)
		if (c->col[k] < 0)
			return cfail(c, c->lineno, "the header has no '%s' column (needs path,x,y,z)", col_names[k]);
	c->nhead = nf;
	c->have_header = true;
	return 0;
}

/* Adds the path read so far (if any) to the set. */
static int csv_end_path(struct csv *c)
{
	if (c->cur.npts == 0)
		return 0;
	if (curve_path_dedup(&c->cur) < 2)
		return cfail(c, c->cur_line, "path '%s' needs at least 2 distinct points", c->cur_id);
	if (curve_set_add(c->s, &c->cur) < 0)
		return cfail(c, c->lineno, "out of memory");
	c->cur.npts = 0;
	return 0;
}

static size_t id_hash(const char *id)
{
	size_t h = 2166136261u; /* FNV-1a */
	for (; *id; id++)
		h = (h ^ (unsigned char)*id) * 16777619u;
	return h;
}

/* The table twice as large, every id placed again. */
static int grow_slots(struct csv *c)
{
	size_t n = c->nslot ? 2 * c->nslot : 64;
	int *ns = calloc(n, sizeof(*ns));
	if (!ns)
		return -1;
	for (int i = 0; i < c->nids; i++) {
		size_t k = id_hash(c->ids[i]) & (n - 1);
		while (ns[k])
			k = (k + 1) & (n - 1);
		ns[k] = i + 1;
	}
	free(c->slot);
	c->slot = ns;
	c->nslot = n;
	return 0;
}

/* Remembers a new path id: one seen before means the path's rows are not
 * consecutive (a hash table: linear in the number of paths). */
static int csv_new_id(struct csv *c, const char *id)
{
	if ((size_t)(c->nids + 1) * 2 > c->nslot && grow_slots(c) < 0)
		return cfail(c, c->lineno, "out of memory");
	size_t k = id_hash(id) & (c->nslot - 1);
	for (; c->slot[k]; k = (k + 1) & (c->nslot - 1))
		if (!strcmp(c->ids[c->slot[k] - 1], id))
			return cfail(c, c->lineno,
				     "rows of path '%s' continue after another path (a path's rows must be consecutive)", id);
	if (c->nids + 1 > c->ids_cap) {
		c->ids_cap = c->ids_cap ? 2 * c->ids_cap : 16;
		char(*ni)[MAX_ID] = realloc(c->ids, sizeof(*c->ids) * (size_t)c->ids_cap);
		if (!ni)
			return cfail(c, c->lineno, "out of memory");
		c->ids = ni;
	}
	snprintf(c->ids[c->nids], sizeof(c->ids[0]), "%s", id);
	c->slot[k] = ++c->nids;
	return 0;
}

/* The first row of a path: its id, its kind and the kind's defaults. */
static int csv_start_path(struct csv *c, char **f)
{
	const char *id = f[c->col[COL_PATH]];
	if (!*id)
		return cfail(c, c->lineno, "empty path id");
	if (strlen(id) >= sizeof(c->cur_id))
		return cfail(c, c->lineno, "path id longer than %zu characters", sizeof(c->cur_id) - 1);
	if (csv_new_id(c, id) < 0)
		return -1;
	snprintf(c->cur_id, sizeof(c->cur_id), "%s", id);
	c->cur_line = c->lineno;
	int kind = CURVE_ROAD;
	if (c->col[COL_KIND] >= 0 && *f[c->col[COL_KIND]]) {
		kind = curve_kind_parse(f[c->col[COL_KIND]]);
		if (kind < 0)
			return cfail(c, c->lineno, "kind '%s' is not road, river, railway, tunnel or bridge", f[c->col[COL_KIND]]);
	}
	float *pts = c->cur.pts;
	curve_path_defaults(&c->cur, kind);
	c->cur.pts = pts;
	c->surface_set = false;
	c->cur.npts = 0;
	snprintf(c->cur.label, sizeof(c->cur.label), "%.80s:%d: path '%.63s'", c->fname, c->lineno, id);
	memset(c->set_prop, 0, sizeof(c->set_prop));
	return 0;
}

/* Per-path properties: the first non-empty value wins, later ones must agree. */
static int csv_props(struct csv *c, char **f)
{
	for (int i = 0; i < CURVE_NPARAMS; i++) {
		int col = c->col[COL_WIDTH + i];
		if (col < 0 || !*f[col])
			continue;
		double v;
		if (!parse_num(f[col], &v))
			return cfail(c, c->lineno, "%s '%s' is not a number", curve_param_names[i], f[col]);
		const char *why = curve_param_check(curve_param_names[i], v);
		if (why)
			return cfail(c, c->lineno, "%s = %s %s", curve_param_names[i], f[col], why);
		if (c->set_prop[i] && *curve_param_slot(&c->cur, i) != (float)v)
			return cfail(c, c->lineno, "%s of path '%s' changes along the path (%g, then %s)",
				     curve_param_names[i], c->cur_id, (double)*curve_param_slot(&c->cur, i), f[col]);
		curve_param_set(&c->cur, i, (float)v);
		c->set_prop[i] = true;
	}
	int kcol = c->col[COL_KIND];
	if (kcol >= 0 && *f[kcol] && curve_kind_parse(f[kcol]) != c->cur.kind)
		return cfail(c, c->lineno, "kind of path '%s' changes along the path", c->cur_id);
	int scol = c->col[COL_SURFACE];
	if (scol >= 0 && *f[scol]) {
		int s = curve_surface_of_tag(f[scol]);
		if (s < 0)
			return cfail(c, c->lineno, "surface '%s' is not asphalt, gravel, dirt, ballast, none or an OSM "
				     "surface value (paved, compacted, ground, ...)", f[scol]);
		if (c->surface_set && s != c->cur.surface)
			return cfail(c, c->lineno, "surface of path '%s' changes along the path", c->cur_id);
		c->cur.surface = s;
		c->surface_set = true;
	}
	return 0;
}

static int csv_point(struct csv *c, char **f)
{
	double xyz[3];
	for (int a = 0; a < 3; a++)
		if (!parse_num(f[c->col[COL_X + a]], &xyz[a]) || fabs(xyz[a]) > 1e7)
			return cfail(c, c->lineno, "%s '%s' is not a number within +-1e7", col_names[COL_X + a],
				     f[c->col[COL_X + a]]);
	if (c->cur.npts + 1 > c->cap) {
		c->cap = c->cap ? c->cap * 2 : 16;
		float *np = realloc(c->cur.pts, sizeof(float) * 3 * (size_t)c->cap);
		if (!np)
			return cfail(c, c->lineno, "out of memory");
		c->cur.pts = np;
	}
	for (int a = 0; a < 3; a++)
		c->cur.pts[3 * c->cur.npts + a] = (float)xyz[a];
	c->cur.npts++;
	return 0;
}

/* One line of the file (NUL-terminated, n bytes before the NUL unless the
 * file has a NUL byte). */
static int csv_line(struct csv *c, char *line, size_t n)
{
	if (strlen(line) != n)
		return cfail(c, c->lineno, "NUL byte in the file (not a text CSV)");
	char *t = trim(line);
	if (!*t || *t == '#')
		return 0;
	char *f[MAX_FIELDS];
	int nf = split(t, f);
	if (nf < 0)
		return cfail(c, c->lineno, "more than %d columns", MAX_FIELDS);
	if (!c->have_header)
		return csv_header(c, f, nf);
	if (nf != c->nhead)
		return cfail(c, c->lineno, "%d fields, the header has %d", nf, c->nhead);
	bool new_path = strcmp(f[c->col[COL_PATH]], c->cur_id) != 0 || c->cur.npts == 0;
	if (new_path && (csv_end_path(c) < 0 || csv_start_path(c, f) < 0))
		return -1;
	if (csv_props(c, f) < 0)
		return -1;
	return csv_point(c, f);
}

/* Rows that are neither blank nor comments (the header and one a point),
 * counted in one pass before anything is parsed. */
static long count_rows(const char *text, size_t len)
{
	long n = 0;
	for (const char *p = text, *end = text + len; p < end;) {
		while (p < end && (*p == ' ' || *p == '\t' || *p == '\r'))
			p++;
		if (p < end && *p != '\n' && *p != '#')
			n++;
		const char *nl = memchr(p, '\n', (size_t)(end - p));
		p = nl ? nl + 1 : end;
	}
	return n;
}

int curves_parse_csv(const char *text, size_t len, const char *fname, struct curve_set *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof(*s));
	snprintf(s->source, sizeof(s->source), "%s", fname);
	long rows = count_rows(text, len);
	if (rows - 1 > CURVE_MAX_POINTS) {
		snprintf(err, errlen, "%s: %ld points, more than the %ld the curve tables may hold", fname, rows - 1,
			 (long)CURVE_MAX_POINTS);
		return -1;
	}
	struct csv c;
	memset(&c, 0, sizeof(c));
	c.fname = fname;
	c.err = err;
	c.errlen = errlen;
	c.s = s;
	for (int i = 0; i < NCOL; i++)
		c.col[i] = -1;
	char *line = NULL;
	int rc = 0;
	for (const char *p = text, *end = text + len; rc == 0 && p < end;) {
		const char *nl = memchr(p, '\n', (size_t)(end - p));
		size_t n = nl ? (size_t)(nl - p) : (size_t)(end - p);
		c.lineno++;
		free(line);
		line = malloc(n + 1);
		if (!line) {
			rc = cfail(&c, c.lineno, "out of memory");
			break;
		}
		memcpy(line, p, n);
		line[n] = 0;
		p = nl ? nl + 1 : end;
		rc = csv_line(&c, line, n);
	}
	if (rc == 0)
		rc = csv_end_path(&c);
	if (rc == 0 && !c.have_header)
		rc = cfail(&c, c.lineno, "empty CSV (needs a header line path,x,y,z[,...])");
	if (rc == 0 && s->npaths == 0)
		rc = cfail(&c, c.lineno, "no points after the header");
	free(c.ids);
	free(c.slot);
	free(line);
	free(c.cur.pts);
	if (rc < 0)
		curve_set_free(s);
	return rc;
}
