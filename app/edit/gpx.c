/* isoterra — curve input, GPX 1.0 / 1.1 (GPS eXchange Format): each track
 * segment (trk/trkseg/trkpt) and each route (rte/rtept) is one path,
 * lat/lon WGS84 degrees (stored as degrees from their centroid, like
 * GeoJSON's lon/lat, for curves_geo_project), <ele> metres as the height;
 * without <ele> the path follows the ground.  The XML is read by libexpat
 * (namespaces resolved: elements of other namespaces, extensions, are
 * ignored; a DTD is refused, so no entity is ever expanded).  Errors name
 * file:line; waypoints and segments of one point are skipped with a note. */
#include "curves.h"
#include "curves_internal.h"

#include <expat.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define NS_SEP '|'
#define MAX_DEPTH 256
#define MAX_SEGMENTS (1 << 20) /* paths of 2 points or more: 2^20 of them fill the tables (CURVE_MAX_POINTS) */

enum gpx_el { EL_OTHER, EL_GPX, EL_TRK, EL_TRKSEG, EL_TRKPT, EL_RTE, EL_RTEPT, EL_ELE, EL_NAME, EL_WPT };

struct gpx_pt {
	double lon, lat, ele; /* ele: NAN when the point has none */
};

/* One path: points [first, first + n) of the point list. */
struct gpx_seg {
	long first;
	int n;
	int line;       /* where it starts */
	bool route;
	int track;      /* 1-based track or route number, segment within it */
	int part;
	char name[64];
};

struct gpx {
	XML_Parser xp;
	const char *fname;
	char *err;
	size_t errlen;
	bool failed;
	int depth;
	enum gpx_el stack[MAX_DEPTH];
	struct gpx_pt *pts;
	long npts, cap;
	struct gpx_seg *segs;
	int nsegs, segcap;
	int ntrk, nrte, nwpt;
	int part;           /* segments so far in the current track */
	char name[64];      /* the current track's or route's <name> */
	char text[64]; /* <ele> / <name> character data */
	size_t textlen;
	bool text_long;
};

/* The parser's line now (expat 2.7 on: its 64-bit call; the old one is
 * deprecated there). */
static unsigned long xml_line(XML_Parser xp)
{
#ifdef ISOTERRA_HAVE_XML_LINE64
	return (unsigned long)XML_GetCurrentLineNumber64(xp);
#else
	return (unsigned long)XML_GetCurrentLineNumber(xp);
#endif
}

