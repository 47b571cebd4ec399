/* isoterra — curve input, GeoJSON: FeatureCollection / Feature /
 * LineString / MultiLineString with [x east, y north] or [x east, y north,
 * z up] positions, the per-path parameters in "properties", the "crs"
 * member noted for curves_geo_project, "bbox" members checked.  Errors
 * name file:line and the feature, and the axis convention where a
 * position is wrong.  Polygon / MultiPolygon rings are areas (paths with
 * `area` set: edits.c takes them out).  A feature that is neither (Point,
 * GeometryCollection, ...) or a malformed polygon is skipped, not refused:
 * one note (curve_set_note) per kind of skip names the features and their
 * types. */
#include "curves.h"
#include "curves_internal.h"
#include "json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Features skipped for one reason: how many, and the first few named. */
#define SKIP_NAMED 4
struct skips {
	int n;
	char named[240];
};

struct gctx {
	const char *fname;
	char *err;
	size_t errlen;
	struct curve_set *s;
	int crs;           /* enum curve_crs */
	bool rel;          /* positions stored as degrees from origin */
	double origin[2];  /* lon, lat: the positions' centroid */
	struct skips other; /* no line: Point, MultiPoint, GeometryCollection, null, ... */
	struct skips areas; /* Polygon, MultiPolygon */
	struct skips classes; /* unknown OSM highway classes */
	long n3d, n3d_nonzero; /* positions of 3D line strings, those with z != 0 */
};

static void skip_add(struct skips *k, const char *what, const char *type, const char *detail)
{
	if (k->n < SKIP_NAMED) {
		size_t len = strlen(k->named);
		snprintf(k->named + len, sizeof(k->named) - len, "%s%s %s%s", k->n ? ", " : "", what, type, detail);
	}
	k->n++;
}

/* "feature 3 (id \"way/12\")", "feature 3", or "geometry" for a bare one. */
static void feature_name(char *buf, size_t len, int idx, const struct json_value *f)
{
	const struct json_value *id = f ? json_get(f, "id") : NULL;
	if (idx < 0)
		snprintf(buf, len, "geometry");
	else if (id && id->type == JSON_STRING)
		snprintf(buf, len, "feature %d (id \"%.40s\")", idx + 1, id->str);
	else if (id && id->type == JSON_NUMBER)
		snprintf(buf, len, "feature %d (id %.17g)", idx + 1, id->num);
	else
		snprintf(buf, len, "feature %d", idx + 1);
}

/* All positions' ranges and centroid (longitudes relative to the first). */
struct geo_stats {
	double lo[2], hi[2], sum[2], ref;
	long n;
};

static double geo_dlon(double lon, double lon0)
{
	double d = fmod(lon - lon0 + 540.0, 360.0);
	return (d < 0.0 ? d + 360.0 : d) - 180.0;
}

/* The positions under "features", "geometry" and "coordinates". */
static void geo_scan(const struct json_value *v, struct geo_stats *st, int depth)
{
	if (depth > 8)
		return;
	if (v->type == JSON_OBJECT) {
		for (int i = 0; i < v->n; i++)
			if (!strcmp(v->keys[i], "features") || !strcmp(v->keys[i], "geometry") ||
			    !strcmp(v->keys[i], "coordinates"))
				geo_scan(&v->items[i], st, depth + 1);
	} else if (v->type == JSON_ARRAY && v->n >= 2 && v->items[0].type == JSON_NUMBER &&
		   v->items[1].type == JSON_NUMBER) {
		double c[2] = { v->items[0].num, v->items[1].num };
		if (st->n == 0)
			st->ref = c[0];
		for (int a = 0; a < 2; a++) {
			st->lo[a] = fmin(st->lo[a], c[a]);
			st->hi[a] = fmax(st->hi[a], c[a]);
		}
		st->sum[0] += geo_dlon(c[0], st->ref);
		st->sum[1] += c[1];
		st->n++;
	} else if (v->type == JSON_ARRAY) {
		for (int i = 0; i < v->n; i++)
			geo_scan(&v->items[i], st, depth + 1);
	}
}

