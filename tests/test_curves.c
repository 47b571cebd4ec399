/* isoterra — curves (roads, rivers, railways) and heightmaps.
 *
 * CPU: the curve pipeline (cubic handles and C1 continuity, inflection
 * split, degree reduction with its degenerate cases, quadratics close to
 * their cubics, inclination from curvature), the closed-form closest point
 * against a brute-force distance (dense sampling + golden-section
 * refinement in double) on random and near-degenerate curves, the spatial
 * hash against a brute-force box test and against the influence of every
 * curve, carving with the hash == carving without it, the affected-region
 * API (every density change lies inside the reported box), GeoJSON / CSV
 * parsing (good files and malformed ones: message with file:line), the
 * heightmap (16-bit PNG round trip, fractal interpolation exact at the
 * samples, detail between them).
 *
 * GPU (llvmpipe): closest point vs brute force, curve evaluation through
 * the GPU hash vs the CPU mirror, heightmap heights vs the mirror, the
 * density pass with curves / heightmap vs density_ref_volume, the 2D
 * displacement bake vs the CPU bake (and the iterative baseline close to
 * the analytic one), and the real pipeline: a road's centre line after
 * carving lies at the curve height +- one voxel in the extracted mesh, where
 * the uncarved terrain was both above (cut) and below (fill) the road.
 * The streaming world: a road added, raised and removed re-generates
 * exactly the known blocks whose samples the CPU carve reaches (none
 * missed, none outside the path's padded box, under half the view).
 * GeoTIFF through GDAL when the build has it. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "world.h"
#include "terrain.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

static uint32_t rng = 12345u;
static float frand(void) /* [0,1) */
{
	rng = rng * 1664525u + 1013904223u;
	return (float)(rng >> 8) / 16777216.0f;
}
static float frange(float a, float b)
{
	return a + (b - a) * frand();
}

static void set(struct params *p, const char *kv)
{
	char buf[1024], err[256];
	snprintf(buf, sizeof(buf), "%s", kv);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
		char *eq = strchr(tok, '=');
		if (!eq)
			continue;
		*eq = 0;
		int rc = params_set(p, tok, eq + 1, err, sizeof(err));
		CHECK(rc == 0, "params_set %s: %s", tok, err);
	}
}

static struct curve_path make_path(int n, const float *pts, float w, float lam, float incl, float om)
{
	struct curve_path p;
	memset(&p, 0, sizeof(p));
	curve_path_defaults(&p, CURVE_ROAD);
	p.width = w;
	p.falloff = lam;
	p.inclination = incl;
	p.smoothing = om;
	p.npts = n;
	p.pts = (float *)pts;
	snprintf(p.label, sizeof(p.label), "test path");
	return p;
}

/* ---- brute-force distance (double) ------------------------------------------ */

static void qeval(const float c[3][4], double t, double *x, double *z)
{
	double u = 1.0 - t;
	*x = u * u * c[0][0] + 2 * u * t * c[1][0] + t * t * c[2][0];
	*z = u * u * c[0][2] + 2 * u * t * c[1][2] + t * t * c[2][2];
}

static double qdist2(const float c[3][4], double t, double px, double pz)
{
	double x, z;
	qeval(c, t, &x, &z);
	return (x - px) * (x - px) + (z - pz) * (z - pz);
}

static double brute_dist(const float c[3][4], double px, double pz)
{
	const int N = 4000;
	int bi = 0;
	double bd = DBL_MAX;
	for (int i = 0; i <= N; i++) {
		double d = qdist2(c, (double)i / N, px, pz);
		if (d < bd) {
			bd = d;
			bi = i;
		}
	}
	double a = fmax(0.0, (bi - 1.0) / N), b = fmin(1.0, (bi + 1.0) / N);
	for (int it = 0; it < 80; it++) { /* golden section */
		double m1 = a + (b - a) * 0.381966, m2 = a + (b - a) * 0.618034;
		if (qdist2(c, m1, px, pz) < qdist2(c, m2, px, pz))
			b = m2;
		else
			a = m1;
	}
	bd = fmin(bd, qdist2(c, 0.5 * (a + b), px, pz));
	return sqrt(bd);
}

/* Random and near-degenerate quadratics + query points.  item: 16 floats
 * (p0, p1, p2 as x y z I; pos x z). */
static int make_closest_cases(float *items, int max)
{
	int n = 0;
	for (int k = 0; n < max; k++) {
		float c[3][4];
		for (int i = 0; i < 3; i++) {
			c[i][0] = frange(-100, 100);
			c[i][1] = frange(-10, 10);
			c[i][2] = frange(-100, 100);
			c[i][3] = frange(-1, 1);
		}
		int kind = k % 10;
		float mx = 0.5f * (c[0][0] + c[2][0]), mz = 0.5f * (c[0][2] + c[2][2]);
		float dx = c[2][0] - c[0][0], dz = c[2][2] - c[0][2];
		float eps[] = { 0.0f, 1e-4f, 1e-2f, 0.3f };
		switch (kind) {
		case 1: /* straight (midpoint handle) and nearly straight */
		case 2: {
			float e = eps[(k / 10) % 4];
			c[1][0] = mx - dz * e;
			c[1][2] = mz + dx * e;
			break;
		}
		case 3: /* handle on the line, off-centre (non-uniform speed) */
			c[1][0] = c[0][0] + 0.9f * dx;
			c[1][2] = c[0][2] + 0.9f * dz;
			break;
		case 4: /* cusp-like: handle far out on the line, the curve turns back */
			c[1][0] = c[0][0] + 3.0f * dx;
			c[1][2] = c[0][2] + 3.0f * dz;
			break;
		case 5: /* zero start tangent */
			c[1][0] = c[0][0];
			c[1][2] = c[0][2];
			break;
		case 6: /* closed needle: p2 == p0 */
			c[2][0] = c[0][0];
			c[2][2] = c[0][2];
			break;
		case 7: /* very sharp: handle far off the chord */
			c[1][0] = mx - dz * 20.0f;
			c[1][2] = mz + dx * 20.0f;
			break;
		case 8: /* tiny curve */
			for (int i = 1; i < 3; i++) {
				c[i][0] = c[0][0] + frange(-1e-2f, 1e-2f);
				c[i][2] = c[0][2] + frange(-1e-2f, 1e-2f);
			}
			break;
		default:
			break;
		}
		for (int j = 0; j < 6 && n < max; j++) {
			float *it = items + 16 * n;
			for (int i = 0; i < 3; i++)
				memcpy(it + 4 * i, c[i], sizeof(float) * 4);
			if (j < 3) { /* anywhere */
				it[12] = frange(-160, 160);
				it[13] = frange(-160, 160);
			} else { /* near the curve */
				double x, z;
				qeval(c, frand(), &x, &z);
				it[12] = (float)x + frange(-3, 3);
				it[13] = (float)z + frange(-3, 3);
			}
			it[14] = it[15] = 0.0f;
			n++;
		}
	}
	return n;
}

static void test_closest_cpu(const float *items, int n, double *worst)
{
	double w = 0;
	int bad = 0;
	for (int i = 0; i < n; i++) {
		const float *it = items + 16 * i;
		float c[3][4], out[4];
		memcpy(c, it, sizeof(c));
		carve_ref_closest(c, it + 12, out);
		double b = brute_dist(c, it[12], it[13]);
		double scale = 1.0 + fabs(it[12]) + fabs(it[13]);
		double e = fabs(fabs((double)out[0]) - b) / scale;
		w = fmax(w, e);
		if (e > 2e-5)
			bad++;
		/* the returned t is the point at that distance */
		double dt = sqrt(qdist2(c, out[1], it[12], it[13]));
		if (fabs(dt - fabs(out[0])) > 1e-4 * scale)
			bad++;
	}
	*worst = w;
	CHECK(bad == 0, "CPU closest point: %d of %d cases off the brute-force distance (worst %.3g relative)", bad, n, w);
}

/* ---- curve pipeline (CPU) ------------------------------------------------------ */