static void gpx_fail(struct gpx *g, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void gpx_fail(struct gpx *g, const char *fmt, ...)
{
	if (g->failed)
		return;
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	snprintf(g->err, g->errlen, "%s:%lu: %s", g->fname, xml_line(g->xp), msg);
	g->failed = true;
	XML_StopParser(g->xp, XML_FALSE);
}

/* The element's kind: its local name in the GPX 1.0 or 1.1 namespace (or
 * none); anything else is EL_OTHER. */
static enum gpx_el element_kind(const XML_Char *name)
{
	const char *local = strrchr(name, NS_SEP);
	if (local) {
		size_t ns = (size_t)(local - name);
		if (!(ns == 33 && !strncmp(name, "http://www.topografix.com/GPX/1/1", ns)) &&
		    !(ns == 33 && !strncmp(name, "http://www.topografix.com/GPX/1/0", ns)))
			return EL_OTHER;
		local++;
	} else {
		local = name;
	}
	static const struct {
		const char *name;
		enum gpx_el el;
	} els[] = { { "gpx", EL_GPX },     { "trk", EL_TRK }, { "trkseg", EL_TRKSEG }, { "trkpt", EL_TRKPT },
		    { "rte", EL_RTE },     { "rtept", EL_RTEPT }, { "ele", EL_ELE },     { "name", EL_NAME },
		    { "wpt", EL_WPT } };
	for (size_t i = 0; i < sizeof(els) / sizeof(els[0]); i++)
		if (!strcmp(local, els[i].name))
			return els[i].el;
	return EL_OTHER;
}

/* A decimal number, all of s (white space around it allowed), finite. */
static bool parse_number(const char *s, double *v)
{
	char *end;
	while (*s == ' ' || *s == '\t' || *s == '\n' || *s == '\r')
		s++;
	if (!*s)
		return false;
	*v = strtod(s, &end);
	while (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r')
		end++;
	return *end == 0 && isfinite(*v);
}

static const char *attr(const XML_Char **atts, const char *name)
{
	for (int i = 0; atts[i]; i += 2)
		if (!strcmp(atts[i], name)) /* unprefixed attributes have no namespace */
			return atts[i + 1];
	return NULL;
}

static void start_segment(struct gpx *g, bool route, int track, int part)
{
	if (g->nsegs >= MAX_SEGMENTS) {
		gpx_fail(g, "more than %d track segments and routes", MAX_SEGMENTS);
		return;
	}
	if (g->nsegs == g->segcap) {
		int cap = g->segcap ? 2 * g->segcap : 16;
		struct gpx_seg *n = realloc(g->segs, sizeof(*n) * (size_t)cap);
		if (!n) {
			gpx_fail(g, "out of memory");
			return;
		}
		g->segs = n;
		g->segcap = cap;
	}
	struct gpx_seg *s = &g->segs[g->nsegs++];
	memset(s, 0, sizeof(*s));
	s->first = g->npts;
	s->line = (int)xml_line(g->xp);
	s->route = route;
	s->track = track;
	s->part = part;
	snprintf(s->name, sizeof(s->name), "%s", g->name);
}

static void add_point(struct gpx *g, const char *el, const XML_Char **atts)
{
	const char *slat = attr(atts, "lat"), *slon = attr(atts, "lon");
	double lat, lon;
	if (!slat || !slon) {
		gpx_fail(g, "<%s> has no %s attribute (every point needs lat and lon, WGS84 degrees)", el,
			 !slat ? "lat" : "lon");
		return;
	}
	if (!parse_number(slat, &lat) || !(fabs(lat) <= 90.0)) {
		gpx_fail(g, "<%s> lat=\"%.40s\" is not a latitude in [-90, 90]", el, slat);
		return;
	}
	if (!parse_number(slon, &lon) || !(fabs(lon) <= 180.0)) {
		gpx_fail(g, "<%s> lon=\"%.40s\" is not a longitude in [-180, 180]", el, slon);
		return;
	}
	if (g->npts >= CURVE_MAX_POINTS) {
		gpx_fail(g, "more than the %ld points the curve tables may hold", (long)CURVE_MAX_POINTS);
		return;
	}
	if (g->npts == g->cap) {
		long cap = g->cap ? 2 * g->cap : 256;
		struct gpx_pt *n = realloc(g->pts, sizeof(*n) * (size_t)cap);
		if (!n) {
			gpx_fail(g, "out of memory");
			return;
		}
		g->pts = n;
		g->cap = cap;
	}
	g->pts[g->npts++] = (struct gpx_pt){ lon, lat, NAN };
	g->segs[g->nsegs - 1].n++;
}

static void XMLCALL on_start(void *ud, const XML_Char *name, const XML_Char **atts)
{
	struct gpx *g = ud;
	if (g->failed)
		return;
	if (g->depth >= MAX_DEPTH) {
		gpx_fail(g, "elements nested deeper than %d", MAX_DEPTH);
		return;
	}
	enum gpx_el el = element_kind(name), parent = g->depth ? g->stack[g->depth - 1] : EL_OTHER;
	if (g->depth == 0 && el != EL_GPX) {
		const char *local = strrchr(name, NS_SEP);
		gpx_fail(g, "not GPX: the root element is <%.40s>, not <gpx>", local ? local + 1 : name);
		return;
	}
	g->stack[g->depth++] = el;
	g->textlen = 0;
	g->text_long = false;
	switch (el) {
	case EL_TRK:
	case EL_RTE:
		if (parent != EL_GPX) {
			gpx_fail(g, "<%s> must be inside the <gpx>", el == EL_TRK ? "trk" : "rte");
			return;
		}
		g->name[0] = 0;
		g->part = 0;
		if (el == EL_TRK)
			g->ntrk++;
		else
			start_segment(g, true, ++g->nrte, 0);
		break;
	case EL_WPT:
		g->nwpt += parent == EL_GPX;
		break;
	case EL_TRKSEG:
		if (parent != EL_TRK) {
			gpx_fail(g, "<trkseg> must be inside a <trk>");
			return;
		}
		start_segment(g, false, g->ntrk, ++g->part);
		break;
	case EL_TRKPT:
	case EL_RTEPT:
		if (parent != (el == EL_TRKPT ? EL_TRKSEG : EL_RTE)) {
			gpx_fail(g, "<%s> must be inside a <%s>", el == EL_TRKPT ? "trkpt" : "rtept",
				 el == EL_TRKPT ? "trkseg" : "rte");
			return;
		}
		add_point(g, el == EL_TRKPT ? "trkpt" : "rtept", atts);
		break;
	default:
		break;
	}
}

static void XMLCALL on_text(void *ud, const XML_Char *s, int len)
{
	struct gpx *g = ud;
	if (g->failed || !g->depth || (g->stack[g->depth - 1] != EL_ELE && g->stack[g->depth - 1] != EL_NAME))
		return;
	if (g->textlen + (size_t)len >= sizeof(g->text)) {
		g->text_long = true;
		len = (int)(sizeof(g->text) - 1 - g->textlen);
	}
	memcpy(g->text + g->textlen, s, (size_t)len);
	g->textlen += (size_t)len;
	g->text[g->textlen] = 0;
}

static void XMLCALL on_end(void *ud, const XML_Char *name)
{
	struct gpx *g = ud;
	(void)name;
	if (g->failed || !g->depth)
		return;
	enum gpx_el el = g->stack[--g->depth], parent = g->depth ? g->stack[g->depth - 1] : EL_OTHER;
	g->text[g->textlen] = 0;
	if (el == EL_ELE && (parent == EL_TRKPT || parent == EL_RTEPT)) {
		double e;
		if (g->text_long || !parse_number(g->text, &e) || !(fabs(e) <= 1e6)) {
			gpx_fail(g, "<ele>%.40s</ele> is not a height in metres within +-1e6", g->text);
			return;
		}
		g->pts[g->npts - 1].ele = e;
	} else if (el == EL_NAME && (parent == EL_TRK || parent == EL_RTE)) {
		/* the track's or route's name, for messages: its segments so far
		 * and those to come */
		snprintf(g->name, sizeof(g->name), "%s", g->text);
		for (int i = g->nsegs - 1; i >= 0; i--) {
			struct gpx_seg *s = &g->segs[i];
			if (s->route != (parent == EL_RTE) || s->track != (parent == EL_RTE ? g->nrte : g->ntrk))
				break;
			snprintf(s->name, sizeof(s->name), "%s", g->name);
		}
	}
	g->textlen = 0;
}

static void XMLCALL on_doctype(void *ud, const XML_Char *name, const XML_Char *sysid, const XML_Char *pubid,
			       int internal)
{
	(void)name, (void)sysid, (void)pubid, (void)internal;
	gpx_fail(ud, "a DTD (<!DOCTYPE ...>) has no place in GPX: refused");
}

static double dlon(double lon, double lon0)
{
	double d = fmod(lon - lon0 + 540.0, 360.0);
	return (d < 0.0 ? d + 360.0 : d) - 180.0;
}

/* The segments as paths, degrees from the points' centroid. */
static int build_paths(struct gpx *g, struct curve_set *s)
{
	double sx = 0.0, sy = 0.0, ref = g->npts ? g->pts[0].lon : 0.0;
	for (long i = 0; i < g->npts; i++) {
		sx += dlon(g->pts[i].lon, ref);
		sy += g->pts[i].lat;
	}
	double origin[2] = { g->npts ? dlon(ref + sx / (double)g->npts, 0.0) : 0.0,
			     g->npts ? sy / (double)g->npts : 0.0 };
	int short_segs = 0, partial_ele = 0;
	long n_ele = 0, n_ele_nonzero = 0;
	snprintf(s->source, sizeof(s->source), "%s", g->fname);
	char first_short[96] = "", first_partial[96] = "";
	for (int k = 0; k < g->nsegs; k++) {
		const struct gpx_seg *sg = &g->segs[k];
		char label[160];
		int len = snprintf(label, sizeof(label), "%s %d", sg->route ? "route" : "track", sg->track);
		if (sg->name[0])
			len += snprintf(label + len, sizeof(label) - (size_t)len, " \"%.60s\"", sg->name);
		if (!sg->route)
			snprintf(label + len, sizeof(label) - (size_t)len, ", segment %d", sg->part);
		struct curve_path p;
		memset(&p, 0, sizeof(p));
		curve_path_defaults(&p, CURVE_ROAD);
		p.npts = sg->n;
		p.pts = malloc(sizeof(float) * 3 * (size_t)(sg->n > 0 ? sg->n : 1));
		if (!p.pts) {
			snprintf(g->err, g->errlen, "%s: out of memory", g->fname);
			return -1;
		}
		int with_ele = 0;
		for (int i = 0; i < sg->n; i++) {
			const struct gpx_pt *q = &g->pts[sg->first + i];
			with_ele += !isnan(q->ele);
			p.pts[3 * i + 0] = (float)dlon(q->lon, origin[0]);
			p.pts[3 * i + 1] = isnan(q->ele) ? 0.0f : (float)q->ele;
			p.pts[3 * i + 2] = (float)-(q->lat - origin[1]);
		}
		p.follow_ground = with_ele < sg->n; /* heights from the ground unless every point has one */
		for (int i = 0; i < sg->n && !p.follow_ground; i++) {
			n_ele++;
			n_ele_nonzero += g->pts[sg->first + i].ele != 0.0;
		}
		if (with_ele > 0 && with_ele < sg->n && partial_ele++ == 0)
			snprintf(first_partial, sizeof(first_partial), "%.60s (line %d)", label, sg->line);
		p.crs = CURVE_CRS_WGS84;
		p.geo_rel = true;
		p.geo_origin[0] = origin[0];
		p.geo_origin[1] = origin[1];
		snprintf(p.label, sizeof(p.label), "%.80s: %.100s", g->fname, label);
		int rc = 0;
		if (curve_path_dedup(&p) < 2) {
			if (short_segs++ == 0)
				snprintf(first_short, sizeof(first_short), "%.60s (line %d)", label, sg->line);
		} else {
			rc = curve_set_add(s, &p);
		}
		free(p.pts);
		if (rc < 0) {
			snprintf(g->err, g->errlen, "%s: out of memory", g->fname);
			return -1;
		}
	}
	if (s->npaths == 0) {
		snprintf(g->err, g->errlen, "%s: no track segment or route of 2 distinct points to carve (%d track%s, %d "
			 "route%s, %d waypoint%s)", g->fname, g->ntrk, g->ntrk == 1 ? "" : "s", g->nrte,
			 g->nrte == 1 ? "" : "s", g->nwpt, g->nwpt == 1 ? "" : "s");
		return -1;
	}
	int rc = 0;
	if (n_ele && !n_ele_nonzero)
		rc |= curves_flat_zero(s, n_ele, "<ele>");
	if (short_segs)
		rc |= curve_set_note(s, "%s: %d track segment%s or route%s of fewer than 2 distinct points skipped, the first "
				     "%s", g->fname, short_segs, short_segs == 1 ? "" : "s", short_segs == 1 ? "" : "s",
				     first_short);
	if (partial_ele)
		rc |= curve_set_note(s, "%s: %d path%s with <ele> on some points only, those follow the ground instead, the "
				     "first %s", g->fname, partial_ele, partial_ele == 1 ? "" : "s", first_partial);
	if (g->nwpt)
		rc |= curve_set_note(s, "%s: %d waypoint%s (<wpt>) skipped: points are not carved", g->fname, g->nwpt,
				     g->nwpt == 1 ? "" : "s");
	if (rc < 0) {
		snprintf(g->err, g->errlen, "%s: out of memory", g->fname);
		return -1;
	}
	return 0;
}

int curves_parse_gpx(const char *text, size_t len, const char *fname, struct curve_set *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof(*s));
	if (len > INT_MAX) {
		snprintf(err, errlen, "%s: larger than %d bytes", fname, INT_MAX);
		return -1;
	}
	struct gpx g;
	memset(&g, 0, sizeof(g));
	g.fname = fname;
	g.err = err;
	g.errlen = errlen;
	g.xp = XML_ParserCreateNS(NULL, NS_SEP);
	if (!g.xp) {
		snprintf(err, errlen, "%s: out of memory", fname);
		return -1;
	}
	XML_SetUserData(g.xp, &g);
	XML_SetElementHandler(g.xp, on_start, on_end);
	XML_SetCharacterDataHandler(g.xp, on_text);
	XML_SetStartDoctypeDeclHandler(g.xp, on_doctype);
	int rc = 0;
	if (XML_Parse(g.xp, text, (int)len, XML_TRUE) != XML_STATUS_OK && !g.failed)
		snprintf(err, errlen, "%s:%lu: invalid XML: %s", fname, xml_line(g.xp),
			 XML_ErrorString(XML_GetErrorCode(g.xp)));
	if (g.failed || XML_GetErrorCode(g.xp) != XML_ERROR_NONE)
		rc = -1;
	if (rc == 0)
		rc = build_paths(&g, s);
	XML_ParserFree(g.xp);
	free(g.pts);
	free(g.segs);
	if (rc < 0)
		curve_set_free(s);
	return rc;
}