/* The auto rule (curves.h, curves_geo_project): lon/lat when the crs member
 * names WGS84, or without one when every position is within lon/lat
 * ranges (RFC 7946: GeoJSON is WGS84); the span is kept for the note. */
static void geo_decide(struct gctx *g, const struct json_value *root, struct geo_stats *stp)
{
	struct geo_stats st = { { 1e300, 1e300 }, { -1e300, -1e300 }, { 0.0, 0.0 }, 0.0, 0 };
	geo_scan(root, &st, 0);
	*stp = st;
	bool ranges = st.n > 0 && st.lo[0] >= -180.0 && st.hi[0] <= 180.0 && st.lo[1] >= -90.0 && st.hi[1] <= 90.0;
	g->rel = g->crs == CURVE_CRS_WGS84 || (g->crs == CURVE_CRS_UNSAID && ranges);
	if (g->crs == CURVE_CRS_UNSAID && ranges) { /* curves_geo_project notes a span over a degree */
		g->s->geo_span[0] = st.hi[0] - st.lo[0];
		g->s->geo_span[1] = st.hi[1] - st.lo[1];
	}
	if (g->rel && st.n > 0) {
		g->origin[0] = geo_dlon(st.ref + st.sum[0] / (double)st.n, 0.0);
		g->origin[1] = st.sum[1] / (double)st.n;
	}
}

static int gfail(struct gctx *g, int line, const char *what, const char *fmt, ...)
	__attribute__((format(printf, 4, 5)));
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

/* A "bbox" member (RFC 7946 5): 2n numbers, the n lowest then the n
 * highest coordinates (n = 2 or 3); the lowest latitude not above the
 * highest (the longitudes may cross the antimeridian: west > east). */
static int geo_bbox(struct gctx *g, const struct json_value *o, const char *what)
{
	const struct json_value *b = json_get(o, "bbox");
	if (!b)
		return 0;
	bool ok = b->type == JSON_ARRAY && (b->n == 4 || b->n == 6);
	for (int i = 0; ok && i < b->n; i++)
		ok = b->items[i].type == JSON_NUMBER && isfinite(b->items[i].num);
	if (!ok)
		return gfail(g, b->line, what, "\"bbox\" must be [west, south, east, north] or [west, south, low, east, "
			     "north, high] (4 or 6 numbers)");
	int n = b->n / 2;
	for (int a = 1; a < n; a++)
		if (b->items[a].num > b->items[n + a].num)
			return gfail(g, b->line, what, "\"bbox\": its %s %g is above its %s %g", a == 1 ? "south" : "low",
				     b->items[a].num, a == 1 ? "north" : "high", b->items[n + a].num);
	return 0;
}

/* OSM tag `key`: a member of properties, or of its "tags" object (some
 * exporters nest the tags). */
static const struct json_value *osm_tag(const struct json_value *props, const char *key)
{
	const struct json_value *v = json_get(props, key), *tags = json_get(props, "tags");
	return v ? v : tags && tags->type == JSON_OBJECT ? json_get(tags, key) : NULL;
}

/* A width left open by the properties: "lanes" (a number, or a string of
 * one as OSM exports write tags) times a lane, else the OSM "highway"
 * class's width; an unknown class is noted (the road_width default). */
