/* isoterra — geographic curve input: WGS84 lon/lat detected (or made from
 * an EPSG-coded CRS) and put in the local east-north-up frame of a
 * georeferenced heightmap or of the data's centroid, and 2D curves put on
 * the terrain's surface.  See curves.h and docs/CURVES.md. */
#include "curves.h"
#include "geo_enu.h"
#include "params.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <strings.h>

/* Longitude difference folded into [-180, 180) (data across the antimeridian). */
static double dlon(double lon, double lon0)
{
	double d = fmod(lon - lon0 + 540.0, 360.0);
	return (d < 0.0 ? d + 360.0 : d) - 180.0;
}

int curves_crs_parse(const char *text, int *mode, char *err, size_t errlen)
{
	static const char *const names[] = { "auto", "lonlat", "local" };
	for (int i = 0; i < 3; i++)
		if (!strcmp(text, names[i])) {
			*mode = i;
			return 0;
		}
	char *end = NULL;
	long code = !strncasecmp(text, "EPSG:", 5) ? strtol(text + 5, &end, 10) : 0;
	if (code > 0 && code < 1000000 && end && !*end) {
		*mode = CURVES_CRS_NAMED;
		return 0;
	}
	snprintf(err, errlen, "curves_crs '%s': auto, lonlat, local or EPSG:CODE (e.g. EPSG:32633)", text);
	return -1;
}

int curves_from_crs(struct curve_set *s, const char *crs, curves_to_lonlat_fn to_lonlat, char *name, size_t namelen,
		    char *err, size_t errlen)
{
	size_t n = 0;
	for (int i = 0; i < s->npaths; i++)
		n += (size_t)s->paths[i].npts;
	double *xy = malloc(sizeof(double) * 2 * (n ? n : 1));
	if (!xy) {
		snprintf(err, errlen, "%s: out of memory", s->source);
		return -1;
	}
	size_t m = 0;
	for (int i = 0; i < s->npaths; i++) {
		const struct curve_path *p = &s->paths[i];
		for (int k = 0; k < p->npts; k++, m++) {
			const float *q = p->pts + 3 * k;
			xy[2 * m] = p->geo_rel ? p->geo_origin[0] + q[0] : q[0];
			xy[2 * m + 1] = p->geo_rel ? p->geo_origin[1] - q[2] : -q[2];
		}
	}
	char e[512];
	if (to_lonlat(crs, xy, n, name, namelen, e, sizeof(e)) < 0) {
		snprintf(err, errlen, "%s: %s", s->source, e);
		free(xy);
		return -1;
	}
	m = 0;
	for (int i = 0; i < s->npaths; i++) {
		struct curve_path *p = &s->paths[i];
		p->geo_rel = true;
		p->geo_origin[0] = xy[0];
		p->geo_origin[1] = xy[1];
		for (int k = 0; k < p->npts; k++, m++) {
			p->pts[3 * k] = (float)dlon(xy[2 * m], xy[0]);
			p->pts[3 * k + 2] = (float)(xy[1] - xy[2 * m + 1]);
		}
	}
	free(xy);
	return 0;
}

static bool choose_lonlat(const struct curve_set *s, int mode, const char **why)
{
	const struct curve_path *p = &s->paths[0]; /* one file: the same for every path */
	if (mode == CURVES_CRS_NAMED) {
		*why = "curves_crs names a projected CRS";
		return true;
	}
	if (mode == CURVES_CRS_LONLAT) {
		*why = "curves_crs=lonlat";
		return true;
	}
	if (mode == CURVES_CRS_LOCAL) {
		*why = "curves_crs=local";
		return false;
	}
	if (p->crs == CURVE_CRS_WGS84)
		*why = "the file names WGS84: a crs member, or GPX";
	else if (p->crs == CURVE_CRS_OTHER)
		*why = "the crs member names another system";
	else if (p->geo_rel)
		*why = "no crs member, every position within lon/lat ranges: RFC 7946's WGS84";
	else
		*why = "the values are not lon/lat of a small area";
	return p->geo_rel;
}

/* Every path's positions as degrees from one origin (lon, lat): as the
 * reader stored them, or (lon/lat forced on absolute values) from their
 * centroid.  -1 with err for a latitude beyond +-90. */