static void test_pipeline_cpu(void)
{
	/* a smooth winding polyline */
	float pts[8 * 3];
	for (int i = 0; i < 8; i++) {
		pts[3 * i] = 30.0f * (float)i;
		pts[3 * i + 1] = 5.0f * sinf((float)i);
		pts[3 * i + 2] = 25.0f * sinf(0.9f * (float)i);
	}
	struct curve_path p = make_path(8, pts, 8, 8, 40.0f, 0.5f);
	struct cubic3 cb[7];
	curve_path_cubics(&p, cb);
	int bad = 0;
	for (int k = 0; k < 7; k++)
		for (int c = 0; c < 3; c++)
			bad += cb[k].p[0][c] != pts[3 * k + c] || cb[k].p[3][c] != pts[3 * k + 3 + c];
	CHECK(bad == 0, "cubic anchors are the polyline's vertices");
	double worst_c1 = 0;
	for (int k = 0; k < 6; k++) { /* C1: incoming and outgoing handle mirror each other */
		const float *a = cb[k].p[3], *hin = cb[k].p[2], *hout = cb[k + 1].p[1];
		for (int c = 0; c < 3; c++)
			worst_c1 = fmax(worst_c1, fabs((double)(a[c] - hin[c]) - (double)(hout[c] - a[c])));
	}
	CHECK(worst_c1 < 1e-4, "C1 at inner anchors: handle mismatch %g", worst_c1);
	/* handle length 0.5 min(l1,l2) Ω */
	{
		float l1 = hypotf(hypotf(pts[3] - pts[0], pts[4] - pts[1]), pts[5] - pts[2]);
		float l2 = hypotf(hypotf(pts[6] - pts[3], pts[7] - pts[4]), pts[8] - pts[5]);
		float hl = hypotf(hypotf(cb[1].p[1][0] - pts[3], cb[1].p[1][1] - pts[4]), cb[1].p[1][2] - pts[5]);
		CHECK_NEAR(hl, 0.5f * fminf(l1, l2) * 0.5f, 1e-3, "handle length 0.5 min(l1,l2) Ω");
	}
	/* end handles lie on the end segments */
	{
		const float *a = cb[0].p[0], *b = cb[0].p[3], *h = cb[0].p[1];
		float cr = (b[0] - a[0]) * (h[2] - a[2]) - (b[2] - a[2]) * (h[0] - a[0]);
		CHECK(fabsf(cr) < 1e-2f, "first handle on the first segment (cross %g)", cr);
	}
	/* quadratics: close to their cubics, anchors shared */
	struct curve_set s = { &p, 1 };
	struct curve_quads q;
	char err[256];
	CHECK(curves_build(&s, &q, err, sizeof(err)) == 0, "curves_build: %s", err);
	CHECK(q.nquads == 14 && q.nctrl == 29, "7 cubics -> 14 quadratics, 29 control points (got %d, %d)", q.nquads,
	      q.nctrl);
	double worst = 0;
	for (int k = 0; k < 7 && q.nquads == 14; k++) {
		float seglen = hypotf(pts[3 * k + 3] - pts[3 * k], pts[3 * k + 5] - pts[3 * k + 2]);
		for (int i = 0; i <= 50; i++) { /* cubic samples vs the two quadratics */
			double t = i / 50.0, u = 1 - t;
			double x = u * u * u * cb[k].p[0][0] + 3 * u * u * t * cb[k].p[1][0] + 3 * u * t * t * cb[k].p[2][0] +
				   t * t * t * cb[k].p[3][0];
			double z = u * u * u * cb[k].p[0][2] + 3 * u * u * t * cb[k].p[1][2] + 3 * u * t * t * cb[k].p[2][2] +
				   t * t * t * cb[k].p[3][2];
			float c0[3][4], c1[3][4];
			curve_quads_get(&q, 2 * k, c0);
			curve_quads_get(&q, 2 * k + 1, c1);
			double d = fmin(brute_dist(c0, x, z), brute_dist(c1, x, z));
			worst = fmax(worst, d / seglen);
		}
	}
	CHECK(worst < 0.02, "quadratics within 2%% of the segment length of their cubic (worst %.4f)", worst);
	printf("  quadratic vs cubic: worst deviation %.4f of the segment length\n", worst);
	/* inclination: gain · curvature, sign follows the turn */
	{
		float circ[13 * 3];
		for (int i = 0; i < 13; i++) { /* counter-clockwise in XZ (x = cos, z = sin) */
			float a = (float)i * 0.25f;
			circ[3 * i] = 50.0f * cosf(a);
			circ[3 * i + 1] = 0.0f;
			circ[3 * i + 2] = 50.0f * sinf(a);
		}
		/* Ω = 0.67 makes the handles those of a circular arc (4/3 tan(θ/4) R) */
		struct curve_path cp = make_path(13, circ, 8, 8, 10.0f, 0.67f);
		struct curve_set cs = { &cp, 1 };
		struct curve_quads cq;
		CHECK(curves_build(&cs, &cq, err, sizeof(err)) == 0, "circle: %s", err);
		/* x = cos, z = sin: cross(C', C'') = +1/R, I = gain / R = 0.2 */
		double mean = 0, worst_def = 0;
		for (int k = 2; k < cq.nquads - 2; k++) {
			float c[3][4];
			curve_quads_get(&cq, k, c);
			float im = 0.25f * c[0][3] + 0.5f * c[1][3] + 0.25f * c[2][3]; /* I(0.5) */
			float want = 10.0f * quad_xz_curvature(c[0], c[1], c[2], 0.5f);
			worst_def = fmax(worst_def, fabs(im - want));
			mean += im;
		}
		mean /= cq.nquads - 4;
		CHECK(worst_def < 1e-4, "I(0.5) = gain * curvature(0.5) (worst %g)", worst_def);
		CHECK(fabs(mean - 0.2) < 0.05, "inclination along a circle of radius 50, gain 10: %g, want ~0.2", mean);
		float mid = cq.ctrl[cq.first[6] + 2][3];
		for (int i = 0; i < 13; i++)
			circ[3 * i + 2] = -circ[3 * i + 2];
		curve_quads_free(&cq);
		CHECK(curves_build(&cs, &cq, err, sizeof(err)) == 0, "mirrored circle: %s", err);
		float mid2 = cq.ctrl[cq.first[6] + 2][3];
		CHECK(mid > 0.0f && fabsf(mid2 + mid) < 1e-3f, "mirrored turn flips the inclination: %g vs %g", mid2, mid);
		curve_quads_free(&cq);
		cp.inclination = 1000.0f;
		CHECK(curves_build(&cs, &cq, err, sizeof(err)) == 0, "steep: %s", err);
		float mx = 0.0f;
		for (int i = 0; i < cq.nctrl; i++)
			mx = fmaxf(mx, fabsf(cq.ctrl[i][3]));
		CHECK(mx <= 2.0f, "inclination capped at 2 (%g)", mx);
		curve_quads_free(&cq);
	}
	curve_quads_free(&q);

	/* inflection: an S-shaped cubic */
	struct cubic3 sc = { { { 0, 0, 0 }, { 10, 0, 10 }, { 20, 0, -10 }, { 30, 0, 0 } } };
	float ti = cubic_xz_inflection(&sc);
	CHECK(fabsf(ti - 0.5f) < 1e-4f, "S-curve inflection at 0.5: %g", ti);
	struct cubic3 sc2 = { { { 0, 0, 0 }, { 5, 0, 10 }, { 20, 0, -10 }, { 30, 0, 0 } } };
	ti = cubic_xz_inflection(&sc2);
	{ /* cross(C', C'') changes sign across it */
		float a[2], b[2], c[2];
		for (int k = 0; k < 2; k++) {
			int ax = k ? 2 : 0;
			float p0 = sc2.p[0][ax], p1 = sc2.p[1][ax], p2 = sc2.p[2][ax], p3 = sc2.p[3][ax];
			a[k] = -p0 + 3 * p1 - 3 * p2 + p3;
			b[k] = 3 * p0 - 6 * p1 + 3 * p2;
			c[k] = -3 * p0 + 3 * p1;
		}
		float cr[2];
		for (int s2 = 0; s2 < 2; s2++) {
			float t = ti + (s2 ? 0.01f : -0.01f);
			float d1x = 3 * a[0] * t * t + 2 * b[0] * t + c[0], d1z = 3 * a[1] * t * t + 2 * b[1] * t + c[1];
			float d2x = 6 * a[0] * t + 2 * b[0], d2z = 6 * a[1] * t + 2 * b[1];
			cr[s2] = d1x * d2z - d1z * d2x;
		}
		CHECK(ti > 0.0f && ti < 1.0f && cr[0] * cr[1] < 0.0f, "inflection %g: curvature sign change (%g, %g)", ti,
		      cr[0], cr[1]);
	}
	struct cubic3 arc = { { { 0, 0, 0 }, { 10, 0, 5 }, { 20, 0, 5 }, { 30, 0, 0 } } };
	CHECK(cubic_xz_inflection(&arc) < 0.0f, "a plain arc has no inflection");

	/* degenerate sub-curves */
	struct quad3 qq;
	struct cubic3 straight = { { { 0, 1, 0 }, { 1, 2, 1 }, { 7, 3, 7 }, { 9, 4, 9 } } };
	CHECK(cubic_to_quad(&straight, &qq) == 1 && qq.p[1][0] == 4.5f && qq.p[1][2] == 4.5f && qq.p[1][1] == 2.5f,
	      "straight sub-curve: chord midpoint, Y averaged (%g %g %g)", qq.p[1][0], qq.p[1][1], qq.p[1][2]);
	struct cubic3 zero = { { { 0, 0, 0 }, { 0, 0, 0 }, { 10, 0, 5 }, { 10, 0, 0 } } };
	int r = cubic_to_quad(&zero, &qq);
	CHECK(r == 0 && isfinite(qq.p[1][0]) && isfinite(qq.p[1][2]), "zero start handle: rc %d (%g, %g)", r, qq.p[1][0],
	      qq.p[1][2]);
	struct cubic3 par = { { { 0, 0, 0 }, { 0, 0, 5 }, { 10, 0, 5 }, { 10, 0, 0 } } }; /* handles parallel */
	r = cubic_to_quad(&par, &qq);
	CHECK(r == 2 && fabsf(qq.p[1][0] - 5.0f) < 1e-5f && fabsf(qq.p[1][2] - 7.5f) < 1e-5f,
	      "parallel handles: least-squares fallback (rc %d: %g, %g)", r, qq.p[1][0], qq.p[1][2]);
	struct cubic3 simple = { { { 0, 0, 0 }, { 5, 2, 5 }, { 10, 4, 5 }, { 15, 0, 0 } } };
	r = cubic_to_quad(&simple, &qq);
	CHECK(r == 0 && fabsf(qq.p[1][0] - 7.5f) < 1e-4f && fabsf(qq.p[1][2] - 7.5f) < 1e-4f && qq.p[1][1] == 3.0f,
	      "handle intersection: (%g, %g, %g)", qq.p[1][0], qq.p[1][1], qq.p[1][2]);

	/* a collinear polyline (with a repeated point) gives a straight road */
	float line[5 * 3] = { 0, 0, 0, 10, 1, 0, 10, 1, 0, 25, 2, 0, 40, 0, 0 };
	struct curve_path lp = make_path(5, line, 4, 4, 10.0f, 0.5f);
	float lcopy[15];
	memcpy(lcopy, line, sizeof(lcopy));
	lp.pts = lcopy;
	CHECK(curve_path_dedup(&lp) == 4, "repeated point dropped");
	struct curve_set ls = { &lp, 1 };
	CHECK(curves_build(&ls, &q, err, sizeof(err)) == 0, "straight: %s", err);
	bad = 0;
	for (int i = 0; i < q.nctrl; i++)
		bad += q.ctrl[i][2] != 0.0f || q.ctrl[i][3] != 0.0f || !isfinite(q.ctrl[i][0]);
	CHECK(bad == 0, "straight road: every control point on the line, no inclination");
	curve_quads_free(&q);
	/* a path that turns back on itself */
	float back[3 * 3] = { 0, 0, 0, 10, 0, 0, 0, 0, 0.0f };
	struct curve_path bp = make_path(3, back, 4, 4, 1.0f, 0.5f);
	struct curve_set bs = { &bp, 1 };
	CHECK(curves_build(&bs, &q, err, sizeof(err)) == 0, "U-turn: %s", err);
	bad = 0;
	for (int i = 0; i < q.nctrl; i++)
		for (int c = 0; c < 4; c++)
			bad += !isfinite(q.ctrl[i][c]);
	CHECK(bad == 0, "U-turn: finite control points");
	curve_quads_free(&q);
	/* fewer than two distinct points */
	float one[3] = { 1, 2, 3 };
	struct curve_path op = make_path(1, one, 4, 4, 0, 0.5f);
	struct curve_set os = { &op, 1 };
	CHECK(curves_build(&os, &q, err, sizeof(err)) < 0 && strstr(err, "two distinct"), "one point rejected: %s", err);
}

/* ---- random curve sets ----------------------------------------------------------- */

static void random_set(struct curve_set *s, int npaths, float extent)
{
	memset(s, 0, sizeof(*s));
	for (int i = 0; i < npaths; i++) {
		int n = 2 + (int)(frand() * 8);
		float pts[10 * 3];
		float x = frange(-extent, extent), z = frange(-extent, extent), a = frange(0, 6.28f);
		for (int k = 0; k < n; k++) {
			pts[3 * k] = x;
			pts[3 * k + 1] = frange(-5, 5);
			pts[3 * k + 2] = z;
			a += frange(-1.2f, 1.2f);
			float l = frange(5, extent * 0.3f);
			x += l * cosf(a);
			z += l * sinf(a);
		}
		struct curve_path p = make_path(n, pts, frange(2, 12), frange(0, 10), frange(-20, 20), frand());
		p.kind = i % CURVE_KIND_COUNT;
		CHECK(curve_set_add(s, &p) == 0, "curve_set_add");
	}
}

