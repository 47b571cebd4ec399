/* isoterra — the curve pipeline (CPU): polyline -> cubic Béziers ->
 * quadratic Béziers -> inclination (the spatial hash: curve_hash.c).  See
 * curves.h. */
#include "curves.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const curve_kind_names[CURVE_KIND_COUNT] = { "road", "river", "railway", "tunnel", "bridge" };
const char *const curve_surface_names[SURFACE_COUNT] = { "none", "asphalt", "gravel", "dirt", "ballast" };

#define MAX_INCLINATION 2.0f /* |tan α| cap (the thesis's MAX_INCLINATION) */

void curve_path_defaults(struct curve_path *p, int kind)
{
	/* w, λ, inclination gain, Ω per kind */
	static const float d[CURVE_KIND_COUNT][4] = {
		{ 8.0f, 8.0f, 0.0f, 0.5f },  /* road */
		{ 10.0f, 12.0f, 0.0f, 0.5f }, /* river */
		{ 5.0f, 6.0f, 0.0f, 0.5f },  /* railway */
		{ 6.0f, 4.0f, 0.0f, 0.5f },  /* tunnel: w = the tube's diameter */
		{ 8.0f, 2.0f, 0.0f, 0.5f },  /* bridge: w = the deck's width, λ its thickness */
	};
	static const int surf[CURVE_KIND_COUNT] = { SURFACE_ASPHALT, SURFACE_NONE, SURFACE_BALLAST, SURFACE_ASPHALT,
						    SURFACE_ASPHALT };
	if (kind < 0 || kind >= CURVE_KIND_COUNT)
		kind = CURVE_ROAD;
	p->kind = kind;
	p->surface = surf[kind];
	p->width = d[kind][0];
	p->falloff = d[kind][1];
	p->inclination = d[kind][2];
	p->smoothing = d[kind][3];
	p->width_set = p->falloff_set = false; /* defaults, not the file's */
	p->width_rel = 0.0f;
}

void curve_set_free(struct curve_set *s)
{
	for (int i = 0; i < s->npaths; i++)
		free(s->paths[i].pts);
	free(s->paths);
	s->paths = NULL;
	s->npaths = 0;
	free(s->notes);
	s->notes = NULL;
	s->nnotes = 0;
}

int curve_set_note(struct curve_set *s, const char *fmt, ...)
{
	if (s->nnotes >= CURVE_NOTES_MAX)
		return 0;
	if (!s->notes) {
		s->notes = malloc(sizeof(*s->notes) * CURVE_NOTES_MAX);
		if (!s->notes)
			return -1;
	}
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(s->notes[s->nnotes], CURVE_NOTE_MAX, fmt, ap);
	va_end(ap);
	s->nnotes++;
	return 0;
}

int curve_set_add(struct curve_set *s, const struct curve_path *p)
{
	/* room for 16 paths, then doubled whenever the count reaches a power
	 * of two: linear in the number of paths */
	int n = s->npaths;
	if (n == 0 || (n >= 16 && (n & (n - 1)) == 0)) {
		struct curve_path *np = realloc(s->paths, sizeof(*np) * (size_t)(n < 16 ? 16 : 2 * n));
		if (!np)
			return -1;
		s->paths = np;
	}
	struct curve_path *d = &s->paths[s->npaths];
	*d = *p;
	d->pts = malloc(sizeof(float) * 3 * (size_t)(p->npts > 0 ? p->npts : 1));
	if (!d->pts)
		return -1;
	if (p->npts > 0)
		memcpy(d->pts, p->pts, sizeof(float) * 3 * (size_t)p->npts);
	s->npaths++;
	return 0;
}

int curve_set_copy(struct curve_set *dst, const struct curve_set *src)
{
	memset(dst, 0, sizeof(*dst));
	for (int i = 0; i < src->npaths; i++)
		if (curve_set_add(dst, &src->paths[i]) < 0) {
			curve_set_free(dst);
			return -1;
		}
	return 0;
}

float curve_path_reach(const struct curve_path *p)
{
	return 0.5f * p->width + p->falloff;
}