static int to_relative(struct curve_set *s, double origin[2], char *err, size_t errlen)
{
	if (s->paths[0].geo_rel) {
		origin[0] = s->paths[0].geo_origin[0];
		origin[1] = s->paths[0].geo_origin[1];
	} else {
		double ref = s->paths[0].pts[0], sx = 0.0, sy = 0.0;
		long n = 0;
		for (int i = 0; i < s->npaths; i++)
			for (int k = 0; k < s->paths[i].npts; k++, n++) {
				sx += dlon(s->paths[i].pts[3 * k], ref);
				sy -= s->paths[i].pts[3 * k + 2];
			}
		origin[0] = dlon(ref + sx / (double)n, 0.0);
		origin[1] = sy / (double)n;
		for (int i = 0; i < s->npaths; i++)
			for (int k = 0; k < s->paths[i].npts; k++) {
				float *q = s->paths[i].pts + 3 * k;
				q[0] = (float)dlon(q[0], origin[0]);
				q[2] = (float)(q[2] + origin[1]);
			}
	}
	for (int i = 0; i < s->npaths; i++)
		for (int k = 0; k < s->paths[i].npts; k++) {
			double lat = origin[1] - s->paths[i].pts[3 * k + 2];
			if (!(fabs(lat) <= 90.0)) {
				snprintf(err, errlen, "%s: position %d: latitude %g (y north) is not within [-90, 90]",
					 s->paths[i].label, k + 1, lat);
				return -1;
			}
		}
	return 0;
}

int curves_geo_project(struct curve_set *s, int mode, float scale, const struct curves_geo_frame *frame, bool *lonlat,
		       const char **why, double origin[2], char *err, size_t errlen)
{
	origin[0] = origin[1] = 0.0;
	*lonlat = false;
	*why = "no curves";
	if (s->npaths == 0)
		return 0;
	*lonlat = choose_lonlat(s, mode, why);
	/* lon/lat by the auto rule alone over more than a degree: world units
	 * that small would be taken the same way, so it is said */
	if (*lonlat && mode == CURVES_CRS_AUTO && s->paths[0].crs == CURVE_CRS_UNSAID &&
	    (s->geo_span[0] > 1.0 || s->geo_span[1] > 1.0) &&
	    curve_set_note(s, "%s: no crs member and every position within lon/lat ranges, spanning %.4g degrees of "
			   "longitude and %.4g of latitude: taken as WGS84 lon/lat (CRS84, RFC 7946); world units need "
			   "curves_crs = local or a crs member naming their system", s->source, s->geo_span[0],
			   s->geo_span[1]) < 0) {
		snprintf(err, errlen, "%s: out of memory", s->source);
		return -1;
	}
	if (!*lonlat) {
		for (int i = 0; i < s->npaths; i++) { /* world units: absolute again */
			struct curve_path *p = &s->paths[i];
			for (int k = 0; p->geo_rel && k < p->npts; k++) {
				p->pts[3 * k] = (float)(p->pts[3 * k] + p->geo_origin[0]);
				p->pts[3 * k + 2] = (float)(p->pts[3 * k + 2] - p->geo_origin[1]);
			}
			p->geo_rel = false;
		}
		return 0;
	}
	double data[2];
	if (to_relative(s, data, err, errlen) < 0)
		return -1;
	struct geo_enu f;
	origin[0] = frame ? frame->lon0 : data[0];
	origin[1] = frame ? frame->lat0 : data[1];
	geo_enu_init(&f, origin[0], origin[1]);
	float ys = frame ? frame->yscale : scale;
	for (int i = 0; i < s->npaths; i++) {
		for (int k = 0; k < s->paths[i].npts; k++) {
			float *q = s->paths[i].pts + 3 * k;
			double e, n;
			geo_enu_forward(&f, data[0] + q[0], data[1] - q[2], &e, &n);
			q[0] = (float)(e * scale);
			q[1] = q[1] * ys;
			q[2] = (float)(-n * scale); /* world z = -north */
		}
		s->paths[i].geo_rel = false;
	}
	return 0;
}

#define FOLLOW_MAX_POINTS 1000000

/* Path p with points inserted so no XZ segment is longer than step: 0, -1
 * when out of memory, -2 beyond FOLLOW_MAX_POINTS. */
static int densify(struct curve_path *p, float step)
{
	int n = 1;
	for (int k = 1; k < p->npts; k++) {
		float dx = p->pts[3 * k] - p->pts[3 * k - 3], dz = p->pts[3 * k + 2] - p->pts[3 * k - 1];
		float len = sqrtf(dx * dx + dz * dz);
		n += len > step ? (int)ceilf(len / step) : 1;
		if (n > FOLLOW_MAX_POINTS)
			return -2;
	}
	float *out = malloc(sizeof(float) * 3 * (size_t)n);
	if (!out)
		return -1;
	int m = 0;
	memcpy(out, p->pts, sizeof(float) * 3);
	m = 1;
	for (int k = 1; k < p->npts; k++) {
		const float *a = p->pts + 3 * k - 3, *b = p->pts + 3 * k;
		float dx = b[0] - a[0], dz = b[2] - a[2];
		float len = sqrtf(dx * dx + dz * dz);
		int parts = len > step ? (int)ceilf(len / step) : 1;
		for (int j = 1; j <= parts; j++) {
			float t = (float)j / (float)parts;
			out[3 * m] = a[0] + dx * t;
			out[3 * m + 1] = 0.0f;
			out[3 * m + 2] = a[2] + dz * t;
			m++;
		}
	}
	free(p->pts);
	p->pts = out;
	p->npts = m;
	return 0;
}