static void test_hash_cpu(void)
{
	char err[256];
	int bad_missing = 0, bad_extra = 0, bad_infl = 0, checked = 0;
	for (int trial = 0; trial < 6; trial++) {
		struct curve_set s;
		random_set(&s, 3 + trial, 200.0f);
		struct curve_quads q;
		CHECK(curves_build(&s, &q, err, sizeof(err)) == 0, "build: %s", err);
		int dims[3] = { 1, 7, 16 + trial * 5 };
		for (int di = 0; di < 3; di++) {
			struct curve_hash h;
			CHECK(curve_hash_build(&q, dims[di], &h, err, sizeof(err)) == 0, "hash: %s", err);
			/* every cell: the curves whose padded box covers it (brute force) */
			for (int cz = 0; cz < h.dim; cz++)
				for (int cx = 0; cx < h.dim; cx++) {
					int c = cx + cz * h.dim;
					float x0 = h.origin[0] + (float)cx * h.cell[0], x1 = x0 + h.cell[0];
					float z0 = h.origin[1] + (float)cz * h.cell[1], z1 = z0 + h.cell[1];
					float tol = 1e-4f * fmaxf(h.cell[0], h.cell[1]);
					for (int k = 0; k < q.nquads; k++) {
						float b[4];
						curve_hash_padded_box(&q, k, b);
						bool strictly = b[0] < x1 - tol && b[2] > x0 + tol && b[1] < z1 - tol &&
								b[3] > z0 + tol;
						bool loosely = b[0] <= x1 + tol && b[2] >= x0 - tol && b[1] <= z1 + tol &&
							       b[3] >= z0 - tol;
						bool listed = false;
						for (int i = 0; i < h.pivot[2 * c + 1]; i++)
							listed |= h.index[h.pivot[2 * c] + i] == q.first[k];
						bad_missing += strictly && !listed;
						bad_extra += listed && !loosely;
						checked++;
					}
				}
			/* every curve that influences a point is in its cell */
			for (int i = 0; i < 400; i++) {
				int k = (int)(frand() * (float)q.nquads);
				float c[3][4];
				curve_quads_get(&q, k, c);
				double x, z;
				qeval(c, frand(), &x, &z);
				float reach = q.prm[q.first[k]][0] + q.prm[q.first[k]][1];
				float a = frange(0, 6.283f), r = frand() * reach * 0.999f;
				float px = (float)x + r * cosf(a), pz = (float)z + r * sinf(a);
				int cell = curve_hash_cell(&h, px, pz);
				bool listed = false;
				for (int j = 0; cell >= 0 && j < h.pivot[2 * cell + 1]; j++)
					listed |= h.index[h.pivot[2 * cell] + j] == q.first[k];
				bad_infl += !listed;
			}
			CHECK(h.nall == q.nquads && h.all_offset == h.nindex, "all-curves list");
			curve_hash_free(&h);
		}
		curve_quads_free(&q);
		curve_set_free(&s);
	}
	CHECK(bad_missing == 0, "hash misses %d curves whose padded box covers the cell (%d checks)", bad_missing, checked);
	CHECK(bad_extra == 0, "hash lists %d curves whose padded box does not touch the cell", bad_extra);
	CHECK(bad_infl == 0, "%d influencing curves missing from a point's cell", bad_infl);
}

/* carving with the hash == carving with one cell holding every curve */
static void test_hash_vs_brute_eval(struct edits *ed)
{
	char err[256];
	struct params p;
	params_defaults(&p);
	struct curve_set s;
	random_set(&s, 6, 120.0f);
	int bad = 0, inside = 0;
	CHECK(edits_set_curves(ed, &s, 1, err, sizeof(err)) == 0, "set curves: %s", err);
	float (*ref)[4] = malloc(sizeof(*ref) * 3000);
	float (*pt)[2] = malloc(sizeof(*pt) * 3000);
	for (int i = 0; i < 3000; i++) {
		pt[i][0] = frange(-160, 160);
		pt[i][1] = frange(-160, 160);
		carve_ref_eval(ed, &p, pt[i][0], pt[i][1], false, ref[i]);
	}
	CHECK(edits_set_curves(ed, &s, 23, err, sizeof(err)) == 0, "set curves: %s", err);
	for (int i = 0; i < 3000; i++) {
		float e[4];
		carve_ref_eval(ed, &p, pt[i][0], pt[i][1], false, e);
		if (ref[i][1] > 0.0f) {
			inside++;
			bad += fabsf(e[0] - ref[i][0]) > 1e-4f * (1.0f + fabsf(ref[i][0])) || e[1] != ref[i][1];
		} else {
			bad += e[1] != 0.0f;
		}
	}
	CHECK(bad == 0, "hash 23^2 vs one cell: %d of 3000 points differ", bad);
	CHECK(inside > 100, "enough points under the curves' influence (%d)", inside);
	free(ref);
	free(pt);
	curve_set_free(&s);
}

/* ---- affected region ------------------------------------------------------------------ */

static void test_affected(struct edits *ed)
{
	char err[256];
	float a[3 * 3] = { -100, 0, -100, -80, 1, -90, -60, 0, -100 };
	float b[3 * 3] = { 0, 0, 0, 20, 1, 10, 40, 0, 0 };
	float c[3 * 3] = { 100, 0, 100, 120, 1, 90, 140, 0, 100 };
	struct curve_set s0 = { 0 }, s1;
	struct curve_path pa = make_path(3, a, 6, 4, 0, 0.5f), pb = make_path(3, b, 6, 4, 0, 0.5f),
			  pc = make_path(3, c, 6, 4, 0, 0.5f);
	curve_set_add(&s0, &pa);
	curve_set_add(&s0, &pb);
	curve_set_add(&s0, &pc);
	curve_set_copy(&s1, &s0);
	float box[4];
	CHECK(!curves_affected_bounds(&s0, &s1, box), "identical sets: nothing changed");
	s1.paths[1].pts[4] += 3.0f; /* lift the middle point of path b */
	s1.paths[1].pts[3] += 5.0f;
	CHECK(curves_affected_bounds(&s0, &s1, box), "moved point: changed");
	float ob[4], nb[4], ab[4], cb[4];
	curve_path_padded_box(&s0.paths[1], ob);
	curve_path_padded_box(&s1.paths[1], nb);
	curve_path_padded_box(&s0.paths[0], ab);
	curve_path_padded_box(&s0.paths[2], cb);
	CHECK(box[0] <= fminf(ob[0], nb[0]) && box[1] <= fminf(ob[1], nb[1]) && box[2] >= fmaxf(ob[2], nb[2]) &&
		      box[3] >= fmaxf(ob[3], nb[3]),
	      "box covers old and new path");
	CHECK(box[2] < cb[0] && box[0] > ab[2], "box excludes the unchanged paths ([%g %g %g %g])", box[0], box[1], box[2],
	      box[3]);
	/* added / removed */
	struct curve_set two = { s0.paths, 2 };
	CHECK(curves_affected_bounds(&two, &s0, box) && box[0] >= cb[0] - 1e-3f && box[2] <= cb[2] + 1e-3f,
	      "added path: its box");
	CHECK(curves_affected_bounds(&s0, &two, box) && box[0] >= cb[0] - 1e-3f, "removed path: its box");
	CHECK(curves_affected_bounds(NULL, &s0, box) && box[0] <= ab[0] && box[2] >= cb[2], "from nothing: all");

	/* every density change lies inside the reported box (CPU density) */
	struct params p;
	params_defaults(&p);
	set(&p, "octaves=3");
	static struct noise_set ns;
	noise_set_init(&ns, p.seed);
	CHECK(edits_set_curves(ed, &s0, 16, err, sizeof(err)) == 0, "set: %s", err);
	float dummy[4];
	edits_take_changes(ed, dummy);
	int N = 64;
	float *d0 = malloc(sizeof(float) * (size_t)(N * N));
	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++)
			d0[j * N + i] = density_ref(&p, &ns, ed, -150.0f + 300.0f * (float)i / (float)(N - 1), 0.5f,
						    -150.0f + 300.0f * (float)j / (float)(N - 1));
	CHECK(edits_set_curves(ed, &s1, 16, err, sizeof(err)) == 0, "set: %s", err);
	float tb[4];
	CHECK(edits_take_changes(ed, tb), "edits_take_changes reports the change");
	int outside = 0, changed = 0;
	for (int j = 0; j < N; j++)
		for (int i = 0; i < N; i++) {
			float x = -150.0f + 300.0f * (float)i / (float)(N - 1), z = -150.0f + 300.0f * (float)j / (float)(N - 1);
			float d = density_ref(&p, &ns, ed, x, 0.5f, z);
			if (d != d0[j * N + i]) {
				changed++;
				outside += !(x >= tb[0] && x <= tb[2] && z >= tb[1] && z <= tb[3]);
			}
		}
	CHECK(changed > 0 && outside == 0, "%d density changes, %d outside the reported box", changed, outside);
	CHECK(!edits_take_changes(ed, tb), "changes cleared after taking them");
	free(d0);
	curve_set_free(&s0);
	curve_set_free(&s1);
	edits_clear(ed);
}

/* ---- input files ----------------------------------------------------------------------- */

static void expect_parse_error(bool csv, const char *text, const char *want)
{
	struct curve_set s;
	char err[512] = "";
	int rc = csv ? curves_parse_csv(text, strlen(text), "t.csv", &s, err, sizeof(err))
		     : curves_parse_geojson(text, strlen(text), "t.geojson", &s, err, sizeof(err));
	CHECK(rc < 0 && strstr(err, want), "malformed %s: want '%s' in '%s'", csv ? "CSV" : "GeoJSON", want, err);
	if (rc == 0)
		curve_set_free(&s);
}