static int geo_road_class(struct gctx *g, const struct json_value *props, const char *what, struct curve_path *base)
{
	const struct json_value *lanes = osm_tag(props, "lanes"), *hw = osm_tag(props, "highway");
	if (lanes) {
		double n = lanes->type == JSON_NUMBER ? lanes->num : NAN;
		if (lanes->type == JSON_STRING) {
			char *end;
			n = strtod(lanes->str, &end);
			if (end == lanes->str || *end)
				n = NAN;
		}
		if (!(n >= 1.0 && n <= CURVE_LANES_MAX && n == floor(n)))
			return gfail(g, lanes->line, what, "\"lanes\" must be a whole number from 1 to %d", CURVE_LANES_MAX);
		if (!base->width_set)
			base->width_rel = 0.5f * (float)n;
	}
	if (hw && hw->type != JSON_STRING)
		return gfail(g, hw->line, what, "\"highway\" must be a string (an OSM highway class), not %s",
			     json_type_names[hw->type]);
	if (hw && !base->width_set && base->width_rel == 0.0f) {
		float rel = curve_highway_width(hw->str);
		if (rel > 0.0f) {
			base->width_rel = rel;
		} else {
			char cls[48];
			snprintf(cls, sizeof(cls), "\"%.40s\"", hw->str);
			skip_add(&g->classes, what, cls, "");
		}
	}
	return 0;
}

static int geo_props(struct gctx *g, const struct json_value *props, const char *what, struct curve_path *base)
{
	curve_path_defaults(base, CURVE_ROAD);
	if (!props || props->type == JSON_NULL)
		return 0;
	if (props->type != JSON_OBJECT)
		return gfail(g, props->line, what, "\"properties\" must be an object, not %s",
			     json_type_names[props->type]);
	const struct json_value *k = json_get(props, "kind");
	if (k) {
		if (k->type != JSON_STRING || curve_kind_parse(k->str) < 0)
			return gfail(g, k->line, what, "\"kind\" must be \"road\", \"river\", \"railway\", \"tunnel\" or \"bridge\"");
		curve_path_defaults(base, curve_kind_parse(k->str));
	} else {
		/* OSM's bridge=* / tunnel=* (any value but "no"): a deck or a
		 * bore, not a cut */
		const struct json_value *br = osm_tag(props, "bridge"), *tu = osm_tag(props, "tunnel");
		if (br && br->type == JSON_STRING && strcmp(br->str, "no"))
			curve_path_defaults(base, CURVE_BRIDGE);
		else if (tu && tu->type == JSON_STRING && strcmp(tu->str, "no") && strcmp(tu->str, "building_passage"))
			curve_path_defaults(base, CURVE_TUNNEL);
	}
	for (int i = 0; i < CURVE_NPARAMS; i++) {
		const struct json_value *v = json_get(props, curve_param_names[i]);
		if (!v)
			continue;
		double num = v->num;
		if (v->type == JSON_STRING && !strcmp(curve_param_names[i], "width")) {
			/* OSM's width tag is a string: metres, "7.5" or "7.5 m" */
			char *end;
			num = strtod(v->str, &end);
			while (*end == ' ')
				end++;
			if (end == v->str || (*end && strcmp(end, "m")))
				return gfail(g, v->line, what, "\"width\" \"%s\" is not a width in metres (\"7.5\" or \"7.5 m\")",
					     v->str);
		} else if (v->type != JSON_NUMBER) {
			return gfail(g, v->line, what, "\"%s\" must be a number, not %s", curve_param_names[i],
				     json_type_names[v->type]);
		}
		const char *why = curve_param_check(curve_param_names[i], num);
		if (why)
			return gfail(g, v->line, what, "\"%s\" = %g %s", curve_param_names[i], num, why);
		curve_param_set(base, i, (float)num);
	}
	if (geo_road_class(g, props, what, base) < 0)
		return -1;
	/* the surface: its OSM surface tag, else its highway class's */
	const struct json_value *sf = osm_tag(props, "surface"), *hw = osm_tag(props, "highway");
	int s = sf && sf->type == JSON_STRING ? curve_surface_of_tag(sf->str) : -1;
	if (s < 0 && hw && hw->type == JSON_STRING && base->surface != SURFACE_NONE)
		s = curve_surface_of_highway(hw->str);
	if (s >= 0)
		base->surface = s;
	return 0;
}