/* A bridge's deck and a tunnel's bore run straight (along the path's
 * length) from the ground at one end to the ground at the other, not over
 * the valley's floor or the hill's top. */
static void straight_between_ends(struct curve_path *p)
{
	double len = 0.0, at = 0.0;
	for (int k = 1; k < p->npts; k++)
		len += hypot(p->pts[3 * k] - p->pts[3 * k - 3], p->pts[3 * k + 2] - p->pts[3 * k - 1]);
	float y0 = p->pts[1], y1 = p->pts[3 * (p->npts - 1) + 1];
	for (int k = 1; k < p->npts - 1; k++) {
		at += hypot(p->pts[3 * k] - p->pts[3 * k - 3], p->pts[3 * k + 2] - p->pts[3 * k - 1]);
		p->pts[3 * k + 1] = y0 + (y1 - y0) * (float)(len > 0.0 ? at / len : 0.0);
	}
}

/* A 3D road or railway that runs more than its reach (w/2 + λ) above the
 * ground for two points or more is a bridge there, below it a tunnel: the
 * path is cut into runs, each a path of its own (the run's end points
 * shared, so the parts join).  Returns the number of parts added, -1 when
 * out of memory. */
static int split_off_ground(struct curve_set *s, int i, curve_ground_fn ground, void *ctx)
{
	struct curve_path *p = &s->paths[i];
	if ((p->kind != CURVE_ROAD && p->kind != CURVE_RAILWAY) || p->area || p->npts < 2)
		return 0;
	int n = p->npts;
	signed char *cls = malloc((size_t)n);
	if (!cls)
		return -1;
	float thr = curve_path_reach(p);
	bool any = false;
	for (int k = 0; k < n; k++) {
		const float *q = p->pts + 3 * k;
		float g;
		cls[k] = 0;
		if (ground(ctx, q[0], q[2], &g))
			cls[k] = (signed char)(q[1] - g > thr ? 1 : g - q[1] > thr ? -1 : 0);
	}
	/* a lone point off the ground is noise, not a structure */
	for (int k = 0; k < n; k++)
		if (cls[k] && (k == 0 || cls[k - 1] != cls[k]) && (k == n - 1 || cls[k + 1] != cls[k]))
			cls[k] = 0;
	for (int k = 0; k < n; k++)
		any |= cls[k] != 0;
	if (!any) {
		free(cls);
		return 0;
	}
	struct curve_path whole = *p; /* its points, owned here from now */
	p->pts = NULL;
	p->npts = 0;
	int added = 0, first = 1;
	/* segment k's class: an end's that is off the ground (so a structure
	 * takes the points where it meets the ground) */
#define SEG(k) (cls[(k) + 1] != 0 ? cls[(k) + 1] : cls[(k)])
	for (int a = 0; a < n - 1;) {
		int b = a + 1;
		int c = SEG(a);
		while (b < n - 1 && SEG(b) == c)
			b++;
#undef SEG
		/* run [a, b]: kind by c */
		struct curve_path part = whole;
		part.npts = b - a + 1;
		part.pts = whole.pts + 3 * a;
		if (c != 0) {
			curve_path_defaults(&part, c > 0 ? CURVE_BRIDGE : CURVE_TUNNEL);
			part.surface = whole.surface;
			part.width = whole.width;
			part.width_set = true;
		}
		snprintf(part.label, sizeof(part.label), "%.150s, %s part", whole.label, curve_kind_names[part.kind]);
		if (first) {
			float *pts = malloc(sizeof(float) * 3 * (size_t)part.npts);
			if (!pts)
				goto oom;
			memcpy(pts, part.pts, sizeof(float) * 3 * (size_t)part.npts);
			part.pts = pts;
			s->paths[i] = part;
			p = &s->paths[i];
			first = 0;
		} else {
			if (curve_set_add(s, &part) < 0)
				goto oom;
			added++;
		}
		a = b;
	}
	free(whole.pts);
	free(cls);
	return added;
oom:
	free(whole.pts);
	free(cls);
	return -1;
}