static void test_io(void)
{
	const char *geo = "{ \"type\": \"FeatureCollection\", \"features\": [\n"
			  "  { \"type\": \"Feature\", \"properties\": { \"kind\": \"river\", \"width\": 12.5, \"name\": \"x\" },\n"
			  "    \"geometry\": { \"type\": \"LineString\", \"coordinates\": [[0, 0, 1], [10, 5, 2.5e0], [20, 0, -3]] } },\n"
			  "  { \"type\": \"Feature\", \"properties\": null,\n"
			  "    \"geometry\": { \"type\": \"MultiLineString\", \"coordinates\": [ [[0,0,0],[1,1,1]], [[5,5,5],[6,6,6],[7,7,7]] ] } }\n"
			  "] }\n";
	struct curve_set s;
	char err[512] = "";
	int rc = curves_parse_geojson(geo, strlen(geo), "t.geojson", &s, err, sizeof(err));
	CHECK(rc == 0, "valid GeoJSON: %s", err);
	if (rc == 0) {
		CHECK(s.npaths == 3, "3 line strings, got %d", s.npaths);
		CHECK(s.paths[0].kind == CURVE_RIVER && s.paths[0].width == 12.5f && s.paths[0].falloff == 12.0f,
		      "river properties (defaults for the rest)");
		CHECK(s.paths[0].npts == 3 && s.paths[0].pts[3] == 10.0f && s.paths[0].pts[4] == 2.5f &&
			      s.paths[0].pts[5] == -5.0f,
		      "[east, north, up] -> (x, up, -north)");
		CHECK(s.paths[2].npts == 3 && s.paths[1].kind == CURVE_ROAD, "MultiLineString parts");
		curve_set_free(&s);
	}
	const char *csv = "# roads\npath,x,y,z,kind,width,falloff,inclination,smoothing\n"
			  "a,0,1,0,railway,3,2,0.5,0.25\na,10,1,0,,,,,\n\n a , 20 , 2 , 5 ,,,,,\n"
			  "b,0,0,0,,,,,\nb,1,0,1,road,,,,\n";
	rc = curves_parse_csv(csv, strlen(csv), "t.csv", &s, err, sizeof(err));
	CHECK(rc == 0, "valid CSV: %s", err);
	if (rc == 0) {
		CHECK(s.npaths == 2 && s.paths[0].npts == 3 && s.paths[1].npts == 2, "two paths (%d)", s.npaths);
		CHECK(s.paths[0].kind == CURVE_RAILWAY && s.paths[0].width == 3.0f && s.paths[0].smoothing == 0.25f &&
			      s.paths[0].pts[7] == 2.0f,
		      "CSV values");
		curve_set_free(&s);
	}
	/* malformed: each names the line */
	expect_parse_error(false, "{ \"type\": \"FeatureCollection\", \"features\": [\n  { \"type\": \"Feature\",\n", "t.geojson:3");
	expect_parse_error(false, "{\n \"type\": \"Feature\", \"geometry\": { \"type\": \"LineString\",\n \"coordinates\": [[0,0,0,0],[1,1,1,1]] } }",
			   "t.geojson:3: feature 1: position 1 has 4 coordinates; GeoJSON positions are [x east, y north] "
			   "(the curve follows the ground) or [x east, y north, z up] (z up, unlike the CSV's y up)");
	expect_parse_error(false, "{\"type\":\"LineString\",\"coordinates\":[[0,0],[1,1,1]]}",
			   "position 2 has 3 coordinates, position 1 has 2: a line string is all 2D [x east, y north] or all "
			   "3D [x east, y north, z up]");
	expect_parse_error(false, "{\"type\":\"LineString\",\"coordinates\":[[0,0],[1,\"n\"]]}",
			   "position 2: y (north) is not a number");
	expect_parse_error(false, "{\"type\":\"LineString\",\"crs\":{\"type\":\"EPSG\"},\"coordinates\":[[0,0],[1,1]]}",
			   "\"crs\" must be");
	expect_parse_error(false, "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1]]}},\n"
			   "{\"type\":\"Feature\",\"geometry\":{\"type\":\"Polygon\",\"coordinates\":[]}}]}",
			   "t.geojson:2: feature 2: geometry type \"Polygon\"");
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"width\":-3},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1]]}}",
			   "\"width\" = -3 must be");
	expect_parse_error(false, "{\"type\":\"Feature\",\"properties\":{\"kind\":\"canal\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1]]}}",
			   "\"kind\" must be");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[0,0,0]]}}",
			   "2 distinct positions");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,1],]}}",
			   "trailing comma");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[0,0,0],[1,1,01]]}}",
			   "expected ',' or ']'");
	expect_parse_error(false, "[1, 2]", "top level");
	expect_parse_error(false, "", "t.geojson:1: invalid JSON");
	expect_parse_error(false, "{\"type\":\"Feature\",\"geometry\":null}", "(it is null)");
	expect_parse_error(true, "path,x,y\na,0,0\n", "t.csv:1: the header has no 'z' column");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\na,1,zz,0\n", "t.csv:3: y 'zz' is not a number");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\na,1,0\n", "t.csv:3: 3 fields, the header has 4");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\na,1,0,0\nb,0,0,0\nb,1,1,1\na,5,5,5\na,6,6,6\n", "t.csv:6: rows of path 'a'");
	expect_parse_error(true, "path,x,y,z,width\na,0,0,0,3\na,1,0,0,4\n", "t.csv:3: width of path 'a' changes");
	expect_parse_error(true, "path,x,y,z,smoothing\na,0,0,0,2\na,1,0,0,\n", "t.csv:2: smoothing = 2 must be in [0, 1]");
	expect_parse_error(true, "path,x,y,z\na,0,0,0\nb,0,0,0\nb,1,1,1\n", "t.csv:2: path 'a' needs at least 2");
	expect_parse_error(true, "path,x,y,z,colour\n", "unknown column 'colour'");
	expect_parse_error(true, "# nothing\n", "empty CSV");

	/* files: extension, missing file */
	CHECK(curves_load("/nonexistent/x.geojson", &s, err, sizeof(err)) < 0 && strstr(err, "cannot open"), "missing: %s",
	      err);
	CHECK(curves_load("roads.kml", &s, err, sizeof(err)) < 0 && strstr(err, "unknown format"), "kml: %s", err);
}

/* Work sized from the input and refused before it is done: a road a
 * million units wide over a 1024^2 hash (each piece in every cell), files
 * with more points than the tables hold; 200 000 paths read in linear time
 * (a repeated id still found). */
static void test_sizes(void)
{
	char err[512] = "";
	float pts[200 * 3];
	for (int i = 0; i < 200; i++) {
		pts[3 * i] = 10.0f * (float)i;
		pts[3 * i + 1] = 0.0f;
		pts[3 * i + 2] = 3.0f * (float)(i % 7);
	}
	struct curve_path wp = make_path(200, pts, 1e6f, 2, 0, 0);
	struct curve_set ws = { &wp, 1 };
	struct curve_quads q;
	struct curve_hash h;
	CHECK(curves_build(&ws, &q, err, sizeof(err)) == 0, "wide road: %s", err);
	CHECK(curve_hash_build(&q, 1024, &h, err, sizeof(err)) == -1 && strstr(err, "curve hash too large: 416"),
	      "wide road over 1024^2 cells refused: '%s'", err);
	curve_quads_free(&q);

	long n = CURVE_MAX_POINTS + 1;
	size_t cap = (size_t)n * 16 + 256, len = 0;
	char *text = malloc(cap);
	len += (size_t)snprintf(text, cap, "path,x,y,z\n");
	for (long i = 0; i < n; i++)
		len += (size_t)snprintf(text + len, cap - len, "%ld,0,0,%d\n", i / 2, (int)(i % 2));
	struct curve_set s;
	CHECK(curves_parse_csv(text, len, "big.csv", &s, err, sizeof(err)) == -1 && strstr(err, "big.csv: 2097152 points"),
	      "CSV with too many points: '%s'", err);
	len = (size_t)snprintf(text, cap, "{\"type\":\"LineString\",\"coordinates\":[");
	for (long i = 0; i < n; i++)
		len += (size_t)snprintf(text + len, cap - len, "%s[%d,0,0]", i ? "," : "", (int)(i % 2));
	len += (size_t)snprintf(text + len, cap - len, "]}");
	CHECK(curves_parse_geojson(text, len, "big.geojson", &s, err, sizeof(err)) == -1 &&
		      strstr(err, "big.geojson: 2097152 positions"),
	      "GeoJSON with too many positions: '%s'", err);

	int np = 200000;
	len = (size_t)snprintf(text, cap, "path,x,y,z\n");
	for (int i = 0; i < np; i++)
		len += (size_t)snprintf(text + len, cap - len, "p%d,%d,0,0\np%d,%d,0,1\n", i, i, i, i);
	int rc = curves_parse_csv(text, len, "many.csv", &s, err, sizeof(err));
	CHECK(rc == 0 && s.npaths == np, "200 000 paths: %s", err);
	if (rc == 0)
		curve_set_free(&s);
	len += (size_t)snprintf(text + len, cap - len, "p17,0,0,0\np17,1,0,0\n");
	CHECK(curves_parse_csv(text, len, "many.csv", &s, err, sizeof(err)) == -1 && strstr(err, "rows of path 'p17'"),
	      "a repeated id among 200 000: '%s'", err);
	free(text);
}

static char tmpdir[] = "/tmp/isoterra-curves-XXXXXX";

/* ---- geographic input ---------------------------------------------------------------------- */

static int parse_geo(const char *text, struct curve_set *s)
{
	char err[512] = "";
	int rc = curves_parse_geojson(text, strlen(text), "g.geojson", s, err, sizeof(err));
	CHECK(rc == 0, "GeoJSON: %s", err);
	return rc;
}

/* lon/lat or world units, per the rule */
static bool geo_mode(const char *text, int mode, const char **why)
{
	struct curve_set s;
	bool ll = false;
	double c[2];
	char err[256];
	if (parse_geo(text, &s) == 0) {
		CHECK(curves_geo_project(&s, mode, 1.0f, &ll, why, c, err, sizeof(err)) == 0, "project: %s", err);
		curve_set_free(&s);
	}
	return ll;
}

static bool ramp_ground(void *ctx, float x, float z, float *y)
{
	(void)ctx;
	*y = 0.5f * x - 0.25f * z + 3.0f;
	return true;
}

