/* isoterra — test_curves (test_curves.c), on the CPU: the curve pipeline,
 * the closed-form closest point against brute force, the spatial hash,
 * the affected-region API, the tunnel's carve. */
#include "curves_test.h"
#include "world.h"
#include "terrain.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

/* Random and near-degenerate quadratics + query points.  item: 16 floats
 * (p0, p1, p2 as x y z I; pos x z). */
int make_closest_cases(float *items, int max)
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

void test_closest_cpu(const float *items, int n, double *worst)
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

void test_pipeline_cpu(void)
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
	struct curve_set s = { .paths = &p, .npaths = 1 };
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
		struct curve_set cs = { .paths = &cp, .npaths = 1 };
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
	struct curve_set ls = { .paths = &lp, .npaths = 1 };
	CHECK(curves_build(&ls, &q, err, sizeof(err)) == 0, "straight: %s", err);
	bad = 0;
	for (int i = 0; i < q.nctrl; i++)
		bad += q.ctrl[i][2] != 0.0f || q.ctrl[i][3] != 0.0f || !isfinite(q.ctrl[i][0]);
	CHECK(bad == 0, "straight road: every control point on the line, no inclination");
	curve_quads_free(&q);
	/* a path that turns back on itself */
	float back[3 * 3] = { 0, 0, 0, 10, 0, 0, 0, 0, 0.0f };
	struct curve_path bp = make_path(3, back, 4, 4, 1.0f, 0.5f);
	struct curve_set bs = { .paths = &bp, .npaths = 1 };
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
	struct curve_set os = { .paths = &op, .npaths = 1 };
	CHECK(curves_build(&os, &q, err, sizeof(err)) < 0 && strstr(err, "two distinct"), "one point rejected: %s", err);
}

void test_hash_cpu(void)
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
void test_hash_vs_brute_eval(struct edits *ed)
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

void test_affected(struct edits *ed)
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
	struct curve_set two = { .paths = s0.paths, .npaths = 2 };
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

/* A tunnel carves a tube and leaves the rock above it; the same curve as a
 * road removes everything above it.  Flat ground at y = 0 (no noise), the
 * curve straight along x at height h, radius r = w/2 (axis at h + r/2). */
void test_tunnel_cpu(struct edits *ed)
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
	struct curve_set cs = { .paths = &cp, .npaths = 1 };
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
	/* a bridge 3 above the ground: a deck w wide and λ thick whose top is
	 * the curve, the air under it and the ground below untouched */
	cp.kind = CURVE_BRIDGE;
	CHECK(edits_set_curves(ed, &cs, 8, err, sizeof(err)) == 0, "bridge: %s", err);
	CHECK(edits_has_tunnels(ed), "a bridge takes the second walk too");
	int bad_deck = 0, bad_under = 0, bad_above = 0, bad_ground = 0, bad_beside = 0;
	n = 0;
	for (float x = -12.0f; x <= 12.0f; x += 0.75f, n++) {
		for (float z = -0.9f * r; z <= 0.9f * r; z += 0.45f * r)
			bad_deck += !(density_ref(&p, &ns, ed, x, 3.0f - 0.5f * lam, z) > 0.0f);
		bad_under += !(density_ref(&p, &ns, ed, x, 3.0f - lam - 0.3f, 0.0f) < 0.0f);
		bad_above += !(density_ref(&p, &ns, ed, x, 3.3f, 0.0f) < 0.0f);
		bad_ground += density_ref(&p, &ns, ed, x, -0.5f, 0.0f) != density_ref(&p, &ns, NULL, x, -0.5f, 0.0f);
		bad_beside += !(density_ref(&p, &ns, ed, x, 3.0f - 0.5f * lam, r + 0.3f) < 0.0f);
	}
	CHECK(bad_deck == 0, "bridge: %d of %d points inside the deck are not rock", bad_deck, 5 * n);
	CHECK(bad_under == 0, "bridge: %d of %d points under the deck are not air", bad_under, n);
	CHECK(bad_above == 0, "bridge: %d of %d points above the deck are not air", bad_above, n);
	CHECK(bad_ground == 0, "bridge: the ground under it changed at %d of %d points", bad_ground, n);
	CHECK(bad_beside == 0, "bridge: %d of %d points beside the deck are not air", bad_beside, n);
	edits_clear(ed);
}