/* GeoJSON's axes, for messages (the CSV's are x, y up, z) */
#define GEO_AXES "GeoJSON positions are [x east, y north] (the curve follows the ground) or [x east, y north, z up]"

static int geo_line(struct gctx *g, const struct json_value *coords, const char *what, const struct curve_path *base,
		    int part)
{
	char label[128];
	if (part >= 0)
		snprintf(label, sizeof(label), "%s, %s %d", what, base->area ? "ring" : "line string", part + 1);
	else
		snprintf(label, sizeof(label), "%s", what);
	if (coords->type != JSON_ARRAY)
		return gfail(g, coords->line, label, "\"coordinates\" must be an array of positions, not %s",
			     json_type_names[coords->type]);
	if (coords->n < 2)
		return gfail(g, coords->line, label, "a line string needs at least 2 positions, has %d", coords->n);
	struct curve_path p = *base;
	p.npts = coords->n;
	p.pts = malloc(sizeof(float) * 3 * (size_t)coords->n);
	if (!p.pts)
		return gfail(g, coords->line, label, "out of memory");
	static const char *const axis[3] = { "x (east)", "y (north)", "z (up)" };
	int dim = coords->items[0].type == JSON_ARRAY ? coords->items[0].n : 0;
	p.follow_ground = dim == 2;
	for (int i = 0; i < coords->n; i++) {
		const struct json_value *pos = &coords->items[i];
		if (pos->type != JSON_ARRAY) {
			free(p.pts);
			return gfail(g, pos->line, label, "position %d must be an array, not %s; " GEO_AXES, i + 1,
				     json_type_names[pos->type]);
		}
		if ((pos->n != 2 && pos->n != 3) || pos->n != dim) {
			free(p.pts);
			if (pos->n == 2 || pos->n == 3)
				return gfail(g, pos->line, label,
					     "position %d has %d coordinates, position 1 has %d: a line string is all 2D "
					     "[x east, y north] or all 3D [x east, y north, z up]",
					     i + 1, pos->n, dim);
			return gfail(g, pos->line, label, "position %d has %d coordinates; " GEO_AXES
				     " (z up, unlike the CSV's y up)", i + 1, pos->n);
		}
		double c[3] = { 0.0, 0.0, 0.0 };
		for (int a = 0; a < pos->n; a++) {
			if (pos->items[a].type != JSON_NUMBER || !isfinite(pos->items[a].num) || fabs(pos->items[a].num) > 1e7) {
				free(p.pts);
				return gfail(g, pos->line, label, "position %d: %s is not a number within +-1e7", i + 1,
					     axis[a]);
			}
			c[a] = pos->items[a].num;
		}
		if (g->rel) { /* degrees from the centroid, exact before rounding */
			c[0] = geo_dlon(c[0], g->origin[0]);
			c[1] -= g->origin[1];
		}
		if (dim == 3) {
			g->n3d++;
			g->n3d_nonzero += c[2] != 0.0;
		}
		/* GeoJSON [east, north, up] -> world (x, y up, z = -north) */
		p.pts[3 * i + 0] = (float)c[0];
		p.pts[3 * i + 1] = (float)c[2];
		p.pts[3 * i + 2] = (float)-c[1];
	}
	p.crs = g->crs;
	p.geo_rel = g->rel;
	p.geo_origin[0] = g->rel ? g->origin[0] : 0.0;
	p.geo_origin[1] = g->rel ? g->origin[1] : 0.0;
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

/* Why a Polygon's rings are not a valid area (RFC 7946 3.1.6: closed
 * rings of at least 4 positions of 2 or 3 numbers), or NULL; *nrings
 * counted. */
static const char *poly_check(const struct json_value *rings, int *nrings, char *why, size_t len)
{
	if (rings->type != JSON_ARRAY || rings->n < 1)
		return "its coordinates are not an array of rings";
	for (int r = 0; r < rings->n; r++, (*nrings)++) {
		const struct json_value *ring = &rings->items[r];
		if (ring->type != JSON_ARRAY || ring->n < 4) {
			snprintf(why, len, "ring %d is not an array of at least 4 positions", r + 1);
			return why;
		}
		for (int i = 0; i < ring->n; i++) {
			const struct json_value *pos = &ring->items[i];
			bool ok = pos->type == JSON_ARRAY && (pos->n == 2 || pos->n == 3);
			for (int a = 0; ok && a < pos->n; a++)
				ok = pos->items[a].type == JSON_NUMBER && isfinite(pos->items[a].num);
			if (!ok) {
				snprintf(why, len, "ring %d, position %d is not 2 or 3 numbers", r + 1, i + 1);
				return why;
			}
		}
		const struct json_value *a = &ring->items[0], *b = &ring->items[ring->n - 1];
		bool closed = a->n == b->n;
		for (int k = 0; closed && k < a->n; k++)
			closed = a->items[k].num == b->items[k].num;
		if (!closed) {
			snprintf(why, len, "ring %d is not closed (its last position is not its first)", r + 1);
			return why;
		}
	}
	return NULL;
}

/* An area's class from its properties: "kind": "water" | "flat", else
 * OSM's water tags, else flat. */
static int area_class(const struct json_value *props)
{
	if (!props || props->type != JSON_OBJECT)
		return AREA_FLAT;
	const struct json_value *k = json_get(props, "kind");
	if (k && k->type == JSON_STRING)
		return !strcmp(k->str, "water") ? AREA_WATER : AREA_FLAT;
	static const char *const tags[][2] = { { "natural", "water" }, { "waterway", "riverbank" },
					       { "landuse", "reservoir" }, { "landuse", "basin" },
					       { "natural", "bay" } };
	for (size_t i = 0; i < sizeof(tags) / sizeof(tags[0]); i++) {
		const struct json_value *v = osm_tag(props, tags[i][0]);
		if (v && v->type == JSON_STRING && !strcmp(v->str, tags[i][1]))
			return AREA_WATER;
	}
	const struct json_value *w = osm_tag(props, "water");
	return w && w->type == JSON_STRING ? AREA_WATER : AREA_FLAT;
}

/* A valid Polygon's rings as area paths: the outer ring, then its holes. */
static int geo_polygon(struct gctx *g, const struct json_value *rings, const char *what, int cls, int *part)
{
	struct curve_path base;
	memset(&base, 0, sizeof(base));
	curve_path_defaults(&base, CURVE_ROAD);
	base.surface = SURFACE_NONE;
	base.area = cls;
	for (int r = 0; r < rings->n; r++) {
		base.ring = r;
		if (geo_line(g, &rings->items[r], what, &base, (*part)++) < 0)
			return -1;
	}
	return 0;
}

/* A Polygon or MultiPolygon: checked; a malformed one is skipped, named in
 * the areas note, a valid one's rings become area paths. */
static int geo_area(struct gctx *g, const char *type, const struct json_value *coords, const struct json_value *props,
		    const char *what)
{
	char why[96], detail[128];
	const char *bad = NULL;
	int nrings = 0, npoly = 0;
	if (!coords) {
		bad = "it has no \"coordinates\"";
	} else if (!strcmp(type, "Polygon")) {
		bad = poly_check(coords, &nrings, why, sizeof(why));
		npoly = 1;
	} else if (coords->type != JSON_ARRAY) {
		bad = "its coordinates are not an array of polygons";
	} else {
		for (int i = 0; !bad && i < coords->n; i++, npoly++)
			bad = poly_check(&coords->items[i], &nrings, why, sizeof(why));
	}
	if (bad) {
		snprintf(detail, sizeof(detail), " (malformed: %s)", bad);
		skip_add(&g->areas, what, type, detail);
		return 0;
	}
	int cls = area_class(props), part = 0;
	if (!strcmp(type, "Polygon"))
		return geo_polygon(g, coords, what, cls, &part);
	for (int i = 0; i < coords->n; i++)
		if (geo_polygon(g, &coords->items[i], what, cls, &part) < 0)
			return -1;
	return 0;
}

static int geo_geometry(struct gctx *g, const struct json_value *geom, const struct json_value *props, const char *what)
{
	if (geom && geom->type == JSON_NULL) { /* RFC 7946 3.2: an unlocated feature */
		skip_add(&g->other, what, "without geometry", " (null)");
		return 0;
	}
	if (!geom || geom->type != JSON_OBJECT)
		return gfail(g, geom ? geom->line : 1, what, "\"geometry\" must be a geometry object or null, not %s",
			     geom ? json_type_names[geom->type] : "missing");
	const struct json_value *t = json_get(geom, "type");
	if (!t || t->type != JSON_STRING)
		return gfail(g, geom->line, what, "geometry has no \"type\"");
	if (geo_bbox(g, geom, what) < 0)
		return -1;
	const struct json_value *coords = json_get(geom, "coordinates");
	bool multi = !strcmp(t->str, "MultiLineString");
	if (!strcmp(t->str, "Polygon") || !strcmp(t->str, "MultiPolygon"))
		return geo_area(g, t->str, coords, props, what);
	if (!multi && strcmp(t->str, "LineString")) {
		char type[48];
		snprintf(type, sizeof(type), "%.40s", t->str);
		skip_add(&g->other, what, type, "");
		return 0;
	}
	if (!coords)
		return gfail(g, geom->line, what, "geometry has no \"coordinates\"");
	struct curve_path base;
	memset(&base, 0, sizeof(base));
	if (geo_props(g, props, what, &base) < 0)
		return -1;
	if (!multi)
		return geo_line(g, coords, what, &base, -1);
	if (coords->type != JSON_ARRAY || coords->n < 1)
		return gfail(g, coords->line, what, "MultiLineString \"coordinates\" must be a non-empty array of line strings");
	for (int i = 0; i < coords->n; i++)
		if (geo_line(g, &coords->items[i], what, &base, i) < 0)
			return -1;
	return 0;
}

static int geo_feature(struct gctx *g, const struct json_value *f, int idx)
{
	char what[80];
	feature_name(what, sizeof(what), idx, f->type == JSON_OBJECT ? f : NULL);
	if (f->type != JSON_OBJECT)
		return gfail(g, f->line, what, "must be an object, not %s", json_type_names[f->type]);
	const struct json_value *t = json_get(f, "type");
	if (!t || t->type != JSON_STRING || strcmp(t->str, "Feature"))
		return gfail(g, f->line, what, "\"type\" must be \"Feature\"");
	if (geo_bbox(g, f, what) < 0)
		return -1;
	return geo_geometry(g, json_get(f, "geometry"), json_get(f, "properties"), what);
}

/* Positions (innermost arrays) in the values of "coordinates" keys, counted
 * on the raw text in one pass: the size of the curves is known before the
 * document is parsed into a tree. */
static long count_positions(const char *text, size_t len)
{
	long n = 0;
	int depth = 0, coords_depth = -1; /* the depth inside a "coordinates" value, -1 outside */
	bool leaf = false, after_key = false;
	for (size_t i = 0; i < len; i++) {
		char c = text[i];
		if (c == '"') {
			size_t j = i + 1;
			while (j < len && text[j] != '"')
				j += text[j] == '\\' ? 2 : 1;
			if (j > len) /* an escape at the very end */
				j = len;
			after_key = j < len && j - i - 1 == 11 && !memcmp(text + i + 1, "coordinates", 11);
			i = j;
		} else if (c == '[' || c == '{') {
			if (after_key && c == '[' && coords_depth < 0)
				coords_depth = depth;
			after_key = false;
			depth++;
			leaf = c == '[';
		} else if (c == ']' || c == '}') {
			depth--;
			if (leaf && coords_depth >= 0)
				n++;
			leaf = false;
			if (depth == coords_depth)
				coords_depth = -1;
		} else if (c != ':' && c != ' ' && c != '\t' && c != '\n' && c != '\r') {
			after_key = false;
		}
	}
	return n;
}

/* The "crs" member (GeoJSON 2008; RFC 7946 dropped it and says WGS84):
 * {"type": "name", "properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}}
 * or "EPSG:4326" names WGS84 lon/lat, any other name another system. */
static int geo_crs(struct gctx *g, const struct json_value *root)
{
	const struct json_value *crs = root->type == JSON_OBJECT ? json_get(root, "crs") : NULL;
	if (!crs || crs->type == JSON_NULL)
		return CURVE_CRS_UNSAID;
	const struct json_value *pr = crs->type == JSON_OBJECT ? json_get(crs, "properties") : NULL;
	const struct json_value *nm = pr && pr->type == JSON_OBJECT ? json_get(pr, "name") : NULL;
	if (!nm || nm->type != JSON_STRING)
		return gfail(g, crs->line, "GeoJSON", "\"crs\" must be {\"type\": \"name\", \"properties\": {\"name\": "
			     "\"...\"}}");
	const char *n = nm->str;
	if (strstr(n, "CRS84") || strstr(n, "crs84") || strstr(n, "EPSG::4326") || strstr(n, "EPSG:4326") ||
	    strstr(n, "WGS84") || strstr(n, "WGS 84"))
		return CURVE_CRS_WGS84;
	return CURVE_CRS_OTHER;
}

/* The top level: a FeatureCollection, a Feature or a bare geometry. */
static int geo_root(struct gctx *g, const struct json_value *root)
{
	const struct json_value *t = root->type == JSON_OBJECT ? json_get(root, "type") : NULL;
	if (!t || t->type != JSON_STRING)
		return gfail(g, root->line, "GeoJSON", "the top level must be an object with a \"type\"");
	if (!strcmp(t->str, "FeatureCollection")) {
		const struct json_value *fs = json_get(root, "features");
		if (!fs || fs->type != JSON_ARRAY)
			return gfail(g, root->line, "GeoJSON", "a FeatureCollection needs a \"features\" array");
		for (int i = 0; i < fs->n; i++)
			if (geo_feature(g, &fs->items[i], i) < 0)
				return -1;
		return 0;
	}
	if (!strcmp(t->str, "Feature"))
		return geo_feature(g, root, 0);
	static const char *const geometries[] = { "LineString", "MultiLineString", "Polygon", "MultiPolygon", "Point",
						  "MultiPoint", "GeometryCollection" };
	for (size_t i = 0; i < sizeof(geometries) / sizeof(geometries[0]); i++)
		if (!strcmp(t->str, geometries[i]))
			return geo_geometry(g, root, NULL, "geometry");
	return gfail(g, t->line, "GeoJSON", "type \"%s\" is not GeoJSON (FeatureCollection, Feature, or a geometry: "
		     "LineString, MultiLineString, ...)", t->str);
}

/* The top level's bbox against the positions (geo_decide's ranges): a
 * note when some lie outside it (a longitude range across the
 * antimeridian, west > east, is not compared). */
static int bbox_note(struct gctx *g, const struct json_value *root, const struct geo_stats *st)
{
	const struct json_value *b = root->type == JSON_OBJECT ? json_get(root, "bbox") : NULL;
	if (!b || st->n == 0)
		return 0;
	int n = b->n / 2;
	double w = b->items[0].num, so = b->items[1].num, e = b->items[n].num, no = b->items[n + 1].num;
	double tol = 1e-9 * fmax(1.0, fmax(fabs(st->hi[0]) + fabs(st->lo[0]), fabs(st->hi[1]) + fabs(st->lo[1])));
	bool lon_in = w > e || (st->lo[0] >= w - tol && st->hi[0] <= e + tol);
	if (lon_in && st->lo[1] >= so - tol && st->hi[1] <= no + tol)
		return 0;
	return curve_set_note(g->s, "%s:%d: the \"bbox\" [%g, %g, %g, %g] does not hold every position: they span x "
			      "[%g, %g], y [%g, %g]; the positions are used", g->fname, b->line, w, so, e, no, st->lo[0],
			      st->hi[0], st->lo[1], st->hi[1]);
}

/* The skipped features, one note per reason. */
static int skip_notes(struct gctx *g)
{
	const struct skips *k[2] = { &g->other, &g->areas };
	static const char *const why[2] = { "not carved (only lines and polygons are)", "malformed areas" };
	if (g->classes.n) {
		char more[48] = "";
		if (g->classes.n > SKIP_NAMED)
			snprintf(more, sizeof(more), ", and %d more", g->classes.n - SKIP_NAMED);
		if (curve_set_note(g->s, "%s: %d feature%s of a highway class without a known width, given road_width: %s%s",
				   g->fname, g->classes.n, g->classes.n == 1 ? "" : "s", g->classes.named, more) < 0)
			return -1;
	}
	for (int i = 0; i < 2; i++) {
		if (!k[i]->n)
			continue;
		char more[48] = "";
		if (k[i]->n > SKIP_NAMED)
			snprintf(more, sizeof(more), ", and %d more", k[i]->n - SKIP_NAMED);
		if (curve_set_note(g->s, "%s: %d feature%s skipped, %s: %s%s", g->fname, k[i]->n, k[i]->n == 1 ? "" : "s",
				   why[i], k[i]->named, more) < 0)
			return -1;
	}
	return 0;
}

int curves_parse_geojson(const char *text, size_t len, const char *fname, struct curve_set *s, char *err,
			 size_t errlen)
{
	memset(s, 0, sizeof(*s));
	long npos = count_positions(text, len);
	if (npos > CURVE_MAX_POINTS) {
		snprintf(err, errlen, "%s: %ld positions in \"coordinates\", more than the %ld the curve tables may hold",
			 fname, npos, (long)CURVE_MAX_POINTS);
		return -1;
	}
	struct json_value root;
	if (json_parse(text, len, fname, &root, err, errlen) < 0)
		return -1;
	struct gctx g;
	memset(&g, 0, sizeof(g));
	g.fname = fname;
	g.err = err;
	g.errlen = errlen;
	g.s = s;
	snprintf(s->source, sizeof(s->source), "%s", fname);
	struct geo_stats st;
	int rc = geo_crs(&g, &root);
	if (rc >= 0) {
		g.crs = rc;
		geo_decide(&g, &root, &st);
		const struct json_value *t = json_get(&root, "type"); /* a Feature, a geometry: checked below */
		rc = t && t->type == JSON_STRING && !strcmp(t->str, "FeatureCollection") ? geo_bbox(&g, &root, "GeoJSON") : 0;
	}
	if (rc == 0)
		rc = geo_root(&g, &root);
	if (rc == 0 && s->npaths == 0) {
		char skipped[600] = "";
		if (g.other.n || g.areas.n)
			snprintf(skipped, sizeof(skipped), " (skipped: %s%s%s)", g.other.named, g.other.n && g.areas.n ? ", " : "",
				 g.areas.named);
		rc = gfail(&g, root.line, "GeoJSON", "no line strings or polygons to carve%s", skipped);
	}
	if (rc == 0 && (bbox_note(&g, &root, &st) < 0 || skip_notes(&g) < 0 ||
			(g.n3d && !g.n3d_nonzero && curves_flat_zero(s, g.n3d, "z (up)") < 0)))
		rc = gfail(&g, root.line, "GeoJSON", "out of memory");
	json_free(&root);
	if (rc < 0)
		curve_set_free(s);
	return rc;
}