static void test_geo(void)
{
	/* WGS84 (crs member): 0.01 degree of longitude and of latitude at 45 N.
	 * Expected lengths from the WGS84 radii of curvature at 45 degrees:
	 * N = 6388838.29 m, M = 6367381.82 m, so 0.01 degree east is
	 * N cos 45 * 0.01 pi/180 = 788.468 m, 0.01 north 1111.330 m. */
	const char *ll = "{\"type\":\"Feature\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
			 "\"urn:ogc:def:crs:OGC:1.3:CRS84\"}},\"geometry\":{\"type\":\"LineString\","
			 "\"coordinates\":[[7.00,44.995],[7.01,44.995],[7.01,45.005]]}}";
	struct curve_set s;
	char err[512];
	if (parse_geo(ll, &s) == 0) {
		bool lonlat;
		const char *why;
		double c[2];
		CHECK(s.paths[0].follow_ground && s.paths[0].crs == CURVE_CRS_WGS84, "2D, WGS84 named");
		CHECK(curves_geo_project(&s, CURVES_CRS_AUTO, 1.0f, &lonlat, &why, c, err, sizeof(err)) == 0, "%s", err);
		const float *q = s.paths[0].pts;
		CHECK(lonlat && strstr(why, "crs"), "lon/lat from the crs member (%s)", why);
		CHECK_NEAR(c[0], (7.00 + 2 * 7.01) / 3, 1e-9, "centroid lon");
		CHECK_NEAR(c[1], (44.995 * 2 + 45.005) / 3, 1e-9, "centroid lat");
		CHECK_NEAR(q[3] - q[0], 788.468, 0.05, "0.01 degree east at 45 N in metres");
		CHECK_NEAR(-(q[8] - q[5]), 1111.330, 0.05, "0.01 degree north at 45 N in metres (world z = -north)");
		CHECK_NEAR((q[0] + q[3] + q[6]) / 3, 0.0, 1e-3, "x centred on the centroid");
		CHECK_NEAR((q[2] + q[5] + q[8]) / 3, 0.0, 0.5, "z near the centroid (the projection is not linear in lat)");
		curve_set_free(&s);
	}
	/* the auto rule */
	const char *why = "";
	const char *small = "{\"type\":\"LineString\",\"coordinates\":[[-3.70,40.41,650],[-3.69,40.42,655]]}";
	const char *local = "{\"type\":\"LineString\",\"coordinates\":[[-14,-2,1],[4,9,2]]}";
	const char *named = "{\"type\":\"LineString\",\"crs\":{\"type\":\"name\",\"properties\":{\"name\":"
			    "\"EPSG:25830\"}},\"coordinates\":[[0.1,0.2,0],[0.3,0.4,0]]}";
	CHECK(geo_mode(small, CURVES_CRS_AUTO, &why), "small lon/lat extent, no crs: lon/lat (%s)", why);
	CHECK(!geo_mode(local, CURVES_CRS_AUTO, &why), "a span over a degree: world units (%s)", why);
	CHECK(!geo_mode(named, CURVES_CRS_AUTO, &why), "another crs named: world units (%s)", why);
	CHECK(geo_mode(local, CURVES_CRS_LONLAT, &why), "forced lon/lat");
	CHECK(!geo_mode(small, CURVES_CRS_LOCAL, &why), "forced local");
	/* 3D lon/lat: the altitude scaled with the rest */
	if (parse_geo(small, &s) == 0) {
		bool lonlat;
		double c[2];
		CHECK(curves_geo_project(&s, CURVES_CRS_AUTO, 0.01f, &lonlat, &why, c, err, sizeof(err)) == 0, "%s", err);
		CHECK(!s.paths[0].follow_ground && fabsf(s.paths[0].pts[1] - 6.5f) < 1e-4f, "altitude 650 m at 0.01: y 6.5");
		curve_set_free(&s);
	}
	/* 2D: points every step along the line, each on the ground */
	const char *flat = "{\"type\":\"LineString\",\"coordinates\":[[-10,0],[10,0],[10,-5]]}";
	if (parse_geo(flat, &s) == 0) {
		CHECK(curves_follow_ground(&s, 2.0f, ramp_ground, NULL, err, sizeof(err)) == 0, "follow: %s", err);
		const struct curve_path *p = &s.paths[0];
		int bad = 0;
		for (int k = 0; k < p->npts; k++)
			bad += fabsf(p->pts[3 * k + 1] - (0.5f * p->pts[3 * k] - 0.25f * p->pts[3 * k + 2] + 3.0f)) > 1e-5f;
		CHECK(p->npts == 1 + 10 + 3, "20 + 5 units at most 2 apart: 14 points, got %d", p->npts);
		CHECK(bad == 0, "%d points off the ground", bad);
		curve_set_free(&s);
	}
	if (parse_geo(flat, &s) == 0) {
		CHECK(curves_follow_ground(&s, 2.0f, NULL, NULL, err, sizeof(err)) < 0 && strstr(err, "[x east, y north, z up]"),
		      "no ground to follow: %s", err);
		curve_set_free(&s);
	}
}

/* A 2D GeoJSON file through the edit state and the terrain: every point on
 * the field's surface (CPU density: air just above, rock just below). */
static void test_geo_terrain(void)
{
	char path[200], err[512] = "";
	snprintf(path, sizeof(path), "%.150s/flat.geojson", tmpdir);
	FILE *f = fopen(path, "w");
	CHECK(f != NULL, "write %s", path);
	if (!f)
		return;
	fputs("{\"type\":\"Feature\",\"properties\":{\"kind\":\"road\",\"width\":3},\"geometry\":{\"type\":"
	      "\"LineString\",\"coordinates\":[[-12,-9],[0,2],[13,6]]}}\n",
	      f);
	fclose(f);
	struct params p;
	params_defaults(&p);
	set(&p, "octaves=5");
	snprintf(p.curves, sizeof(p.curves), "%s", path);
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	CHECK(edits_load(ed, &p, err, sizeof(err)) == 0, "2D curves on the terrain: %s", err);
	static struct noise_set ns;
	noise_set_init(&ns, p.seed);
	int bad = 0, n = 0;
	if (ed->curves.npaths == 1) {
		const struct curve_path *c = &ed->curves.paths[0];
		for (int k = 0; k < c->npts; k++, n++) {
			const float *q = c->pts + 3 * k;
			bad += !(density_ref(&p, &ns, NULL, q[0], q[1] + 0.02f, q[2]) < p.iso &&
				 density_ref(&p, &ns, NULL, q[0], q[1] - 0.02f, q[2]) >= p.iso);
		}
	}
	CHECK(n > 10 && bad == 0, "2D curve on the surface: %d of %d points not", bad, n);
	terrain_destroy(tr);
	/* without a terrain there is no ground to follow: refused */
	edits_clear(ed);
	CHECK(edits_load(ed, &p, err, sizeof(err)) < 0 && strstr(err, "follow the terrain"), "no terrain: %s", err);
	edits_destroy(ed);
	unlink(path);
}

/* ---- heightmap (CPU) --------------------------------------------------------------------- */

static void hm_path(char *buf, size_t len, const char *name)
{
	snprintf(buf, len, "%s/%s", tmpdir, name);
}

#define HM_W 9
#define HM_H 7
static uint16_t hm_data[HM_W * HM_H];

#ifdef ISOTERRA_HAVE_GDAL
#include <gdal.h>
/* GeoTIFF through GDAL: a Float32 DEM in metres with a no-data sample is
 * read with its valid range [min, max] mapped onto 0..65535; garbage and a
 * band-less file are refused with a message naming the file. */
static void test_geotiff(void)
{
	char path[600], err[512];
	const int W = 7, H = 5;
	float dem[7 * 5];
	for (int z = 0; z < H; z++)
		for (int x = 0; x < W; x++)
			dem[z * W + x] = 250.0f + 3.5f * (float)x - 2.0f * (float)z; /* 242 .. 271 */
	dem[2 * W + 3] = -9999.0f;                                                  /* no data */
	GDALAllRegister();
	hm_path(path, sizeof(path), "dem.tif");
	GDALDriverH drv = GDALGetDriverByName("GTiff");
	CHECK(drv != NULL, "GDAL has the GTiff driver");
	if (!drv)
		return;
	GDALDatasetH ds = GDALCreate(drv, path, W, H, 1, GDT_Float32, NULL);
	CHECK(ds != NULL, "create %s", path);
	if (!ds)
		return;
	GDALRasterBandH b = GDALGetRasterBand(ds, 1);
	CHECK(GDALSetRasterNoDataValue(b, -9999.0) == CE_None, "set no-data");
	CHECK(GDALRasterIO(b, GF_Write, 0, 0, W, H, dem, W, H, GDT_Float32, 0, 0) == CE_None, "write GeoTIFF");
	GDALClose(ds);
	struct heightmap hm;
	CHECK(heightmap_load(path, &hm, err, sizeof(err)) == 0, "load GeoTIFF: %s", err);
	int bad = 0;
	for (int i = 0; i < W * H && hm.v; i++) {
		float want = i == 2 * W + 3 ? 0.0f : (dem[i] - 242.0f) / (271.0f - 242.0f) * 65535.0f;
		bad += fabsf(hm.v[i] - want) > 0.05f;
	}
	CHECK(hm.w == W && hm.h == H && bad == 0, "GeoTIFF %dx%d: %d samples differ from the normalised DEM", hm.w, hm.h,
	      bad);
	heightmap_free(&hm);
	hm_path(path, sizeof(path), "garbage.tif");
	FILE *f = fopen(path, "w");
	if (f) {
		fputs("II*\\0 this is not a TIFF", f);
		fclose(f);
	}
	CHECK(heightmap_load(path, &hm, err, sizeof(err)) < 0 && strstr(err, "garbage.tif") &&
		      strstr(err, "GDAL cannot read it"),
	      "garbage GeoTIFF refused by GDAL (through the module): %s", err);
	printf("  GeoTIFF through GDAL: %dx%d Float32 DEM with no-data read and normalised; garbage refused (%s)\n", W,
	       H, err);
}
#endif

static void test_heightmap_cpu(struct edits *ed, struct params *p, const struct noise_set *ns)
{
	char path[256], err[512];
	for (int i = 0; i < HM_W * HM_H; i++)
		hm_data[i] = (uint16_t)(frand() * 65535.0f);
	hm_data[0] = 0;
	hm_data[1] = 65535;
	hm_path(path, sizeof(path), "hm.png");
	CHECK(image_write_png_gray16(path, hm_data, HM_W, HM_H, err, sizeof(err)) == 0, "write png16: %s", err);
	struct heightmap hm;
	CHECK(heightmap_load(path, &hm, err, sizeof(err)) == 0, "load: %s", err);
	int bad = 0;
	for (int i = 0; i < HM_W * HM_H && hm.v; i++)
		bad += hm.v[i] != (float)hm_data[i];
	CHECK(hm.w == HM_W && hm.h == HM_H && bad == 0, "16-bit round trip (%dx%d, %d differ)", hm.w, hm.h, bad);
	heightmap_free(&hm);
	CHECK(heightmap_load("x.tif", &hm, err, sizeof(err)) < 0 && strstr(err, "GDAL"), "GeoTIFF: %s", err);
#ifdef ISOTERRA_HAVE_GDAL
	test_geotiff();
#endif
	/* load through the parameters */
	char kv[512];
	snprintf(kv, sizeof(kv), "field=heightmap;heightmap=%s;heightmap_scale=2;heightmap_height=50;heightmap_base=-10;"
		 "heightmap_detail=0", path);
	set(p, kv);
	CHECK(edits_load(ed, p, err, sizeof(err)) == 0, "edits_load: %s", err);
	const struct edits *e = ed;
	/* exact at samples, with and without detail */
	p->heightmap_detail = 3.0f;
	double worst = 0;
	for (int z = 0; z < HM_H; z++)
		for (int x = 0; x < HM_W; x++) {
			float wx = ((float)x - 0.5f * (HM_W - 1)) * 2.0f, wz = ((float)z - 0.5f * (HM_H - 1)) * 2.0f;
			float want = -10.0f + (float)hm_data[z * HM_W + x] * 50.0f / 65535.0f;
			worst = fmax(worst, fabs(heightmap_ref_height(e, p, ns, wx, wz, true) - want));
		}
	CHECK(worst < 1e-4, "fractal interpolation exact at the samples (worst %g)", worst);
	/* between samples: detail adds roughness that bilinear lacks (magnified 16x) */
	double rough_b = 0, rough_f = 0, mean_dev = 0;
	int nline = 0;
	for (int z = 1; z < HM_H - 1; z++)
		for (int i = 1; i < 16 * (HM_W - 1) - 1; i++) {
			float wx0 = -0.5f * (HM_W - 1) * 2.0f;
			float wz = ((float)z - 0.5f * (HM_H - 1) + 0.37f) * 2.0f;
			float h3[2][3];
			for (int k = -1; k <= 1; k++) {
				float wx = wx0 + (float)(i + k) * 2.0f / 16.0f;
				h3[0][k + 1] = heightmap_ref_height(e, p, ns, wx, wz, false);
				h3[1][k + 1] = heightmap_ref_height(e, p, ns, wx, wz, true);
			}
			if ((i - 1) / 16 != (i + 1) / 16 || i % 16 == 0)
				continue; /* the stencil crosses a sample column: bilinear kinks there */
			rough_b += fabs(h3[0][0] - 2 * h3[0][1] + h3[0][2]);
			rough_f += fabs(h3[1][0] - 2 * h3[1][1] + h3[1][2]);
			mean_dev += fabs(h3[1][1] - h3[0][1]);
			nline++;
		}
	mean_dev /= nline;
	CHECK(rough_f > 3.0 * rough_b, "detail adds sub-sample roughness: %g vs bilinear %g", rough_f, rough_b);
	CHECK(mean_dev > 0.05 && mean_dev < 3.0, "detail deviation from bilinear %g (amplitude 3)", mean_dev);
	printf("  heightmap: roughness with detail %.3g vs bilinear %.3g, mean deviation %.3g\n", rough_f, rough_b,
	       mean_dev);
	/* bump continuity across a cell edge */
	float ex = (1.0f - 0.5f * (HM_W - 1)) * 2.0f, ez = (2.3f - 0.5f * (HM_H - 1)) * 2.0f;
	float l = heightmap_ref_height(e, p, ns, ex - 1e-3f, ez, true), r = heightmap_ref_height(e, p, ns, ex + 1e-3f, ez, true);
	CHECK(fabsf(l - r) < 0.05f, "continuous across a cell edge: %g vs %g", l, r);
}

