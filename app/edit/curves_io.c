/* isoterra — curve input: GeoJSON (a small strict JSON parser that keeps
 * line numbers, so errors name the line and the feature) and CSV. */
#include "curves.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_FILE_BYTES (64u << 20)
#define MAX_DEPTH 64

/* ---- JSON DOM --------------------------------------------------------------- */

enum jtype { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };
static const char *const jtype_names[] = { "null", "a boolean", "a number", "a string", "an array", "an object" };

struct jval {
	enum jtype type;
	int line;
	double num;
	char *str;            /* J_STR */
	struct jval *items;   /* J_ARR, J_OBJ values */
	char **keys;          /* J_OBJ */
	int n;
};

struct jparser {
	const char *s, *end;
	int line;
	const char *fname;
	char *err;
	size_t errlen;
	bool failed;
};

static void jfail(struct jparser *jp, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void jfail(struct jparser *jp, const char *fmt, ...)
{
	if (jp->failed)
		return;
	jp->failed = true;
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	snprintf(jp->err, jp->errlen, "%s:%d: invalid JSON: %s", jp->fname, jp->line, msg);
}

static void jfree(struct jval *v)
{
	if (v->type == J_STR)
		free(v->str);
	if (v->type == J_ARR || v->type == J_OBJ) {
		for (int i = 0; i < v->n; i++) {
			jfree(&v->items[i]);
			if (v->keys)
				free(v->keys[i]);
		}
		free(v->items);
		free(v->keys);
	}
	memset(v, 0, sizeof(*v));
}

static void jskip(struct jparser *jp)
{
	while (jp->s < jp->end) {
		char c = *jp->s;
		if (c == '\n')
			jp->line++;
		else if (c != ' ' && c != '\t' && c != '\r')
			break;
		jp->s++;
	}
}

static void describe(const struct jparser *jp, char *buf, size_t len)
{
	if (jp->s >= jp->end)
		snprintf(buf, len, "end of file");
	else if (isprint((unsigned char)*jp->s))
		snprintf(buf, len, "'%c'", *jp->s);
	else
		snprintf(buf, len, "byte 0x%02x", (unsigned char)*jp->s);
}

static char *jstring(struct jparser *jp)
{
	/* at the opening quote */
	jp->s++;
	size_t cap = 32, n = 0;
	char *out = malloc(cap);
	if (!out) {
		jfail(jp, "out of memory");
		return NULL;
	}
	while (jp->s < jp->end && *jp->s != '"') {
		unsigned char c = (unsigned char)*jp->s++;
		if (c < 0x20) {
			jfail(jp, "control character in a string (unterminated string?)");
			free(out);
			return NULL;
		}
		if (c == '\\') {
			if (jp->s >= jp->end)
				break;
			char e = *jp->s++;
			switch (e) {
			case '"': c = '"'; break;
			case '\\': c = '\\'; break;
			case '/': c = '/'; break;
			case 'b': c = '\b'; break;
			case 'f': c = '\f'; break;
			case 'n': c = '\n'; break;
			case 'r': c = '\r'; break;
			case 't': c = '\t'; break;
			case 'u':
				for (int i = 0; i < 4; i++)
					if (jp->s + i >= jp->end || !isxdigit((unsigned char)jp->s[i])) {
						jfail(jp, "bad \\u escape in a string");
						free(out);
						return NULL;
					}
				jp->s += 4;
				c = '?'; /* names and kinds are ASCII; others are not used */
				break;
			default:
				jfail(jp, "bad escape '\\%c' in a string", isprint((unsigned char)e) ? e : '?');
				free(out);
				return NULL;
			}
		}
		if (n + 2 > cap) {
			cap *= 2;
			char *no = realloc(out, cap);
			if (!no) {
				free(out);
				jfail(jp, "out of memory");
				return NULL;
			}
			out = no;
		}
		out[n++] = (char)c;
	}
	if (jp->s >= jp->end) {
		jfail(jp, "unterminated string");
		free(out);
		return NULL;
	}
	jp->s++;
	out[n] = 0;
	return out;
}

static bool jvalue(struct jparser *jp, struct jval *v, int depth);

static bool jappend(struct jparser *jp, struct jval *v, int *cap, char *key)
{
	if (v->n + 1 > *cap) {
		int nc = *cap ? *cap * 2 : 4;
		struct jval *ni = realloc(v->items, sizeof(*ni) * (size_t)nc);
		if (!ni) {
			jfail(jp, "out of memory");
			return false;
		}
		v->items = ni;
		if (v->type == J_OBJ) {
			char **nk = realloc(v->keys, sizeof(*nk) * (size_t)nc);
			if (!nk) {
				jfail(jp, "out of memory");
				return false;
			}
			v->keys = nk;
		}
		*cap = nc;
	}
	memset(&v->items[v->n], 0, sizeof(struct jval));
	if (v->type == J_OBJ)
		v->keys[v->n] = key;
	v->n++;
	return true;
}

static bool jvalue(struct jparser *jp, struct jval *v, int depth)
{
	memset(v, 0, sizeof(*v));
	jskip(jp);
	v->line = jp->line;
	if (depth > MAX_DEPTH) {
		jfail(jp, "nested deeper than %d levels", MAX_DEPTH);
		return false;
	}
	if (jp->s >= jp->end) {
		jfail(jp, "unexpected end of file, expected a value");
		return false;
	}
	char c = *jp->s;
	char what[32];
	if (c == '{' || c == '[') {
		bool obj = c == '{';
		v->type = obj ? J_OBJ : J_ARR;
		jp->s++;
		int cap = 0;
		jskip(jp);
		if (jp->s < jp->end && *jp->s == (obj ? '}' : ']')) {
			jp->s++;
			return true;
		}
		for (;;) {
			char *key = NULL;
			jskip(jp);
			if (obj) {
				if (jp->s >= jp->end || *jp->s != '"') {
					describe(jp, what, sizeof(what));
					jfail(jp, "expected a quoted member name, got %s", what);
					return false;
				}
				key = jstring(jp);
				if (!key)
					return false;
				jskip(jp);
				if (jp->s >= jp->end || *jp->s != ':') {
					describe(jp, what, sizeof(what));
					jfail(jp, "expected ':' after member \"%s\", got %s", key, what);
					free(key);
					return false;
				}
				jp->s++;
			}
			if (!jappend(jp, v, &cap, key)) {
				free(key);
				return false;
			}
			if (!jvalue(jp, &v->items[v->n - 1], depth + 1))
				return false;
			jskip(jp);
			if (jp->s < jp->end && *jp->s == ',') {
				jp->s++;
				jskip(jp);
				if (jp->s < jp->end && (*jp->s == '}' || *jp->s == ']')) {
					jfail(jp, "trailing comma");
					return false;
				}
				continue;
			}
			if (jp->s < jp->end && *jp->s == (obj ? '}' : ']')) {
				jp->s++;
				return true;
			}
			describe(jp, what, sizeof(what));
			jfail(jp, "expected ',' or '%c', got %s", obj ? '}' : ']', what);
			return false;
		}
	}
	if (c == '"') {
		v->type = J_STR;
		v->str = jstring(jp);
		return v->str != NULL;
	}
	static const char *const words[] = { "true", "false", "null" };
	for (int i = 0; i < 3; i++) {
		size_t l = strlen(words[i]);
		if ((size_t)(jp->end - jp->s) >= l && !strncmp(jp->s, words[i], l)) {
			jp->s += l;
			v->type = i < 2 ? J_BOOL : J_NULL;
			v->num = i == 0;
			return true;
		}
	}
	if (c == '-' || isdigit((unsigned char)c)) {
		/* JSON number grammar: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)? */
		const char *p = jp->s;
		if (*p == '-')
			p++;
		if (p < jp->end && *p == '0')
			p++;
		else if (p < jp->end && isdigit((unsigned char)*p))
			while (p < jp->end && isdigit((unsigned char)*p))
				p++;
		else {
			jfail(jp, "malformed number");
			return false;
		}
		if (p < jp->end && *p == '.') {
			p++;
			if (p >= jp->end || !isdigit((unsigned char)*p)) {
				jfail(jp, "malformed number (digits expected after '.')");
				return false;
			}
			while (p < jp->end && isdigit((unsigned char)*p))
				p++;
		}
		if (p < jp->end && (*p == 'e' || *p == 'E')) {
			p++;
			if (p < jp->end && (*p == '+' || *p == '-'))
				p++;
			if (p >= jp->end || !isdigit((unsigned char)*p)) {
				jfail(jp, "malformed number (exponent digits expected)");
				return false;
			}
			while (p < jp->end && isdigit((unsigned char)*p))
				p++;
		}
		char buf[64];
		size_t l = (size_t)(p - jp->s);
		if (l >= sizeof(buf)) {
			jfail(jp, "number too long");
			return false;
		}
		memcpy(buf, jp->s, l);
		buf[l] = 0;
		errno = 0;
		v->num = strtod(buf, NULL);
		if (errno == ERANGE && fabs(v->num) > 1.0) {
			jfail(jp, "number %s out of range", buf);
			return false;
		}
		v->type = J_NUM;
		jp->s = p;
		return true;
	}
	describe(jp, what, sizeof(what));
	jfail(jp, "unexpected %s, expected a value", what);
	return false;
}

static const struct jval *jget(const struct jval *o, const char *key)
{
	if (o->type != J_OBJ)
		return NULL;
	for (int i = 0; i < o->n; i++)
		if (!strcmp(o->keys[i], key))
			return &o->items[i];
	return NULL;
}

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
	struct jparser jp = { text, text + len, 1, fname, err, errlen, false };
	struct jval root;
	bool ok = jvalue(&jp, &root, 0);
	if (ok) {
		jskip(&jp);
		if (jp.s < jp.end) {
			jfail(&jp, "text after the end of the top-level value");
			ok = false;
		}
	}
	if (!ok) {
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

int curves_parse_csv(const char *text, size_t len, const char *fname, struct curve_set *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof(*s));
	int col[NCOL];
	for (int i = 0; i < NCOL; i++)
		col[i] = -1;
	int nhead = 0, lineno = 0;
	bool have_header = false;
	struct curve_path cur;
	memset(&cur, 0, sizeof(cur));
	int cap = 0, cur_line = 0;
	char cur_id[64] = "";
	bool set_prop[5] = { false };
	char(*ids)[64] = NULL;
	int nids = 0, ids_cap = 0;
	char *line = NULL;
	int rc = -1;
	const char *p = text, *end = text + len;
#define CFAIL(...)                                                       \
	do {                                                             \
		char m_[256];                                            \
		snprintf(m_, sizeof(m_), __VA_ARGS__);                   \
		snprintf(err, errlen, "%s:%d: %s", fname, lineno, m_);   \
		goto out;                                                \
	} while (0)
	for (;;) {
		/* finish the current path at a new id or at the end */
		const char *nl = p < end ? memchr(p, '\n', (size_t)(end - p)) : NULL;
		size_t n = p < end ? (nl ? (size_t)(nl - p) : (size_t)(end - p)) : 0;
		char *f[MAX_FIELDS];
		int nf = 0;
		bool eof = p >= end;
		if (!eof) {
			lineno++;
			free(line);
			line = malloc(n + 1);
			if (!line)
				CFAIL("out of memory");
			memcpy(line, p, n);
			line[n] = 0;
			p = nl ? nl + 1 : end;
			if (strlen(line) != n)
				CFAIL("NUL byte in the file (not a text CSV)");
			char *t = trim(line);
			if (!*t || *t == '#')
				continue;
			nf = split(t, f);
			if (nf < 0)
				CFAIL("more than %d columns", MAX_FIELDS);
			if (!have_header) {
				for (int i = 0; i < nf; i++) {
					int c = -1;
					for (int k = 0; k < NCOL; k++)
						if (!strcasecmp(f[i], col_names[k]))
							c = k;
					if (c < 0)
						CFAIL("unknown column '%s' in the header (path,x,y,z[,kind,width,falloff,"
						      "inclination,smoothing])", f[i]);
					if (col[c] >= 0)
						CFAIL("column '%s' appears twice in the header", f[i]);
					col[c] = i;
				}
				for (int k = 0; k <= COL_Z; k++)
					if (col[k] < 0)
						CFAIL("the header has no '%s' column (needs path,x,y,z)", col_names[k]);
				nhead = nf;
				have_header = true;
				continue;
			}
			if (nf != nhead)
				CFAIL("%d fields, the header has %d", nf, nhead);
		}
		bool new_path = eof || strcmp(f[col[COL_PATH]], cur_id) != 0 || cur.npts == 0;
		if (new_path && cur.npts > 0) {
			int at = lineno;
			lineno = cur_line;
			if (curve_path_dedup(&cur) < 2)
				CFAIL("path '%s' needs at least 2 distinct points", cur_id);
			lineno = at;
			if (curve_set_add(s, &cur) < 0)
				CFAIL("out of memory");
			cur.npts = 0;
		}
		if (eof)
			break;
		if (new_path) {
			const char *id = f[col[COL_PATH]];
			if (!*id)
				CFAIL("empty path id");
			if (strlen(id) >= sizeof(cur_id))
				CFAIL("path id longer than %zu characters", sizeof(cur_id) - 1);
			/* ids seen before (a path's rows are consecutive) */
			for (int i = 0; i < nids; i++)
				if (!strcmp(ids[i], id))
					CFAIL("rows of path '%s' continue after another path (a path's rows must be consecutive)", id);
			if (nids + 1 > ids_cap) {
				ids_cap = ids_cap ? 2 * ids_cap : 16;
				char(*ni)[64] = realloc(ids, sizeof(*ids) * (size_t)ids_cap);
				if (!ni)
					CFAIL("out of memory");
				ids = ni;
			}
			snprintf(ids[nids++], sizeof(ids[0]), "%s", id);
			snprintf(cur_id, sizeof(cur_id), "%s", id);
			cur_line = lineno;
			int kind = CURVE_ROAD;
			if (col[COL_KIND] >= 0 && *f[col[COL_KIND]]) {
				kind = parse_kind(f[col[COL_KIND]]);
				if (kind < 0)
					CFAIL("kind '%s' is not road, river or railway", f[col[COL_KIND]]);
			}
			float *pts = cur.pts;
			curve_path_defaults(&cur, kind);
			cur.pts = pts;
			cur.npts = 0;
			snprintf(cur.label, sizeof(cur.label), "%.80s:%d: path '%.63s'", fname, lineno, id);
			memset(set_prop, 0, sizeof(set_prop));
		}
		/* per-path properties: first non-empty value wins, later ones must agree */
		for (int i = 0; i < 4; i++) {
			int c = col[COL_WIDTH + i];
			if (c < 0 || !*f[c])
				continue;
			double v;
			if (!parse_num(f[c], &v))
				CFAIL("%s '%s' is not a number", param_names[i], f[c]);
			const char *why = check_param(param_names[i], v);
			if (why)
				CFAIL("%s = %s %s", param_names[i], f[c], why);
			if (set_prop[i] && *param_slot(&cur, i) != (float)v)
				CFAIL("%s of path '%s' changes along the path (%g, then %s)", param_names[i], cur_id,
				      (double)*param_slot(&cur, i), f[c]);
			*param_slot(&cur, i) = (float)v;
			set_prop[i] = true;
		}
		if (col[COL_KIND] >= 0 && *f[col[COL_KIND]] && parse_kind(f[col[COL_KIND]]) != cur.kind)
			CFAIL("kind of path '%s' changes along the path", cur_id);
		double xyz[3];
		for (int a = 0; a < 3; a++)
			if (!parse_num(f[col[COL_X + a]], &xyz[a]) || fabs(xyz[a]) > 1e7)
				CFAIL("%s '%s' is not a number within +-1e7", col_names[COL_X + a], f[col[COL_X + a]]);
		if (cur.npts + 1 > cap) {
			cap = cap ? cap * 2 : 16;
			float *np = realloc(cur.pts, sizeof(float) * 3 * (size_t)cap);
			if (!np)
				CFAIL("out of memory");
			cur.pts = np;
		}
		for (int a = 0; a < 3; a++)
			cur.pts[3 * cur.npts + a] = (float)xyz[a];
		cur.npts++;
	}
	if (!have_header) {
		snprintf(err, errlen, "%s:%d: empty CSV (needs a header line path,x,y,z[,...])", fname, lineno);
		goto out;
	}
	if (s->npaths == 0) {
		snprintf(err, errlen, "%s:%d: no points after the header", fname, lineno);
		goto out;
	}
	rc = 0;
out:
#undef CFAIL
	free(ids);
	free(line);
	free(cur.pts);
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
