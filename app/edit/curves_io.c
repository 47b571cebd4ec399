/* isoterra — curve input: GeoJSON (through the strict JSON parser of
 * curves_json.c, which keeps line numbers, so errors name the line and the
 * feature) and CSV. */
#include "curves.h"
#include "curves_json.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_FILE_BYTES (64u << 20)

/* ---- GeoJSON --------------------------------------------------------------- */

struct gctx {
	const char *fname;
	char *err;
	size_t errlen;
	struct curve_set *s;
};

static int gfail(struct gctx *g, int line, const char *what, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int gfail(struct gctx *g, int line, const char *what, const char *fmt, ...)
{
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	snprintf(g->err, g->errlen, "%s:%d: %s: %s", g->fname, line, what, msg);
	return -1;
}

static int parse_kind(const char *s)
{
	for (int k = 0; k < CURVE_KIND_COUNT; k++)
		if (!strcmp(s, curve_kind_names[k]))
			return k;
	return -1;
}

/* Range checks shared by GeoJSON and CSV; NULL when fine, else the reason. */
static const char *check_param(const char *name, double v)
{
	if (!isfinite(v))
		return "is not a finite number";
	if (!strcmp(name, "width") && !(v > 0.0 && v <= 1e6))
		return "must be in (0, 1e6]";
	if (!strcmp(name, "falloff") && !(v >= 0.0 && v <= 1e6))
		return "must be in [0, 1e6]";
	if (!strcmp(name, "smoothing") && !(v >= 0.0 && v <= 1.0))
		return "must be in [0, 1]";
	if (!strcmp(name, "inclination") && !(fabs(v) <= 1e6))
		return "must be in [-1e6, 1e6]";
	return NULL;
}

static const char *const param_names[4] = { "width", "falloff", "inclination", "smoothing" };

static float *param_slot(struct curve_path *p, int i)
{
	return i == 0 ? &p->width : i == 1 ? &p->falloff : i == 2 ? &p->inclination : &p->smoothing;
}

static int geo_props(struct gctx *g, const struct jval *props, const char *what, struct curve_path *base)
{
	curve_path_defaults(base, CURVE_ROAD);
	if (!props || props->type == J_NULL)
		return 0;
	if (props->type != J_OBJ)
		return gfail(g, props->line, what, "\"properties\" must be an object, not %s", jtype_names[props->type]);
	const struct jval *k = jget(props, "kind");
	if (k) {
		if (k->type != J_STR || parse_kind(k->str) < 0)
			return gfail(g, k->line, what, "\"kind\" must be \"road\", \"river\" or \"railway\"");
		curve_path_defaults(base, parse_kind(k->str));
	}
	for (int i = 0; i < 4; i++) {
		const struct jval *v = jget(props, param_names[i]);
		if (!v)
			continue;
		if (v->type != J_NUM)
			return gfail(g, v->line, what, "\"%s\" must be a number, not %s", param_names[i], jtype_names[v->type]);
		const char *why = check_param(param_names[i], v->num);
		if (why)
			return gfail(g, v->line, what, "\"%s\" = %g %s", param_names[i], v->num, why);
		*param_slot(base, i) = (float)v->num;
	}
	return 0;
}

static int geo_line(struct gctx *g, const struct jval *coords, const char *what, const struct curve_path *base,
		    int part)
{
	char label[96];
	if (part >= 0)
		snprintf(label, sizeof(label), "%s, line string %d", what, part + 1);
	else
		snprintf(label, sizeof(label), "%s", what);
	if (coords->type != J_ARR)
		return gfail(g, coords->line, label, "\"coordinates\" must be an array of positions, not %s",
			     jtype_names[coords->type]);
	if (coords->n < 2)
		return gfail(g, coords->line, label, "a line string needs at least 2 positions, has %d", coords->n);
	struct curve_path p = *base;
	p.npts = coords->n;
	p.pts = malloc(sizeof(float) * 3 * (size_t)coords->n);
	if (!p.pts)
		return gfail(g, coords->line, label, "out of memory");
	for (int i = 0; i < coords->n; i++) {
		const struct jval *pos = &coords->items[i];
		if (pos->type != J_ARR) {
			free(p.pts);
			return gfail(g, pos->line, label, "position %d must be an array [x, y, z], not %s", i + 1,
				     jtype_names[pos->type]);
		}
		if (pos->n != 3) {
			free(p.pts);
			return gfail(g, pos->line, label, "position %d has %d coordinates; 3D positions [x, y, z] are needed",
				     i + 1, pos->n);
		}
		double c[3];
		for (int a = 0; a < 3; a++) {
			if (pos->items[a].type != J_NUM || !isfinite(pos->items[a].num) || fabs(pos->items[a].num) > 1e7) {
				free(p.pts);
				return gfail(g, pos->line, label, "position %d: coordinate %d is not a number within +-1e7", i + 1,
					     a + 1);
			}
			c[a] = pos->items[a].num;
		}
		/* GeoJSON [east, north, up] -> world (x, y up, z = -north) */
		p.pts[3 * i + 0] = (float)c[0];
		p.pts[3 * i + 1] = (float)c[2];
		p.pts[3 * i + 2] = (float)-c[1];
	}
	snprintf(p.label, sizeof(p.label), "%.80s: %.96s", g->fname, label);
	if (curve_path_dedup(&p) < 2) {
		free(p.pts);
		return gfail(g, coords->line, label, "needs at least 2 distinct positions");
	}
	int rc = curve_set_add(g->s, &p);
	free(p.pts);
	if (rc < 0)
		return gfail(g, coords->line, label, "out of memory");
	return 0;
}

static int geo_geometry(struct gctx *g, const struct jval *geom, const struct jval *props, const char *what)
{
	if (!geom || geom->type != J_OBJ)
		return gfail(g, geom ? geom->line : 1, what, "\"geometry\" must be a LineString or MultiLineString object%s",
			     geom && geom->type == J_NULL ? " (it is null)" : "");
	const struct jval *t = jget(geom, "type");
	if (!t || t->type != J_STR)
		return gfail(g, geom->line, what, "geometry has no \"type\"");
	const struct jval *coords = jget(geom, "coordinates");
	bool multi = !strcmp(t->str, "MultiLineString");
	if (!multi && strcmp(t->str, "LineString"))
		return gfail(g, t->line, what, "geometry type \"%s\" is not supported (LineString or MultiLineString)",
			     t->str);
	if (!coords)
		return gfail(g, geom->line, what, "geometry has no \"coordinates\"");
	struct curve_path base;
	memset(&base, 0, sizeof(base));
	if (geo_props(g, props, what, &base) < 0)
		return -1;
	if (!multi)
		return geo_line(g, coords, what, &base, -1);
	if (coords->type != J_ARR || coords->n < 1)
		return gfail(g, coords->line, what, "MultiLineString \"coordinates\" must be a non-empty array of line strings");
	for (int i = 0; i < coords->n; i++)
		if (geo_line(g, &coords->items[i], what, &base, i) < 0)
			return -1;
	return 0;
}

static int geo_feature(struct gctx *g, const struct jval *f, int idx)
{
	char what[48];
	snprintf(what, sizeof(what), "feature %d", idx + 1);
	if (f->type != J_OBJ)
		return gfail(g, f->line, what, "must be an object, not %s", jtype_names[f->type]);
	const struct jval *t = jget(f, "type");
	if (!t || t->type != J_STR || strcmp(t->str, "Feature"))
		return gfail(g, f->line, what, "\"type\" must be \"Feature\"");
	return geo_geometry(g, jget(f, "geometry"), jget(f, "properties"), what);
}

int curves_parse_geojson(const char *text, size_t len, const char *fname, struct curve_set *s, char *err,
			 size_t errlen)
{
	memset(s, 0, sizeof(*s));
	struct jval root;
	if (!json_parse(text, len, fname, &root, err, errlen)) {
		jfree(&root);
		return -1;
	}
	struct gctx g = { fname, err, errlen, s };
	int rc = 0;
	const struct jval *t = root.type == J_OBJ ? jget(&root, "type") : NULL;
	if (!t || t->type != J_STR) {
		rc = gfail(&g, root.line, "GeoJSON", "the top level must be an object with a \"type\"");
	} else if (!strcmp(t->str, "FeatureCollection")) {
		const struct jval *fs = jget(&root, "features");
		if (!fs || fs->type != J_ARR)
			rc = gfail(&g, root.line, "GeoJSON", "a FeatureCollection needs a \"features\" array");
		for (int i = 0; rc == 0 && i < fs->n; i++)
			rc = geo_feature(&g, &fs->items[i], i);
	} else if (!strcmp(t->str, "Feature")) {
		rc = geo_feature(&g, &root, 0);
	} else if (!strcmp(t->str, "LineString") || !strcmp(t->str, "MultiLineString")) {
		rc = geo_geometry(&g, &root, NULL, "geometry");
	} else {
		rc = gfail(&g, t->line, "GeoJSON", "type \"%s\" is not supported (FeatureCollection, Feature, LineString, "
			   "MultiLineString)", t->str);
	}
	if (rc == 0 && s->npaths == 0)
		rc = gfail(&g, root.line, "GeoJSON", "no line strings");
	jfree(&root);
	if (rc < 0)
		curve_set_free(s);
	return rc;
}

/* ---- CSV ------------------------------------------------------------------------ */

enum { COL_PATH, COL_X, COL_Y, COL_Z, COL_KIND, COL_WIDTH, COL_FALLOFF, COL_INCL, COL_SMOOTH, NCOL };
static const char *const col_names[NCOL] = { "path", "x", "y", "z", "kind", "width", "falloff", "inclination",
					     "smoothing" };
#define MAX_FIELDS 32

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

/* The CSV reader's state: the header's columns, the path being read. */
struct csv {
	const char *fname;
	char *err;
	size_t errlen;
	int lineno;
	int col[NCOL], nhead;      /* column of each field (-1 none), header fields */
	bool have_header;
	struct curve_path cur;     /* the path being read */
	int cap, cur_line;         /* cur.pts capacity (points); the line it began on */
	char cur_id[64];
	bool set_prop[4];          /* width, falloff, inclination, smoothing given */
	char (*ids)[64];           /* the ids of the paths begun so far */
	int nids, ids_cap;
};

static int cfail(struct csv *c, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int cfail(struct csv *c, const char *fmt, ...)
{
	char m[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(m, sizeof(m), fmt, ap);
	va_end(ap);
	snprintf(c->err, c->errlen, "%s:%d: %s", c->fname, c->lineno, m);
	return -1;
}

static int csv_header(struct csv *c, char **f, int nf)
{
	for (int i = 0; i < nf; i++) {
		int k = -1;
		for (int j = 0; j < NCOL; j++)
			if (!strcasecmp(f[i], col_names[j]))
				k = j;
		if (k < 0)
			return cfail(c, "unknown column '%s' in the header (path,x,y,z[,kind,width,falloff,"
				     "inclination,smoothing])", f[i]);
		if (c->col[k] >= 0)
			return cfail(c, "column '%s' appears twice in the header", f[i]);
		c->col[k] = i;
	}
	for (int k = 0; k <= COL_Z; k++)
		if (c->col[k] < 0)
			return cfail(c, "the header has no '%s' column (needs path,x,y,z)", col_names[k]);
	c->nhead = nf;
	c->have_header = true;
	return 0;
}

/* The path read so far, if any, into s. */
static int csv_finish_path(struct csv *c, struct curve_set *s)
{
	if (c->cur.npts == 0)
		return 0;
	if (curve_path_dedup(&c->cur) < 2) {
		c->lineno = c->cur_line;
		return cfail(c, "path '%s' needs at least 2 distinct points", c->cur_id);
	}
	if (curve_set_add(s, &c->cur) < 0)
		return cfail(c, "out of memory");
	c->cur.npts = 0;
	return 0;
}

/* A new path begins at this row (its id, kind and label). */
static int csv_start_path(struct csv *c, char **f)
{
	const char *id = f[c->col[COL_PATH]];
	if (!*id)
		return cfail(c, "empty path id");
	if (strlen(id) >= sizeof(c->cur_id))
		return cfail(c, "path id longer than %zu characters", sizeof(c->cur_id) - 1);
	/* ids seen before (a path's rows are consecutive) */
	for (int i = 0; i < c->nids; i++)
		if (!strcmp(c->ids[i], id))
			return cfail(c, "rows of path '%s' continue after another path (a path's rows must be consecutive)",
				     id);
	if (c->nids + 1 > c->ids_cap) {
		c->ids_cap = c->ids_cap ? 2 * c->ids_cap : 16;
		char(*ni)[64] = realloc(c->ids, sizeof(*c->ids) * (size_t)c->ids_cap);
		if (!ni)
			return cfail(c, "out of memory");
		c->ids = ni;
	}
	snprintf(c->ids[c->nids++], sizeof(c->ids[0]), "%s", id);
	snprintf(c->cur_id, sizeof(c->cur_id), "%s", id);
	c->cur_line = c->lineno;
	int kind = CURVE_ROAD;
	const char *ks = c->col[COL_KIND] >= 0 ? f[c->col[COL_KIND]] : "";
	if (*ks) {
		kind = parse_kind(ks);
		if (kind < 0)
			return cfail(c, "kind '%s' is not road, river or railway", ks);
	}
	float *pts = c->cur.pts;
	curve_path_defaults(&c->cur, kind);
	c->cur.pts = pts;
	c->cur.npts = 0;
	snprintf(c->cur.label, sizeof(c->cur.label), "%.80s:%d: path '%.63s'", c->fname, c->lineno, id);
	memset(c->set_prop, 0, sizeof(c->set_prop));
	return 0;
}

/* One row of the current path: its properties (first non-empty value wins,
 * the rest must agree) and its point. */
static int csv_row(struct csv *c, char **f)
{
	for (int i = 0; i < 4; i++) {
		int k = c->col[COL_WIDTH + i];
		if (k < 0 || !*f[k])
			continue;
		double v;
		if (!parse_num(f[k], &v))
			return cfail(c, "%s '%s' is not a number", param_names[i], f[k]);
		const char *why = check_param(param_names[i], v);
		if (why)
			return cfail(c, "%s = %s %s", param_names[i], f[k], why);
		if (c->set_prop[i] && *param_slot(&c->cur, i) != (float)v)
			return cfail(c, "%s of path '%s' changes along the path (%g, then %s)", param_names[i], c->cur_id,
				     (double)*param_slot(&c->cur, i), f[k]);
		*param_slot(&c->cur, i) = (float)v;
		c->set_prop[i] = true;
	}
	if (c->col[COL_KIND] >= 0 && *f[c->col[COL_KIND]] && parse_kind(f[c->col[COL_KIND]]) != c->cur.kind)
		return cfail(c, "kind of path '%s' changes along the path", c->cur_id);
	double xyz[3];
	for (int a = 0; a < 3; a++)
		if (!parse_num(f[c->col[COL_X + a]], &xyz[a]) || fabs(xyz[a]) > 1e7)
			return cfail(c, "%s '%s' is not a number within +-1e7", col_names[COL_X + a], f[c->col[COL_X + a]]);
	if (c->cur.npts + 1 > c->cap) {
		c->cap = c->cap ? c->cap * 2 : 16;
		float *np = realloc(c->cur.pts, sizeof(float) * 3 * (size_t)c->cap);
		if (!np)
			return cfail(c, "out of memory");
		c->cur.pts = np;
	}
	for (int a = 0; a < 3; a++)
		c->cur.pts[3 * c->cur.npts + a] = (float)xyz[a];
	c->cur.npts++;
	return 0;
}

/* The next line (a copy in *line, NUL-checked) of [*p, end).  1, 0 at the
 * end, -1 with the message. */
static int csv_line(struct csv *c, const char **p, const char *end, char **line)
{
	if (*p >= end)
		return 0;
	const char *nl = memchr(*p, '\n', (size_t)(end - *p));
	size_t n = nl ? (size_t)(nl - *p) : (size_t)(end - *p);
	c->lineno++;
	free(*line);
	*line = malloc(n + 1);
	if (!*line)
		return cfail(c, "out of memory");
	memcpy(*line, *p, n);
	(*line)[n] = 0;
	*p = nl ? nl + 1 : end;
	if (strlen(*line) != n)
		return cfail(c, "NUL byte in the file (not a text CSV)");
	return 1;
}

int curves_parse_csv(const char *text, size_t len, const char *fname, struct curve_set *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof(*s));
	struct csv c;
	memset(&c, 0, sizeof(c));
	c.fname = fname;
	c.err = err;
	c.errlen = errlen;
	for (int i = 0; i < NCOL; i++)
		c.col[i] = -1;
	char *line = NULL;
	int rc = -1, more;
	const char *p = text, *end = text + len;
	while ((more = csv_line(&c, &p, end, &line)) >= 0) {
		char *f[MAX_FIELDS];
		int nf = 0;
		if (more) {
			char *t = trim(line);
			if (!*t || *t == '#')
				continue;
			nf = split(t, f);
			if (nf < 0) {
				cfail(&c, "more than %d columns", MAX_FIELDS);
				break;
			}
			if (!c.have_header) {
				if (csv_header(&c, f, nf) < 0)
					break;
				continue;
			}
			if (nf != c.nhead) {
				cfail(&c, "%d fields, the header has %d", nf, c.nhead);
				break;
			}
		}
		/* finish the current path at a new id or at the end */
		bool new_path = !more || strcmp(f[c.col[COL_PATH]], c.cur_id) != 0 || c.cur.npts == 0;
		if (new_path && csv_finish_path(&c, s) < 0)
			break;
		if (!more) {
			if (!c.have_header)
				cfail(&c, "empty CSV (needs a header line path,x,y,z[,...])");
			else if (s->npaths == 0)
				cfail(&c, "no points after the header");
			else
				rc = 0;
			break;
		}
		if ((new_path && csv_start_path(&c, f) < 0) || csv_row(&c, f) < 0)
			break;
	}
	free(c.ids);
	free(line);
	free(c.cur.pts);
	if (rc < 0)
		curve_set_free(s);
	return rc;
}

/* ---- files -------------------------------------------------------------------- */

static char *read_all(const char *path, size_t *len, char *err, size_t errlen)
{
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "cannot open curves file '%s': %s", path, strerror(errno));
		return NULL;
	}
	char *buf = NULL;
	size_t cap = 0, n = 0;
	for (;;) {
		if (n + 65536 + 1 > cap) {
			cap = cap ? cap * 2 : 131072;
			if (cap > MAX_FILE_BYTES + 65536 + 1) {
				snprintf(err, errlen, "curves file '%s' is larger than %u MB", path, MAX_FILE_BYTES >> 20);
				goto fail;
			}
			char *nb = realloc(buf, cap);
			if (!nb) {
				snprintf(err, errlen, "out of memory reading '%s'", path);
				goto fail;
			}
			buf = nb;
		}
		size_t r = fread(buf + n, 1, cap - n - 1, f);
		n += r;
		if (r == 0)
			break;
	}
	if (ferror(f)) {
		snprintf(err, errlen, "error reading curves file '%s'", path);
		goto fail;
	}
	fclose(f);
	buf[n] = 0;
	*len = n;
	return buf;
fail:
	free(buf);
	fclose(f);
	return NULL;
}

int curves_load(const char *path, struct curve_set *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof(*s));
	const char *dot = strrchr(path, '.');
	bool csv = dot && !strcasecmp(dot, ".csv");
	bool geo = dot && (!strcasecmp(dot, ".geojson") || !strcasecmp(dot, ".json"));
	if (!csv && !geo) {
		snprintf(err, errlen, "curves file '%s': unknown format (use .geojson, .json or .csv)", path);
		return -1;
	}
	size_t len;
	char *text = read_all(path, &len, err, errlen);
	if (!text)
		return -1;
	int rc = csv ? curves_parse_csv(text, len, path, s, err, errlen)
		     : curves_parse_geojson(text, len, path, s, err, errlen);
	free(text);
	return rc;
}