/* ---- GPU ------------------------------------------------------------------------------------ */

static void test_closest_gpu(struct edits *ed, const struct params *p, const float *items, int n)
{
	char err[512];
	float *out = malloc(sizeof(float) * 4 * (size_t)n);
	int rc = curves_gpu_test(ed, p, 0, items, n, out, err, sizeof(err));
	CHECK(rc == 0, "curve_test mode 0: %s", err);
	double worst = 0, worst_ref = 0;
	int bad = 0, bad_ref = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		const float *it = items + 16 * i;
		float c[3][4], ref[4];
		memcpy(c, it, sizeof(c));
		double b = brute_dist(c, it[12], it[13]);
		double scale = 1.0 + fabs(it[12]) + fabs(it[13]);
		double e = fabs(fabs((double)out[4 * i]) - b) / scale;
		worst = fmax(worst, e);
		bad += e > 2e-5;
		carve_ref_closest(c, it + 12, ref);
		/* |d| (two parts of a curve may be equally near, with either sign) */
		double er = fabs(fabs(out[4 * i]) - fabs(ref[0])) / scale;
		worst_ref = fmax(worst_ref, er);
		bad_ref += er > 1e-5;
	}
	printf("  closest point on the GPU: %d cases, worst error %.3g (relative to 1+|x|+|z|), vs CPU mirror %.3g\n", n,
	       worst, worst_ref);
	CHECK(bad == 0, "GPU closest point: %d of %d off the brute-force distance (worst %.3g)", bad, n, worst);
	CHECK(bad_ref == 0, "GPU vs CPU mirror: %d of %d differ (worst %.3g)", bad_ref, n, worst_ref);
	free(out);
}

static void test_eval_gpu(struct edits *ed, struct params *p)
{
	char err[512];
	struct curve_set s;
	random_set(&s, 5, 100.0f);
	CHECK(edits_set_curves(ed, &s, 16, err, sizeof(err)) == 0, "set: %s", err);
	set(p, "curve_incl_lo=0.3;curve_incl_hi=0.9;curve_incl_exp=2;curve_blend_lo=0.2;curve_blend_hi=0.8;curve_strength=0.9");
	int n = 4000;
	float *in = malloc(sizeof(float) * 4 * (size_t)n), *out = malloc(sizeof(float) * 4 * (size_t)n);
	for (int i = 0; i < n; i++) {
		in[4 * i] = frange(-140, 140);
		in[4 * i + 1] = frange(-140, 140);
		in[4 * i + 2] = frange(-10, 10);
		in[4 * i + 3] = frange(-20, 20);
	}
	int rc = curves_gpu_test(ed, p, 1, in, n, out, err, sizeof(err));
	CHECK(rc == 0, "curve_test mode 1: %s", err);
	int bad = 0, influenced = 0;
	double worst = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		float e[4];
		carve_ref_eval(ed, p, in[4 * i], in[4 * i + 1], false, e);
		float d = carve_ref_density(ed, p, in[4 * i], in[4 * i + 2], in[4 * i + 1], in[4 * i + 3]);
		if (e[1] > 0.0f) {
			influenced++;
			double err_h = fabs(out[4 * i] - e[0]), err_t = fabs(out[4 * i + 1] - e[1]);
			worst = fmax(worst, fmax(err_h, err_t));
			bad += err_h > 1e-3 || err_t > 1e-3;
		} else {
			bad += out[4 * i + 1] != 0.0f;
		}
		bad += fabsf(out[4 * i + 3] - d) > 1e-3f * (1.0f + fabsf(d));
	}
	printf("  curve evaluation through the GPU hash: %d points (%d influenced), worst |h|/Θ error %.3g\n", n,
	       influenced, worst);
	CHECK(bad == 0, "GPU curve_eval/carve vs CPU: %d of %d differ (worst %.3g)", bad, n, worst);
	/* (path 3 is a tunnel: no surface, its tube checked by the carve above) */
	CHECK(influenced > 150, "points under the surface curves' influence: %d", influenced);
	/* displacement bake: GPU vs CPU, and the iterative baseline near it */
	struct bake_opts o = { { 96, 80 }, { -120, -110 }, { 240, 220 }, false, false };
	float *g = malloc(sizeof(float) * 96 * 80), *c = malloc(sizeof(float) * 96 * 80), *gi = malloc(sizeof(float) * 96 * 80);
	rc = curves_bake(ed, p, &o, g, err, sizeof(err));
	CHECK(rc == 0, "bake: %s", err);
	carve_ref_bake(ed, p, &o, c);
	o.dense = true; /* every texel: the same map as the tiles over non-empty cells */
	CHECK(curves_bake(ed, p, &o, gi, err, sizeof(err)) == 0, "dense bake: %s", err);
	int tdiff = 0;
	for (int i = 0; i < 96 * 80; i++)
		tdiff += gi[i] != g[i];
	CHECK(tdiff == 0, "tiled bake vs dense bake: %d texels differ", tdiff);
	o.iterative = true;
	CHECK(curves_bake(ed, p, &o, gi, err, sizeof(err)) == 0, "iterative bake: %s", err);
	double wb = 0, wi = 0, mean_i = 0;
	int nz = 0;
	for (int i = 0; i < 96 * 80; i++) {
		wb = fmax(wb, fabs(g[i] - c[i]));
		wi = fmax(wi, fabs(gi[i] - g[i]));
		mean_i += fabs(gi[i] - g[i]);
		nz += g[i] != 0.0f;
	}
	mean_i /= 96 * 80;
	printf("  bake 96x80: GPU vs CPU worst %.3g; iterative (32 segments) vs analytic worst %.3g, mean %.3g\n", wb, wi,
	       mean_i);
	CHECK(nz > 200 && wb < 2e-3, "bake GPU vs CPU: worst %g (%d non-zero texels)", wb, nz);
	CHECK(mean_i < 0.05 && wi < 2.0, "iterative baseline close to the analytic bake (worst %g, mean %g)", wi, mean_i);
	free(g);
	free(c);
	free(gi);
	free(in);
	free(out);
	curve_set_free(&s);
	params_defaults(p);
}

static void test_heightmap_gpu(struct edits *ed, struct params *p, const struct noise_set *ns)
{
	char err[512];
	struct noise_gl ng;
	CHECK(noise_gl_init(&ng, ns, err, sizeof(err)) == 0, "noise gl: %s", err);
	noise_gl_bind(&ng);
	int n = 2000;
	float *in = malloc(sizeof(float) * 4 * (size_t)n), *out = malloc(sizeof(float) * 4 * (size_t)n);
	for (int i = 0; i < n; i++) {
		in[4 * i] = frange(-12, 12);
		in[4 * i + 1] = frange(-9, 9);
		in[4 * i + 2] = in[4 * i + 3] = 0;
	}
	int rc = curves_gpu_test(ed, p, 2, in, n, out, err, sizeof(err));
	CHECK(rc == 0, "curve_test mode 2: %s", err);
	double w = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		float hf = heightmap_ref_height(ed, p, ns, in[4 * i], in[4 * i + 1], true);
		float hb = heightmap_ref_height(ed, p, ns, in[4 * i], in[4 * i + 1], false);
		w = fmax(w, fmax(fabs(out[4 * i] - hf), fabs(out[4 * i + 1] - hb)));
	}
	CHECK(w < 1e-3, "GPU heightmap (fractal + bilinear) vs CPU: worst %g", w);
	noise_gl_destroy(&ng);
	free(in);
	free(out);
}

/* density pass with curves (terrain) or heightmap vs density_ref_volume */
static void check_density(struct edits *ed, const char *what, const struct params *p, int gridn)
{
	char err[512] = "";
	struct params q = *p;
	q.grid = gridn;
	struct grid g;
	grid_from_params(&g, &q);
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &q, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "%s: pipeline_create: %s", what, err);
	if (!pl) {
		terrain_destroy(tr);
		return;
	}
	CHECK(fixture_density(pl, &q) == 0, "%s: density pass", what);
	long nd = grid_dens_count(&g);
	float *dg = malloc(sizeof(float) * (size_t)nd), *dc = malloc(sizeof(float) * (size_t)nd);
	CHECK(pipeline_read_density(pl, dg) == 0, "%s: read", what);
	static struct noise_set ns;
	noise_set_init(&ns, q.seed);
	density_ref_volume(&q, &ns, ed, g.origin, g.cell, g.nx, g.ny, g.nz, dc);
	double dmax = 0, scale = 0;
	for (long i = 0; i < nd; i++) {
		dmax = fmax(dmax, fabs((double)dg[i] - dc[i]));
		scale = fmax(scale, fabs((double)dc[i]));
	}
	printf("  %s: GPU vs CPU density max error %.3g (scale %.3g)\n", what, dmax, scale);
	CHECK(dmax <= 2e-5 * fmax(scale, 1.0), "%s: GPU vs CPU density max error %g (scale %g)", what, dmax, scale);
	free(dg);
	free(dc);
	pipeline_destroy(pl);
	terrain_destroy(tr);
}

/* Heights where a vertical line at (x, z) crosses the mesh. */
static int ray_hits(const struct mesh *m, float x, float z, float *ys, int max)
{
	int n = 0;
	for (uint32_t t = 0; t < m->ntris; t++) {
		const float *a = m->pos + 3 * m->idx[3 * t], *b = m->pos + 3 * m->idx[3 * t + 1],
			    *c = m->pos + 3 * m->idx[3 * t + 2];
		float d = (b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0]);
		if (fabsf(d) < 1e-12f)
			continue;
		float u = ((x - a[0]) * (c[2] - a[2]) - (z - a[2]) * (c[0] - a[0])) / d;
		float v = ((b[0] - a[0]) * (z - a[2]) - (b[2] - a[2]) * (x - a[0])) / d;
		if (u < -1e-5f || v < -1e-5f || u + v > 1.0f + 1e-5f)
			continue;
		if (n < max)
			ys[n++] = a[1] + u * (b[1] - a[1]) + v * (c[1] - a[1]);
	}
	return n;
}