int curves_follow_ground(struct curve_set *s, float step, curve_ground_fn ground, void *ctx, char *err, size_t errlen)
{
	int nsplit = 0, nbridge = 0, ntunnel = 0;
	for (int i = 0, n0 = s->npaths; i < n0 && ground; i++) {
		if (s->paths[i].follow_ground)
			continue;
		int before = s->npaths, kind0 = s->paths[i].kind;
		int rc = split_off_ground(s, i, ground, ctx);
		if (rc < 0) {
			snprintf(err, errlen, "%s: out of memory", s->paths[i].label);
			return -1;
		}
		if (rc == 0 && s->paths[i].kind == kind0)
			continue;
		nsplit++;
		/* path i's first part, then the parts added after it */
		for (int j = i; j < s->npaths; j = j == i ? before : j + 1) {
			nbridge += s->paths[j].kind == CURVE_BRIDGE;
			ntunnel += s->paths[j].kind == CURVE_TUNNEL;
		}
	}
	if (nsplit && curve_set_note(s, "%s: %d 3D path%s run%s far above or below the ground: %d bridge and %d tunnel "
				     "part%s made (more than w/2 + falloff off the ground for two points or more)",
				     s->source, nsplit, nsplit == 1 ? "" : "s", nsplit == 1 ? "s" : "", nbridge, ntunnel,
				     nbridge + ntunnel == 1 ? "" : "s") < 0) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	for (int i = 0; i < s->npaths; i++) {
		struct curve_path *p = &s->paths[i];
		if (!p->follow_ground)
			continue;
		if (!ground) {
			snprintf(err, errlen, "%s: 2D positions [x east, y north] follow the terrain, and there is none to "
				 "follow here; give [x east, y north, z up]", p->label);
			return -1;
		}
		int rc = densify(p, step);
		if (rc == -2) {
			snprintf(err, errlen, "%s: more than %d points at most curves_follow_step = %g apart to follow the "
				 "ground: is it in the units meant (curves_crs, curves_geo_scale)?", p->label,
				 FOLLOW_MAX_POINTS, (double)step);
			return -1;
		}
		if (rc < 0) {
			snprintf(err, errlen, "%s: out of memory following the ground", p->label);
			return -1;
		}
		for (int k = 0; k < p->npts; k++) {
			float *q = p->pts + 3 * k;
			if (!ground(ctx, q[0], q[2], &q[1])) {
				snprintf(err, errlen, "%s: no ground under world (x, z) = (%g, %g) to put the 2D curve on",
					 p->label, q[0], q[2]);
				return -1;
			}
		}
		if (p->kind == CURVE_BRIDGE || p->kind == CURVE_TUNNEL)
			straight_between_ends(p);
	}
	return 0;
}

/* Length of segment a-b (XZ) inside the box, by clipping its parameter
 * range against the four sides (Liang-Barsky). */
static double clipped_length(const float *a, const float *b, const float box[4])
{
	double t0 = 0.0, t1 = 1.0, d[2] = { b[0] - a[0], b[2] - a[2] }, o[2] = { a[0], a[2] };
	for (int k = 0; k < 2; k++) {
		double lo = box[k], hi = box[k + 2];
		if (d[k] == 0.0) {
			if (o[k] < lo || o[k] > hi)
				return 0.0;
			continue;
		}
		double ta = (lo - o[k]) / d[k], tb = (hi - o[k]) / d[k];
		t0 = fmax(t0, fmin(ta, tb));
		t1 = fmin(t1, fmax(ta, tb));
	}
	return t1 > t0 ? (t1 - t0) * hypot(d[0], d[1]) : 0.0;
}

double curves_inside_fraction(const struct curve_set *s, const float box[4], float ext[4])
{
	double len = 0.0, in = 0.0;
	ext[0] = ext[1] = INFINITY;
	ext[2] = ext[3] = -INFINITY;
	for (int i = 0; i < s->npaths; i++) {
		const struct curve_path *p = &s->paths[i];
		for (int k = 0; k < p->npts; k++) {
			const float *q = p->pts + 3 * k;
			ext[0] = fminf(ext[0], q[0]);
			ext[1] = fminf(ext[1], q[2]);
			ext[2] = fmaxf(ext[2], q[0]);
			ext[3] = fmaxf(ext[3], q[2]);
			if (k > 0) {
				len += hypot(q[0] - q[-3], q[2] - q[-1]);
				in += clipped_length(q - 3, q, box);
			}
		}
	}
	return len > 0.0 ? in / len : 1.0;
}
