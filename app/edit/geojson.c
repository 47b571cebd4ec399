/* isoterra — curve input, GeoJSON: FeatureCollection / Feature /
 * LineString / MultiLineString with [x, y, z] positions and the per-path
 * parameters in "properties".  Errors name file:line and the feature. */
#include "curves.h"
#include "curves_internal.h"
#include "json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct gctx {
	const char *fname;
	char *err;
	size_t errlen;
	struct curve_set *s;
};

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
			return gfail(g, k->line, what, "\"kind\" must be \"road\", \"river\", \"railway\" or \"tunnel\"");
		curve_path_defaults(base, curve_kind_parse(k->str));
	}
	for (int i = 0; i < CURVE_NPARAMS; i++) {
		const struct json_value *v = json_get(props, curve_param_names[i]);
		if (!v)
			continue;
		if (v->type != JSON_NUMBER)
			return gfail(g, v->line, what, "\"%s\" must be a number, not %s", curve_param_names[i],
				     json_type_names[v->type]);
		const char *why = curve_param_check(curve_param_names[i], v->num);
		if (why)
			return gfail(g, v->line, what, "\"%s\" = %g %s", curve_param_names[i], v->num, why);
		*curve_param_slot(base, i) = (float)v->num;
	}
	return 0;
}

static int geo_line(struct gctx *g, const struct json_value *coords, const char *what, const struct curve_path *base,
		    int part)
{
	char label[96];
	if (part >= 0)
		snprintf(label, sizeof(label), "%s, line string %d", what, part + 1);
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
	for (int i = 0; i < coords->n; i++) {
		const struct json_value *pos = &coords->items[i];
		if (pos->type != JSON_ARRAY) {
			free(p.pts);
			return gfail(g, pos->line, label, "position %d must be an array [x, y, z], not %s", i + 1,
				     json_type_names[pos->type]);
		}
		if (pos->n != 3) {
			free(p.pts);
			return gfail(g, pos->line, label, "position %d has %d coordinates; 3D positions [x, y, z] are needed",
				     i + 1, pos->n);
		}
		double c[3];
		for (int a = 0; a < 3; a++) {
			if (pos->items[a].type != JSON_NUMBER || !isfinite(pos->items[a].num) || fabs(pos->items[a].num) > 1e7) {
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

static int geo_geometry(struct gctx *g, const struct json_value *geom, const struct json_value *props, const char *what)
{
	if (!geom || geom->type != JSON_OBJECT)
		return gfail(g, geom ? geom->line : 1, what, "\"geometry\" must be a LineString or MultiLineString object%s",
			     geom && geom->type == JSON_NULL ? " (it is null)" : "");
	const struct json_value *t = json_get(geom, "type");
	if (!t || t->type != JSON_STRING)
		return gfail(g, geom->line, what, "geometry has no \"type\"");
	const struct json_value *coords = json_get(geom, "coordinates");
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
	if (coords->type != JSON_ARRAY || coords->n < 1)
		return gfail(g, coords->line, what, "MultiLineString \"coordinates\" must be a non-empty array of line strings");
	for (int i = 0; i < coords->n; i++)
		if (geo_line(g, &coords->items[i], what, &base, i) < 0)
			return -1;
	return 0;
}

static int geo_feature(struct gctx *g, const struct json_value *f, int idx)
{
	char what[48];
	snprintf(what, sizeof(what), "feature %d", idx + 1);
	if (f->type != JSON_OBJECT)
		return gfail(g, f->line, what, "must be an object, not %s", json_type_names[f->type]);
	const struct json_value *t = json_get(f, "type");
	if (!t || t->type != JSON_STRING || strcmp(t->str, "Feature"))
		return gfail(g, f->line, what, "\"type\" must be \"Feature\"");
	return geo_geometry(g, json_get(f, "geometry"), json_get(f, "properties"), what);
}

int curves_parse_geojson(const char *text, size_t len, const char *fname, struct curve_set *s, char *err,
			 size_t errlen)
{
	memset(s, 0, sizeof(*s));
	struct json_value root;
	if (json_parse(text, len, fname, &root, err, errlen) < 0)
		return -1;
	struct gctx g = { fname, err, errlen, s };
	int rc = 0;
	const struct json_value *t = root.type == JSON_OBJECT ? json_get(&root, "type") : NULL;
	if (!t || t->type != JSON_STRING) {
		rc = gfail(&g, root.line, "GeoJSON", "the top level must be an object with a \"type\"");
	} else if (!strcmp(t->str, "FeatureCollection")) {
		const struct json_value *fs = json_get(&root, "features");
		if (!fs || fs->type != JSON_ARRAY)
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
	json_free(&root);
	if (rc < 0)
		curve_set_free(s);
	return rc;
}