bool curve_path_equal(const struct curve_path *a, const struct curve_path *b)
{
	return a->kind == b->kind && a->width == b->width && a->falloff == b->falloff &&
	       a->follow_ground == b->follow_ground &&
	       a->inclination == b->inclination && a->smoothing == b->smoothing && a->npts == b->npts &&
	       (a->npts == 0 || memcmp(a->pts, b->pts, sizeof(float) * 3 * (size_t)a->npts) == 0);
}

/* ---- small vector helpers ------------------------------------------------ */

static float dist3(const float *a, const float *b)
{
	float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
	return sqrtf(dx * dx + dy * dy + dz * dz);
}

static float cross2(float ax, float az, float bx, float bz)
{
	return ax * bz - az * bx;
}

int curve_path_dedup(struct curve_path *p)
{
	if (p->npts <= 0)
		return 0;
	float ext = 0.0f;
	for (int i = 1; i < p->npts; i++)
		ext = fmaxf(ext, dist3(p->pts, p->pts + 3 * i));
	float eps = 1e-6f * fmaxf(ext, 1e-3f);
	int n = 1;
	for (int i = 1; i < p->npts; i++)
		if (dist3(p->pts + 3 * (n - 1), p->pts + 3 * i) > eps) {
			memmove(p->pts + 3 * n, p->pts + 3 * i, sizeof(float) * 3);
			n++;
		}
	p->npts = n;
	return n;
}

/* ---- polyline -> cubic chain (§5.1) --------------------------------------- */