/* Top surface height of a density column at (i, k) of the grid (the GPU densities). */
static float column_top(const struct grid *g, const float *dens, int i, int k, float iso)
{
	int sx = g->nx + 3, sy = g->ny + 3;
	for (int j = g->ny - 1; j >= 1; j--) { /* from the top, skipping the closed border */
		float d0 = dens[((size_t)(k + 1) * sy + (size_t)(j + 1)) * sx + (size_t)(i + 1)];
		float d1 = dens[((size_t)(k + 1) * sy + (size_t)(j + 2)) * sx + (size_t)(i + 1)];
		if (d0 > iso && d1 <= iso)
			return g->origin[1] + g->cell * ((float)j + (d0 - iso) / (d0 - d1));
	}
	return NAN;
}

static void test_road_centreline(struct edits *ed)
{
	char err[512] = "";
	struct params p;
	params_defaults(&p);
	set(&p, "grid=48;octaves=5;noise_amp=16;closed=true;vol_size=32;vol_height=0.75;vol_y=-1"); /* the diorama box */
	struct grid g;
	grid_from_params(&g, &p);
	/* the road: an S across the volume; first the uncarved surface along it */
	const int NP = 5;
	float pts[5 * 3] = { -14, 0, -9, -5, 0, -3, 0, 0, 1, 6, 0, 2, 14, 0, 9 };
	edits_clear(ed);
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	CHECK(pl != NULL, "pipeline: %s", err);
	if (!pl) {
		terrain_destroy(tr);
		return;
	}
	long nd = grid_dens_count(&g);
	float *dens = malloc(sizeof(float) * (size_t)nd);
	CHECK(fixture_density(pl, &p) == 0 && pipeline_read_density(pl, dens) == 0, "uncarved density");
	/* heights of the uncarved terrain at the road's vertices; road at their median */
	float tops[5], sorted[5];
	for (int v = 0; v < NP; v++) {
		int i = (int)lroundf((pts[3 * v] - g.origin[0]) / g.cell), k = (int)lroundf((pts[3 * v + 2] - g.origin[2]) / g.cell);
		tops[v] = column_top(&g, dens, i, k, p.iso);
		sorted[v] = isnan(tops[v]) ? 0.0f : tops[v];
	}
	for (int a = 0; a < NP; a++)
		for (int b = a + 1; b < NP; b++)
			if (sorted[b] < sorted[a]) {
				float t = sorted[a];
				sorted[a] = sorted[b];
				sorted[b] = t;
			}
	for (int v = 0; v < NP; v++) /* a gentle grade around the median */
		pts[3 * v + 1] = sorted[NP / 2] + 0.15f * pts[3 * v];
	struct curve_path rp = make_path(NP, pts, 4.0f, 3.0f, 0.0f, 0.5f);
	struct curve_set rs = { &rp, 1 };
	CHECK(edits_set_curves(ed, &rs, 16, err, sizeof(err)) == 0, "road: %s", err);
	CHECK(fixture_run(pl, &p) == 0, "carved pipeline run");
	struct mesh m;
	CHECK(pipeline_read_mesh(pl, &m) == 0, "read mesh");
	CHECK(pipeline_read_density(pl, dens) == 0, "carved density");
	/* along the centre line, away from the closed volume's walls */
	const struct edits *e = ed;
	int n = 0, bad_mesh = 0, bad_col = 0, cut = 0, fill = 0;
	double worst = 0;
	for (int qi = 0; qi < e->quads.nquads; qi++) {
		float c[3][4];
		curve_quads_get(&e->quads, qi, c);
		for (int s = 0; s < 8; s++) {
			double t = (s + 0.5) / 8.0, x, z;
			qeval(c, t, &x, &z);
			if (fabs(x) > 16 - 3 * g.cell || fabs(z) > 16 - 3 * g.cell)
				continue;
			float ev[4];
			carve_ref_eval(e, &p, (float)x, (float)z, false, ev);
			float h = ev[0];
			float ys[16];
			int nh = ray_hits(&m, (float)x, (float)z, ys, 16), nk = 0;
			for (int k = 0; k < nh; k++) /* not the closed volume's floor and ceiling */
				if (ys[k] > g.origin[1] + 1.5f * g.cell && ys[k] < g.origin[1] + ((float)g.ny - 1.5f) * g.cell)
					ys[nk++] = ys[k];
			nh = nk;
			int ok = nh > 0;
			for (int k = 0; k < nh; k++) {
				ok &= fabsf(ys[k] - h) <= g.cell;
				worst = fmax(worst, fabs(ys[k] - h));
			}
			bad_mesh += !ok;
			/* the density column at the nearest grid column */
			int ci = (int)lroundf(((float)x - g.origin[0]) / g.cell), ck = (int)lroundf(((float)z - g.origin[2]) / g.cell);
			float cx = g.origin[0] + (float)ci * g.cell, cz = g.origin[2] + (float)ck * g.cell;
			carve_ref_eval(e, &p, cx, cz, false, ev);
			float top = column_top(&g, dens, ci, ck, p.iso);
			bad_col += !(fabsf(top - ev[0]) <= g.cell);
			n++;
		}
	}
	for (int v = 0; v < NP; v++) {
		if (isnan(tops[v]))
			continue;
		cut += tops[v] > pts[3 * v + 1] + 2 * g.cell;
		fill += tops[v] < pts[3 * v + 1] - 2 * g.cell;
	}
	printf("  road centre line: %d points, worst |mesh y - curve height| %.3f (voxel %.3f); uncarved terrain above "
	       "the road at %d vertices, below at %d\n",
	       n, worst, g.cell, cut, fill);
	CHECK(n >= 40, "centre-line points checked: %d", n);
	CHECK(bad_mesh == 0, "%d of %d centre-line points: the mesh is not at the curve height +- one voxel (worst %g)",
	      bad_mesh, n, worst);
	CHECK(bad_col == 0, "%d of %d density columns: surface not at the curve height +- one voxel", bad_col, n);
	CHECK(cut > 0 && fill > 0, "the road both cuts (%d) and fills (%d) the terrain", cut, fill);
	mesh_free(&m);
	free(dens);
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_clear(ed);
}

/* A tunnel carves a tube and leaves the rock above it; the same curve as a
 * road removes everything above it.  Flat ground at y = 0 (no noise), the
 * curve straight along x at height h, radius r = w/2 (axis at h + r/2). */
static void test_tunnel_cpu(struct edits *ed)
{
	struct params p;
	params_defaults(&p);
	static struct noise_set ns;
	noise_set_init(&ns, p.seed);
	set(&p, "noise_amp=0;warp_amp=0;floor_strength=0");
	const float h = -6.0f, r = 2.0f, lam = 1.5f;
	float pts[3 * 3] = { -20, h, 0, 0, h, 0.01f, 20, h, 0 };
	struct curve_path cp = make_path(3, pts, 2 * r, lam, 0, 0.5f);
	cp.kind = CURVE_TUNNEL;
	struct curve_set cs = { &cp, 1 };
	char err[256];
	CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "tunnel: %s", err);
	CHECK(edits_has_tunnels(ed), "the edit state knows it holds a tunnel");
	int bad_air = 0, bad_roof = 0, bad_floor = 0, bad_side = 0, n = 0;
	for (float x = -12.0f; x <= 12.0f; x += 0.75f, n++) {
		bad_air += !(density_ref(&p, &ns, ed, x, h + 0.5f * r, 0.0f) < 0.0f);
		bad_air += !(density_ref(&p, &ns, ed, x, h + 0.2f, 0.0f) < 0.0f);
		/* above the tube's top: rock, and the ground's surface untouched */
		bad_roof += !(density_ref(&p, &ns, ed, x, h + 1.5f * r + 0.5f, 0.0f) > 0.0f);
		bad_roof += density_ref(&p, &ns, ed, x, -0.3f, 0.0f) != density_ref(&p, &ns, NULL, x, -0.3f, 0.0f);
		bad_floor += !(density_ref(&p, &ns, ed, x, h - 0.3f, 0.0f) > 0.0f);
		bad_side += !(density_ref(&p, &ns, ed, x, h + 0.5f * r, r + 0.4f) > 0.0f);
	}
	CHECK(bad_air == 0, "tunnel: %d of %d points on the tube's axis and above its floor are not air", bad_air, 2 * n);
	CHECK(bad_roof == 0, "tunnel: the rock above the tube changed at %d of %d points", bad_roof, 2 * n);
	CHECK(bad_floor == 0, "tunnel: %d of %d points under the floor are not rock", bad_floor, n);
	CHECK(bad_side == 0, "tunnel: %d of %d points beside the tube are not rock", bad_side, n);
	/* the same curve as a road: a slot, everything above h removed */
	cp.kind = CURVE_ROAD;
	CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "road: %s", err);
	CHECK(!edits_has_tunnels(ed), "a road is no tunnel");
	CHECK(density_ref(&p, &ns, ed, 1.0f, h + 1.5f * r + 0.5f, 0.0f) < 0.0f, "a road removes the rock above it");
	/* in the open (the curve above the ground): an embankment carries the
	 * floor, the air above it stays air, nothing beyond the reach */
	for (int i = 0; i < 3; i++)
		pts[3 * i + 1] = 3.0f;
	cp.kind = CURVE_TUNNEL;
	CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "tunnel in the open: %s", err);
	CHECK(density_ref(&p, &ns, ed, 2.0f, 2.5f, 0.0f) > 0.0f, "tunnel in the open: rock under the floor");
	CHECK(density_ref(&p, &ns, ed, 2.0f, 3.0f - lam, r + 0.5f * lam) > 0.0f, "tunnel in the open: the embankment's slope");
	CHECK(density_ref(&p, &ns, ed, 2.0f, 2.5f, r + 0.5f * lam) < 0.0f, "tunnel in the open: 45 degrees, no wider");
	CHECK(density_ref(&p, &ns, ed, 2.0f, 4.0f, 0.0f) < 0.0f, "tunnel in the open: air above the floor");
	CHECK(density_ref(&p, &ns, ed, 2.0f, 1.0f, r + lam + 1.0f) == density_ref(&p, &ns, NULL, 2.0f, 1.0f, r + lam + 1.0f),
	      "tunnel in the open: nothing beyond the reach");
	edits_clear(ed);
}

/* ---- edits re-generate only the affected world blocks ------------------------ */

#define WB_LODS 2
#define WB_R 12 /* block indices -WB_R..WB_R-1 in x and z, -4..3 in y */
struct wb_snap {
	int gens[WB_LODS][8][2 * WB_R][2 * WB_R];
	int state[WB_LODS][8][2 * WB_R][2 * WB_R];
};