void curve_path_cubics(const struct curve_path *p, struct cubic3 *out)
{
	int n = p->npts;
	float om = fminf(fmaxf(p->smoothing, 0.0f), 1.0f);
	/* handle length and tangent at every anchor (inner ones) */
	for (int s = 0; s < n - 1; s++) {
		const float *a = p->pts + 3 * s, *b = p->pts + 3 * (s + 1);
		memcpy(out[s].p[0], a, sizeof(float) * 3);
		memcpy(out[s].p[3], b, sizeof(float) * 3);
	}
	for (int i = 1; i < n - 1; i++) {
		const float *pa = p->pts + 3 * (i - 1), *pb = p->pts + 3 * i, *pc = p->pts + 3 * (i + 1);
		float l1 = dist3(pa, pb), l2 = dist3(pb, pc);
		float dir[3];
		for (int c = 0; c < 3; c++)
			dir[c] = (pb[c] - pa[c]) / l1 + (pc[c] - pb[c]) / l2;
		float dl = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
		if (dl < 1e-6f) { /* the path turns back on itself: tangent across */
			for (int c = 0; c < 3; c++)
				dir[c] = (pc[c] - pb[c]) / l2;
		} else {
			for (int c = 0; c < 3; c++)
				dir[c] /= dl;
		}
		float hd = 0.5f * fminf(l1, l2) * om;
		for (int c = 0; c < 3; c++) {
			out[i - 1].p[2][c] = pb[c] - dir[c] * hd; /* incoming handle */
			out[i].p[1][c] = pb[c] + dir[c] * hd;     /* outgoing handle */
		}
	}
	/* end handles: the neighbouring handle projected onto the end segment
	 * (a single segment: handles at 1/3 and 2/3 of it when Ω = 1) */
	for (int end = 0; end < 2; end++) {
		int s = end == 0 ? 0 : n - 2;
		struct cubic3 *cb = &out[s];
		const float *a = cb->p[0], *b = cb->p[3];
		float seg[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
		float ll = seg[0] * seg[0] + seg[1] * seg[1] + seg[2] * seg[2];
		float t;
		if (n == 2) {
			t = end == 0 ? om / 3.0f : 1.0f - om / 3.0f;
		} else {
			const float *other = end == 0 ? cb->p[2] : cb->p[1];
			t = ((other[0] - a[0]) * seg[0] + (other[1] - a[1]) * seg[1] + (other[2] - a[2]) * seg[2]) / ll;
			t = fminf(fmaxf(t, 0.0f), 1.0f);
		}
		float *h = end == 0 ? cb->p[1] : cb->p[2];
		for (int c = 0; c < 3; c++)
			h[c] = a[c] + seg[c] * t;
	}
}

/* ---- cubic -> quadratics (§5.2) ------------------------------------------- */

float cubic_xz_inflection(const struct cubic3 *cb)
{
	/* power form on XZ: a t^3 + b t^2 + c t + d */
	float a[2], b[2], c[2];
	for (int k = 0; k < 2; k++) {
		int ax = k == 0 ? 0 : 2;
		float p0 = cb->p[0][ax], p1 = cb->p[1][ax], p2 = cb->p[2][ax], p3 = cb->p[3][ax];
		a[k] = -p0 + 3.0f * p1 - 3.0f * p2 + p3;
		b[k] = 3.0f * p0 - 6.0f * p1 + 3.0f * p2;
		c[k] = -3.0f * p0 + 3.0f * p1;
	}
	/* Eq. 5.11: 3(b×a) t² + 3(c×a) t + (c×b) = 0 */
	double qa = 3.0 * cross2(b[0], b[1], a[0], a[1]);
	double qb = 3.0 * cross2(c[0], c[1], a[0], a[1]);
	double qc = cross2(c[0], c[1], b[0], b[1]);
	double scale = fabs(qa) + fabs(qb) + fabs(qc);
	if (scale < 1e-30)
		return -1.0f; /* straight */
	double roots[2];
	int nr = 0;
	if (fabs(qa) < 1e-9 * scale) {
		if (fabs(qb) > 1e-12 * scale)
			roots[nr++] = -qc / qb;
	} else {
		double disc = qb * qb - 4.0 * qa * qc;
		if (disc >= 0.0) {
			double sq = sqrt(disc);
			double q = -0.5 * (qb + (qb >= 0 ? sq : -sq)); /* stable form */
			roots[nr++] = q / qa;
			if (q != 0.0)
				roots[nr++] = qc / q;
		}
	}
	float best = -1.0f;
	for (int i = 0; i < nr; i++) {
		double t = roots[i];
		if (t > 1e-3 && t < 1.0 - 1e-3 && (best < 0.0f || fabs(t - 0.5) < fabs(best - 0.5)))
			best = (float)t;
	}
	return best;
}

void cubic_split(const struct cubic3 *c, float t, struct cubic3 *l, struct cubic3 *r)
{
	for (int k = 0; k < 3; k++) {
		float p0 = c->p[0][k], p1 = c->p[1][k], p2 = c->p[2][k], p3 = c->p[3][k];
		float p01 = p0 + (p1 - p0) * t, p12 = p1 + (p2 - p1) * t, p23 = p2 + (p3 - p2) * t;
		float p012 = p01 + (p12 - p01) * t, p123 = p12 + (p23 - p12) * t;
		float m = p012 + (p123 - p012) * t;
		l->p[0][k] = p0;
		l->p[1][k] = p01;
		l->p[2][k] = p012;
		l->p[3][k] = m;
		r->p[0][k] = m;
		r->p[1][k] = p123;
		r->p[2][k] = p23;
		r->p[3][k] = p3;
	}
}

int cubic_to_quad(const struct cubic3 *c, struct quad3 *q)
{
	const float *A = c->p[0], *B = c->p[1], *C = c->p[2], *D = c->p[3];
	memcpy(q->p[0], A, sizeof(float) * 3);
	memcpy(q->p[2], D, sizeof(float) * 3);
	q->p[1][1] = 0.5f * (B[1] + C[1]);
	/* straight in XZ?  distances of B, C to the chord A-D */
	float cx = D[0] - A[0], cz = D[2] - A[2];
	float chord = sqrtf(cx * cx + cz * cz);
	float hb = fabsf(cross2(cx, cz, B[0] - A[0], B[2] - A[2]));
	float hc = fabsf(cross2(cx, cz, C[0] - A[0], C[2] - A[2]));
	float ext = fmaxf(chord, fmaxf(hypotf(B[0] - A[0], B[2] - A[2]), hypotf(C[0] - D[0], C[2] - D[2])));
	if (chord > 0.0f && fmaxf(hb, hc) <= 1e-5f * chord * ext) {
		/* on the chord: the midpoint keeps the parametrisation uniform */
		q->p[1][0] = 0.5f * (A[0] + D[0]);
		q->p[1][2] = 0.5f * (A[2] + D[2]);
		return 1;
	}
	/* tangent directions at both ends (zero handles: next control point) */
	float u[2] = { B[0] - A[0], B[2] - A[2] }, v[2] = { C[0] - D[0], C[2] - D[2] };
	float tiny = 1e-6f * fmaxf(ext, 1e-6f);
	if (hypotf(u[0], u[1]) < tiny) {
		u[0] = C[0] - A[0];
		u[1] = C[2] - A[2];
	}
	if (hypotf(v[0], v[1]) < tiny) {
		v[0] = B[0] - D[0];
		v[1] = B[2] - D[2];
	}
	/* A + s u = D + r v */
	float den = cross2(u[0], u[1], v[0], v[1]);
	float lu = hypotf(u[0], u[1]), lv = hypotf(v[0], v[1]);
	if (fabsf(den) > 1e-6f * lu * lv) {
		float wx = D[0] - A[0], wz = D[2] - A[2];
		float s = cross2(wx, wz, v[0], v[1]) / den;
		float r = cross2(wx, wz, u[0], u[1]) / den;
		float ex = A[0] + s * u[0], ez = A[2] + s * u[1];
		float far = 4.0f * fmaxf(chord, 1e-6f);
		if (s > 0.0f && r > 0.0f && hypotf(ex - A[0], ez - A[2]) < far && hypotf(ex - D[0], ez - D[2]) < far) {
			q->p[1][0] = ex;
			q->p[1][2] = ez;
			return 0;
		}
	}
	/* fallback: least-squares degree reduction */
	q->p[1][0] = (3.0f * (B[0] + C[0]) - (A[0] + D[0])) * 0.25f;
	q->p[1][2] = (3.0f * (B[2] + C[2]) - (A[2] + D[2])) * 0.25f;
	return 2;
}

float quad_xz_curvature(const float p0[3], const float p1[3], const float p2[3], float t)
{
	float ax = p1[0] - p0[0], az = p1[2] - p0[2];
	float bx = p0[0] - 2.0f * p1[0] + p2[0], bz = p0[2] - 2.0f * p1[2] + p2[2];
	float dx = 2.0f * (ax + bx * t), dz = 2.0f * (az + bz * t); /* C'  */
	float ddx = 2.0f * bx, ddz = 2.0f * bz;                       /* C'' */
	float sp = sqrtf(dx * dx + dz * dz);
	if (sp < 1e-12f)
		return 0.0f;
	return cross2(dx, dz, ddx, ddz) / (sp * sp * sp);
}

static float clamp_incl(float v)
{
	return fminf(fmaxf(v, -MAX_INCLINATION), MAX_INCLINATION);
}

void curve_quads_free(struct curve_quads *q)
{
	free(q->ctrl);
	free(q->prm);
	free(q->first);
	free(q->path);
	free(q->box);
	memset(q, 0, sizeof(*q));
}

void curve_quads_get(const struct curve_quads *q, int k, float out[3][4])
{
	for (int i = 0; i < 3; i++)
		memcpy(out[i], q->ctrl[q->first[k] + i], sizeof(float) * 4);
}

static void quad_box(const float p0[3], const float p1[3], const float p2[3], float box[4])
{
	for (int k = 0; k < 2; k++) {
		int ax = k == 0 ? 0 : 2;
		float a = p0[ax], b = p1[ax], c = p2[ax];
		float lo = fminf(a, c), hi = fmaxf(a, c);
		float den = a - 2.0f * b + c;
		if (den != 0.0f) {
			float t = (a - b) / den;
			if (t > 0.0f && t < 1.0f) {
				float u = 1.0f - t;
				float v = u * u * a + 2.0f * u * t * b + t * t * c;
				lo = fminf(lo, v);
				hi = fmaxf(hi, v);
			}
		}
		box[k] = lo;
		box[k + 2] = hi;
	}
}

/* (w/2, λ, kind, surface) of a path's control points. */
static void set_prm(float prm[4], const struct curve_path *p)
{
	prm[0] = 0.5f * p->width;
	prm[1] = p->falloff;
	prm[2] = (float)p->kind;
	prm[3] = (float)p->surface;
}

/* Appends path pi's quadratics (two per cubic, split at its XZ inflection or
 * at t = 0.5) from control point q->nctrl on; returns its last anchor. */
static int add_path_quads(struct curve_quads *q, const struct curve_path *p, int pi, const struct cubic3 *cubics)
{
	int c = q->nctrl;
	memcpy(q->ctrl[c], p->pts, sizeof(float) * 3);
	for (int k = 0; k < p->npts - 1; k++) {
		struct cubic3 l, r;
		float t = cubic_xz_inflection(&cubics[k]);
		cubic_split(&cubics[k], t > 0.0f ? t : 0.5f, &l, &r);
		struct quad3 ql, qr;
		cubic_to_quad(&l, &ql);
		cubic_to_quad(&r, &qr);
		const struct quad3 *qq[2] = { &ql, &qr };
		for (int h = 0; h < 2; h++) {
			int qi = q->nquads++;
			q->first[qi] = c;
			q->path[qi] = pi;
			memcpy(q->ctrl[c + 1], qq[h]->p[1], sizeof(float) * 3);
			memcpy(q->ctrl[c + 2], qq[h]->p[2], sizeof(float) * 3);
			set_prm(q->prm[c], p);
			c += 2;
		}
	}
	return c;
}

/* Lateral inclination (§7.2) of the nqp quadratics from control point base
 * on: gain · curvature at t = 0, 0.5, 1; shared anchors average their two
 * curves; the middle control value is chosen so the quadratic
 * interpolation hits I(0.5). */
static void path_inclination(struct curve_quads *q, const struct curve_path *p, int base, int nqp)
{
	for (int k = 0; k < nqp; k++) {
		int f = base + 2 * k;
		const float *p0 = q->ctrl[f], *p1 = q->ctrl[f + 1], *p2 = q->ctrl[f + 2];
		float i0 = clamp_incl(p->inclination * quad_xz_curvature(p0, p1, p2, 0.0f));
		float i2 = clamp_incl(p->inclination * quad_xz_curvature(p0, p1, p2, 1.0f));
		q->ctrl[f][3] = k == 0 ? i0 : 0.5f * (q->ctrl[f][3] + i0);
		q->ctrl[f + 2][3] = i2;
	}
	for (int k = 0; k < nqp; k++) {
		int f = base + 2 * k;
		const float *p0 = q->ctrl[f], *p1 = q->ctrl[f + 1], *p2 = q->ctrl[f + 2];
		float im = clamp_incl(p->inclination * quad_xz_curvature(p0, p1, p2, 0.5f));
		q->ctrl[f + 1][3] = clamp_incl(2.0f * im - 0.5f * (q->ctrl[f][3] + q->ctrl[f + 2][3]));
	}
}

/* Cubics of the whole set (one per segment), or -1 with err. */
static int count_cubics(const struct curve_set *s, char *err, size_t errlen)
{
	long total_cubics = 0;
	for (int i = 0; i < s->npaths; i++) {
		if (s->paths[i].npts < 2) {
			snprintf(err, errlen, "%s: a path needs at least two distinct points", s->paths[i].label);
			return -1;
		}
		total_cubics += s->paths[i].npts - 1;
	}
	/* the control point table: 4 per segment + 1 per path, 16 bytes each */
	long max_cubics = (CURVE_TABLE_MAX_BYTES / 16 - s->npaths - 1) / 4;
	if (total_cubics > max_cubics) {
		snprintf(err, errlen, "too many curve segments (%ld in %d paths, at most %ld: the curve tables are limited "
			 "to %ld MB)", total_cubics, s->npaths, max_cubics > 0 ? max_cubics : 0, CURVE_TABLE_MAX_BYTES >> 20);
		return -1;
	}
	return (int)total_cubics;
}

int curves_build(const struct curve_set *s, struct curve_quads *q, char *err, size_t errlen)
{
	memset(q, 0, sizeof(*q));
	int total_cubics = count_cubics(s, err, errlen);
	if (total_cubics < 0)
		return -1;
	size_t nq = 2 * (size_t)total_cubics + 1, nc = 4 * (size_t)total_cubics + (size_t)s->npaths + 1;
	q->ctrl = calloc(nc, sizeof(*q->ctrl));
	q->prm = calloc(nc, sizeof(*q->prm));
	q->first = calloc(nq, sizeof(int));
	q->path = calloc(nq, sizeof(int));
	q->box = calloc(nq, sizeof(*q->box));
	struct cubic3 *cubics = NULL;
	if (!q->ctrl || !q->prm || !q->first || !q->path || !q->box)
		goto oom;
	for (int pi = 0; pi < s->npaths; pi++) {
		const struct curve_path *p = &s->paths[pi];
		if (p->area) /* a polygon's ring: the edit state's areas (areas.c), no curve */
			continue;
		int ncub = p->npts - 1;
		struct cubic3 *nb = realloc(cubics, sizeof(*cubics) * (size_t)(ncub > 0 ? ncub : 1));
		if (!nb)
			goto oom;
		cubics = nb;
		curve_path_cubics(p, cubics);
		int base = q->nctrl;
		int c = add_path_quads(q, p, pi, cubics);
		path_inclination(q, p, base, 2 * ncub);
		set_prm(q->prm[c], p); /* last anchor: same parameters */
		q->nctrl = c + 1;
	}
	for (int k = 0; k < q->nquads; k++) {
		int f = q->first[k];
		quad_box(q->ctrl[f], q->ctrl[f + 1], q->ctrl[f + 2], q->box[k]);
	}
	free(cubics);
	return 0;
oom:
	free(cubics);
	curve_quads_free(q);
	snprintf(err, errlen, "out of memory building the curves");
	return -1;
}

/* ---- edits ----------------------------------------------------------------- */

void curve_path_padded_box(const struct curve_path *p, float box[4])
{
	/* the padded boxes of the path's quadratics, exactly as the hash pads
	 * them; the points themselves too (also when out of memory) */
	box[0] = box[1] = FLT_MAX;
	box[2] = box[3] = -FLT_MAX;
	if (p->npts <= 0) {
		box[0] = box[1] = box[2] = box[3] = 0.0f;
		return;
	}
	float pad = curve_path_reach(p);
	for (int i = 0; i < p->npts; i++) {
		box[0] = fminf(box[0], p->pts[3 * i] - pad);
		box[2] = fmaxf(box[2], p->pts[3 * i] + pad);
		box[1] = fminf(box[1], p->pts[3 * i + 2] - pad);
		box[3] = fmaxf(box[3], p->pts[3 * i + 2] + pad);
	}
	struct curve_set one = { .paths = (struct curve_path *)p, .npaths = 1 };
	struct curve_quads q;
	char err[16];
	if (p->npts < 2 || curves_build(&one, &q, err, sizeof(err)) < 0)
		return;
	for (int k = 0; k < q.nquads; k++) {
		float b[4];
		curve_hash_padded_box(&q, k, b);
		box[0] = fminf(box[0], b[0]);
		box[1] = fminf(box[1], b[1]);
		box[2] = fmaxf(box[2], b[2]);
		box[3] = fmaxf(box[3], b[3]);
	}
	curve_quads_free(&q);
}

static void box_union(float acc[4], const float b[4], bool *any)
{
	if (!*any) {
		memcpy(acc, b, sizeof(float) * 4);
		*any = true;
		return;
	}
	acc[0] = fminf(acc[0], b[0]);
	acc[1] = fminf(acc[1], b[1]);
	acc[2] = fmaxf(acc[2], b[2]);
	acc[3] = fmaxf(acc[3], b[3]);
}

bool curves_affected_bounds(const struct curve_set *o, const struct curve_set *n, float out[4])
{
	bool any = false;
	out[0] = out[1] = out[2] = out[3] = 0.0f;
	int no = o ? o->npaths : 0, nn = n ? n->npaths : 0;
	int m = no > nn ? no : nn;
	for (int i = 0; i < m; i++) {
		const struct curve_path *a = i < no ? &o->paths[i] : NULL, *b = i < nn ? &n->paths[i] : NULL;
		if (a && b && curve_path_equal(a, b))
			continue;
		float box[4];
		if (a) {
			curve_path_padded_box(a, box);
			box_union(out, box, &any);
		}
		if (b) {
			curve_path_padded_box(b, box);
			box_union(out, box, &any);
		}
	}
	return any;
}