static void wb_snapshot(const struct world *w, struct wb_snap *s)
{
	for (int l = 0; l < WB_LODS; l++)
		for (int y = 0; y < 8; y++)
			for (int z = 0; z < 2 * WB_R; z++)
				for (int x = 0; x < 2 * WB_R; x++) {
					int idx[3] = { x - WB_R, y - 4, z - WB_R };
					s->gens[l][y][z][x] = world_block_generations(w, l, idx, &s->state[l][y][z][x]);
				}
}

/* Blocks of the world (known before the edit) whose density samples see a
 * curve (Θ > 0 somewhere in the block's XZ footprint padded by its sample
 * margin), by sampling the CPU mirror of the carve on a fine XZ grid: the
 * blocks an edit of these curves must re-generate. */
static void wb_touched(const struct edits *ed, const struct params *p, const struct wb_snap *before, bool touched[WB_LODS][2 * WB_R][2 * WB_R])
{
	const struct edits *e = ed;
	memset(touched, 0, sizeof(bool) * WB_LODS * 4 * WB_R * WB_R);
	const float step = 0.25f;
	for (float z = -WB_R * p->block_size * 2; z < WB_R * p->block_size * 2; z += step)
		for (float x = -WB_R * p->block_size * 2; x < WB_R * p->block_size * 2; x += step) {
			float ev[4];
			carve_ref_eval(e, p, x, z, false, ev);
			if (ev[1] <= 0.0f)
				continue;
			for (int l = 0; l < WB_LODS; l++) {
				float bs = p->block_size * (float)(1 << l);
				/* world.c: 1 + AO_MARGIN (6) density samples around a block */
				float pad = 7.0f * bs / (float)p->block_cells;
				for (int bz = 0; bz < 2 * WB_R; bz++)
					for (int bx = 0; bx < 2 * WB_R; bx++) {
						float lx = (float)(bx - WB_R) * bs, lz = (float)(bz - WB_R) * bs;
						if (x >= lx - pad && x <= lx + bs + pad && z >= lz - pad && z <= lz + bs + pad)
							touched[l][bz][bx] = true;
					}
			}
		}
	(void)before;
}

/* One edit: the blocks re-generated must include every known block whose
 * samples the changed curves reach, and lie within the path's padded
 * bounding box (computed here from the input points). */
static void wb_check_edit(struct edits *ed, const char *what, struct world *w, const struct params *p, const struct camera *c,
			  const struct curve_set *next, const float *pts, int npts, float reach)
{
	static struct wb_snap before, after;
	static bool touched_old[WB_LODS][2 * WB_R][2 * WB_R], touched_new[WB_LODS][2 * WB_R][2 * WB_R];
	char err[256];
	wb_snapshot(w, &before);
	wb_touched(ed, p, &before, touched_old);
	struct world_stats s0, s1;
	world_get_stats(w, &s0);
	CHECK(edits_set_curves(ed, next, 16, err, sizeof(err)) == 0, "%s: %s", what, err);
	wb_touched(ed, p, &before, touched_new);
	CHECK(world_fill(w, p, c, 1.0) == 0, "%s: world_fill", what);
	world_get_stats(w, &s1);
	wb_snapshot(w, &after);
	float bx0 = FLT_MAX, bz0 = FLT_MAX, bx1 = -FLT_MAX, bz1 = -FLT_MAX;
	for (int i = 0; i < npts; i++) {
		bx0 = fminf(bx0, pts[3 * i] - reach);
		bx1 = fmaxf(bx1, pts[3 * i] + reach);
		bz0 = fminf(bz0, pts[3 * i + 2] - reach);
		bz1 = fmaxf(bz1, pts[3 * i + 2] + reach);
	}
	int known = 0, regen = 0, must = 0, missed = 0, outside = 0;
	for (int l = 0; l < WB_LODS; l++) {
		float bs = p->block_size * (float)(1 << l);
		float pad = 8.0f * bs / (float)p->block_cells; /* the margin + one cell of rounding */
		for (int y = 0; y < 8; y++)
			for (int z = 0; z < 2 * WB_R; z++)
				for (int x = 0; x < 2 * WB_R; x++) {
					int st = before.state[l][y][z][x];
					if (st == 0) /* unknown or evicted */
						continue;
					known++;
					bool again = after.gens[l][y][z][x] > before.gens[l][y][z][x];
					regen += again;
					if (touched_old[l][z][x] || touched_new[l][z][x]) {
						must++;
						missed += !again;
					}
					float lx = (float)(x - WB_R) * bs, lz = (float)(z - WB_R) * bs;
					bool in_box = lx + bs + pad >= bx0 && lx - pad <= bx1 && lz + bs + pad >= bz0 && lz - pad <= bz1;
					outside += again && !in_box;
				}
	}
	printf("  world edit (%s): %d known blocks, %d must re-generate, %d re-generated (%llu generations in all)\n",
	       what, known, must, regen, (unsigned long long)(s1.generated - s0.generated));
	CHECK(must > 0, "%s: the edit touches blocks of the view", what);
	CHECK(missed == 0, "%s: %d blocks under the edit were not re-generated", what, missed);
	CHECK(outside == 0, "%s: %d blocks away from the edited path were re-generated", what, outside);
	CHECK(regen < known / 2, "%s: %d of %d blocks re-generated: not local", what, regen, known);
	CHECK(s1.generated - s0.generated == (uint64_t)regen, "%s: generations %llu == blocks re-generated %d", what,
	      (unsigned long long)(s1.generated - s0.generated), regen);
}

static void test_world_edits(struct edits *ed)
{
	struct params p;
	params_defaults(&p);
	set(&p, "scene=world;block_pool=200;view_distance=40;lod_levels=2;ao_rays=0;fade_time=0;gen_per_frame=64");
	edits_clear(ed);
	char err[512] = "";
	struct world *w = world_create(&p, ed, err, sizeof(err));
	CHECK(w != NULL, "world_create: %s", err);
	if (!w)
		return;
	struct camera c;
	float eye[3] = { 0, 14, 30 }, at[3] = { 0, 0, 0 };
	camera_look(&c, eye, at, p.fov, 1.5f, 0.1f, 100.0f);
	CHECK(world_fill(w, &p, &c, 0.0) == 0, "world_fill");
	struct world_stats st;
	world_get_stats(w, &st);
	uint64_t g0 = st.generated;
	CHECK(world_fill(w, &p, &c, 0.5) == 0, "world_fill again");
	world_get_stats(w, &st);
	CHECK(st.generated == g0, "no edit, nothing re-generated (%llu -> %llu)", (unsigned long long)g0,
	      (unsigned long long)st.generated);
	/* a road across part of the view, then moved, then removed */
	float a[3 * 3] = { -10, 0.5f, -2, -2, 1.0f, 2, 6, 1.5f, 0 };
	struct curve_path rp = make_path(3, a, 3.0f, 2.0f, 0.0f, 0.5f);
	struct curve_set rs = { &rp, 1 };
	float reach = 3.0f / 2 + 2.0f;
	wb_check_edit(ed, "road added", w, &p, &c, &rs, a, 3, reach);
	float b[3 * 3] = { -10, 0.5f, -2, -2, 3.0f, 2, 6, 1.5f, 0 }, ab[6 * 3];
	memcpy(ab, a, sizeof(a));
	memcpy(ab + 9, b, sizeof(b));
	rp.pts = b;
	wb_check_edit(ed, "road raised", w, &p, &c, &rs, ab, 6, reach);
	struct curve_set none = { NULL, 0 };
	wb_check_edit(ed, "road removed", w, &p, &c, &none, b, 3, reach);
	world_destroy(w);
	edits_clear(ed);
}

int main(void)
{
	if (!mkdtemp(tmpdir)) {
		perror("mkdtemp");
		return 1;
	}
	struct edits *ed = edits_create();
	test_pipeline_cpu();
	test_hash_cpu();
	test_hash_vs_brute_eval(ed);
	test_affected(ed);
	test_io();
	test_sizes();
	int ncases = 1200;
	float *items = malloc(sizeof(float) * 16 * (size_t)ncases);
	ncases = make_closest_cases(items, ncases);
	double worst_cpu;
	test_closest_cpu(items, ncases, &worst_cpu);
	printf("  closest point on the CPU: %d cases, worst error %.3g\n", ncases, worst_cpu);

	static struct noise_set ns;
	struct params p;
	params_defaults(&p);
	noise_set_init(&ns, p.seed);
	test_heightmap_cpu(ed, &p, &ns);
	test_tunnel_cpu(ed);
	test_geo();
	test_geo_terrain();

	struct platform *plat = fixture_open();
	test_heightmap_gpu(ed, &p, &ns);
	/* density pass: heightmap field with detail, 3D noise and a river */
	{
		float riv[4 * 3] = { -8, -6, -8, -2, -7, 0, 3, -8, 3, 8, -9, 9 };
		struct curve_path rp = make_path(4, riv, 3, 2, 5, 0.7f);
		rp.kind = CURVE_RIVER;
		struct curve_set rs = { &rp, 1 };
		char err[256];
		CHECK(edits_set_curves(ed, &rs, 8, err, sizeof(err)) == 0, "river: %s", err);
		set(&p, "heightmap_noise=0.2;octaves=3;vol_size=16;vol_y=-2;closed=false");
		check_density(ed, "heightmap + detail + noise + river", &p, 24);
	}
	edits_clear(ed);
	params_defaults(&p);
	{
		struct curve_set s;
		random_set(&s, 4, 20.0f);
		char err[256];
		CHECK(edits_set_curves(ed, &s, 16, err, sizeof(err)) == 0, "curves: %s", err);
		set(&p, "octaves=4;curve_incl_lo=0.2;curve_incl_hi=0.8");
		check_density(ed, "terrain + 4 random curves", &p, 24);
		curve_set_free(&s);
		edits_clear(ed);
		params_defaults(&p);
	}
	/* a tunnel through the terrain beside a road: the tube, its embankment,
	 * the road's blend skipping the tunnel */
	{
		float tun[4 * 3] = { -14, -3, -6, -4, -2, -1, 5, -1, 2, 14, 0, 7 };
		float road[3 * 3] = { -14, 1, 8, 0, 2, 4, 14, 2, -6 };
		struct curve_path tp[2] = { make_path(4, tun, 5, 3, 0, 0.5f), make_path(3, road, 4, 3, 0, 0.5f) };
		tp[0].kind = CURVE_TUNNEL;
		struct curve_set ts = { tp, 2 };
		char err[256];
		CHECK(edits_set_curves(ed, &ts, 8, err, sizeof(err)) == 0, "tunnel and road: %s", err);
		set(&p, "octaves=4");
		check_density(ed, "terrain + tunnel + road", &p, 24);
		edits_clear(ed);
		params_defaults(&p);
	}
	test_closest_gpu(ed, &p, items, ncases);
	test_eval_gpu(ed, &p);
	edits_gl_release(ed);
	test_road_centreline(ed);
	edits_gl_release(ed);
	test_world_edits(ed);
	free(items);
	edits_destroy(ed);
	platform_close(plat);
	char cmd[300];
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		fprintf(stderr, "warning: could not remove %s\n", tmpdir);
	return tc_done("curves");
}
