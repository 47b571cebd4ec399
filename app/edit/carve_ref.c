/* isoterra — CPU mirror of shaders/curves.glsl, heightmap.glsl and
 * carve.glsl, term by term in plain C float.  Differences to the GPU come
 * from libm vs GLSL pow/acos/cos/sqrt and FMA contraction only. */
#include "edits.h"

#include <math.h>
#include <string.h>

#define CURVE_SEGMENTS 32

static float clampf(float x, float lo, float hi)
{
	return x < lo ? lo : (x > hi ? hi : x);
}

static float signf(float x)
{
	return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f);
}

static float cross2(float ax, float ay, float bx, float by)
{
	return ax * by - ay * bx;
}

static float curve_smooth(float lo, float hi, float x)
{
	float t = clampf((x - lo) / fmaxf(hi - lo, 1e-6f), 0.0f, 1.0f);
	return t * t * (3.0f - 2.0f * t);
}

float carve_ref_closest_t(const float p0[2], const float p1[2], const float p2[2], const float pos[2])
{
	float A[2] = { p1[0] - p0[0], p1[1] - p0[1] };
	float B[2] = { p0[0] - 2.0f * p1[0] + p2[0], p0[1] - 2.0f * p1[1] + p2[1] };
	float D[2] = { p0[0] - pos[0], p0[1] - pos[1] };
	float aa = A[0] * A[0] + A[1] * A[1], bb = B[0] * B[0] + B[1] * B[1], ab = A[0] * B[0] + A[1] * B[1];
	float c1 = 2.0f * aa + (D[0] * B[0] + D[1] * B[1]), c0 = D[0] * A[0] + D[1] * A[1];
	float t[3];
	int steps;
	if (bb > 0.01f * aa) {
		float kk = 1.0f / bb;
		float kx = kk * ab;
		float ky = kk * c1 * (1.0f / 3.0f);
		float kz = kk * c0;
		float p = ky - kx * kx;
		float q = kx * (2.0f * kx * kx - 3.0f * ky) + kz;
		float h = q * q + 4.0f * p * p * p;
		if (h >= 0.0f) {
			h = sqrtf(h);
			float x0 = (h - q) * 0.5f, x1 = (-h - q) * 0.5f;
			float u0 = signf(x0) * powf(fabsf(x0), 1.0f / 3.0f), u1 = signf(x1) * powf(fabsf(x1), 1.0f / 3.0f);
			t[0] = t[1] = t[2] = u0 + u1 - kx;
		} else {
			float z = sqrtf(-p);
			float v = acosf(clampf(q / (p * z * 2.0f), -1.0f, 1.0f)) * (1.0f / 3.0f);
			float m = cosf(v);
			float n = sinf(v) * 1.7320508f;
			t[0] = (m + m) * z - kx;
			t[1] = (-n - m) * z - kx;
			t[2] = (n - m) * z - kx;
		}
		steps = 1;
	} else {
		t[0] = t[1] = t[2] = aa > 0.0f ? -c0 / (2.0f * aa) : 0.0f;
		steps = 3;
	}
	for (int i = 0; i < 3; i++)
		t[i] = clampf(t[i], 0.0f, 1.0f);
	for (int s = 0; s < steps; s++)
		for (int i = 0; i < 3; i++) {
			float f = ((bb * t[i] + 3.0f * ab) * t[i] + c1) * t[i] + c0;
			float df = (3.0f * bb * t[i] + 6.0f * ab) * t[i] + c1;
			float nt = t[i] - f / df;
			t[i] = clampf(df > 1e-30f ? nt : t[i], 0.0f, 1.0f);
		}
	float best = 0.0f;
	float ex = D[0], ey = D[1];
	float bd = ex * ex + ey * ey;
	ex = D[0] + 2.0f * A[0] + B[0];
	ey = D[1] + 2.0f * A[1] + B[1];
	float dd = ex * ex + ey * ey;
	if (dd < bd) {
		bd = dd;
		best = 1.0f;
	}
	for (int i = 0; i < 3; i++) {
		float ti = t[i];
		ex = D[0] + (2.0f * A[0] + B[0] * ti) * ti;
		ey = D[1] + (2.0f * A[1] + B[1] * ti) * ti;
		dd = ex * ex + ey * ey;
		if (dd < bd) {
			bd = dd;
			best = ti;
		}
	}
	return best;
}

void carve_ref_closest(const float c[3][4], const float pos[2], float out[4])
{
	float p0[2] = { c[0][0], c[0][2] }, p1[2] = { c[1][0], c[1][2] }, p2[2] = { c[2][0], c[2][2] };
	float t = carve_ref_closest_t(p0, p1, p2, pos);
	float u = 1.0f - t;
	float w0 = u * u, w1 = 2.0f * u * t, w2 = t * t;
	float A[2] = { p1[0] - p0[0], p1[1] - p0[1] };
	float B[2] = { p0[0] - 2.0f * p1[0] + p2[0], p0[1] - 2.0f * p1[1] + p2[1] };
	float ox = pos[0] - (p0[0] + (2.0f * A[0] + B[0] * t) * t);
	float oy = pos[1] - (p0[1] + (2.0f * A[1] + B[1] * t) * t);
	float tx = A[0] + B[0] * t, ty = A[1] + B[1] * t;
	float d = sqrtf(ox * ox + oy * oy);
	float side = cross2(tx, ty, ox, oy) >= 0.0f ? 1.0f : -1.0f;
	out[0] = side * d;
	out[1] = t;
	out[2] = w0 * c[0][1] + w1 * c[1][1] + w2 * c[2][1];
	out[3] = w0 * c[0][3] + w1 * c[1][3] + w2 * c[2][3];
}

static void closest_iter(const float c[3][4], const float pos[2], float out[4])
{
	float best = 1e30f, bt = 0.0f;
	float bo[2] = { 0.0f, 0.0f }, btan[2] = { 1.0f, 0.0f };
	float a[2] = { c[0][0], c[0][2] };
	for (int s = 1; s <= CURVE_SEGMENTS; s++) {
		float t1 = (float)s / (float)CURVE_SEGMENTS;
		float u = 1.0f - t1;
		float b[2] = { u * u * c[0][0] + 2.0f * u * t1 * c[1][0] + t1 * t1 * c[2][0],
			       u * u * c[0][2] + 2.0f * u * t1 * c[1][2] + t1 * t1 * c[2][2] };
		float ab[2] = { b[0] - a[0], b[1] - a[1] }, ap[2] = { pos[0] - a[0], pos[1] - a[1] };
		float l = fmaxf(ab[0] * ab[0] + ab[1] * ab[1], 1e-30f);
		float k = clampf((ap[0] * ab[0] + ap[1] * ab[1]) / l, 0.0f, 1.0f);
		float off[2] = { ap[0] - ab[0] * k, ap[1] - ab[1] * k };
		float dd = off[0] * off[0] + off[1] * off[1];
		if (dd < best) {
			best = dd;
			bt = ((float)(s - 1) + k) / (float)CURVE_SEGMENTS;
			memcpy(bo, off, sizeof(bo));
			memcpy(btan, ab, sizeof(btan));
		}
		memcpy(a, b, sizeof(a));
	}
	float u = 1.0f - bt;
	float w0 = u * u, w1 = 2.0f * u * bt, w2 = bt * bt;
	float side = cross2(btan[0], btan[1], bo[0], bo[1]) >= 0.0f ? 1.0f : -1.0f;
	out[0] = side * sqrtf(best);
	out[1] = bt;
	out[2] = w0 * c[0][1] + w1 * c[1][1] + w2 * c[2][1];
	out[3] = w0 * c[0][3] + w1 * c[1][3] + w2 * c[2][3];
}

float carve_ref_theta(float d, float hw, float lam)
{
	float psi = clampf((hw + lam - d) / fmaxf(lam, 1e-3f), 0.0f, 1.0f);
	return psi * psi * psi * (psi * (psi * 6.0f - 15.0f) + 10.0f);
}

static float seg_d2(const float p[2], const float a[2], const float b[2])
{
	float ab[2] = { b[0] - a[0], b[1] - a[1] }, ap[2] = { p[0] - a[0], p[1] - a[1] };
	float t = clampf((ap[0] * ab[0] + ap[1] * ab[1]) / fmaxf(ab[0] * ab[0] + ab[1] * ab[1], 1e-20f), 0.0f, 1.0f);
	float dx = ap[0] - ab[0] * t, dz = ap[1] - ab[1] * t;
	return dx * dx + dz * dz;
}

/* curves.glsl curve_near: quadratic f can reach pos (its control points in c) */
static bool near(const float c[3][4], const float *prm, const float pos[2])
{
	float reach = prm[0] + prm[1];
	float lox = fminf(fminf(c[0][0], c[1][0]), c[2][0]) - reach, loz = fminf(fminf(c[0][2], c[1][2]), c[2][2]) - reach;
	float hix = fmaxf(fmaxf(c[0][0], c[1][0]), c[2][0]) + reach, hiz = fmaxf(fmaxf(c[0][2], c[1][2]), c[2][2]) + reach;
	if (pos[0] < lox || pos[1] < loz || pos[0] > hix || pos[1] > hiz)
		return false;
	/* outside the control triangle and beyond the reach of its edges */
	float q[3][2] = { { c[0][0], c[0][2] }, { c[1][0], c[1][2] }, { c[2][0], c[2][2] } };
	float e0 = cross2(q[1][0] - q[0][0], q[1][1] - q[0][1], pos[0] - q[0][0], pos[1] - q[0][1]);
	float e1 = cross2(q[2][0] - q[1][0], q[2][1] - q[1][1], pos[0] - q[1][0], pos[1] - q[1][1]);
	float e2 = cross2(q[0][0] - q[2][0], q[0][1] - q[2][1], pos[0] - q[2][0], pos[1] - q[2][1]);
	bool inside = (e0 >= 0.0f && e1 >= 0.0f && e2 >= 0.0f) || (e0 <= 0.0f && e1 <= 0.0f && e2 <= 0.0f);
	if (inside)
		return true;
	float r = reach * 1.001f + 1e-3f;
	float d2 = fminf(fminf(seg_d2(pos, q[0], q[1]), seg_d2(pos, q[1], q[2])), seg_d2(pos, q[2], q[0]));
	return d2 <= r * r;
}

static void accumulate(const struct edits *e, const struct params *p, const float pos[2], const int32_t *list,
		       int count, bool iterative, float out[4])
{
	float sh = 0.0f, sw = 0.0f;
	float bd = 1e30f, bh = 0.0f, bi = 0.0f, bth = 0.0f, bside = 1.0f;
	for (int i = 0; i < count; i++) {
		int f = list[i];
		float c[3][4], cl[4];
		for (int k = 0; k < 3; k++)
			memcpy(c[k], e->quads.ctrl[f + k], sizeof(float) * 4);
		const float *prm = e->quads.prm[f];
		if (!near(c, prm, pos) || prm[2] >= (float)CURVE_TUNNEL) /* tunnels, bridges: tunnel_ref */
			continue;
		if (iterative)
			closest_iter(c, pos, cl);
		else
			carve_ref_closest(c, pos, cl);
		float ad = fabsf(cl[0]);
		float th = carve_ref_theta(ad, prm[0], prm[1]);
		sh += cl[2] * th;
		sw += th;
		if (ad < bd) {
			bd = ad;
			bh = cl[2];
			bi = cl[3];
			bth = th;
			bside = cl[0] >= 0.0f ? 1.0f : -1.0f;
		}
	}
	float avg = sw > 0.0f ? sh / sw : bh;
	float beta = curve_smooth(p->curve_blend_lo, p->curve_blend_hi, bth);
	float h = avg + (bh - avg) * beta;
	float s = curve_smooth(p->curve_incl_lo, p->curve_incl_hi, bth);
	float sp = s > 0.0f ? powf(s, p->curve_incl_exp) : 0.0f;
	h -= bi * bd / sqrtf(bi * bi + 1.0f) * sp * bside;
	out[0] = h;
	out[1] = bth;
	out[2] = bd;
	out[3] = sw;
}

void carve_ref_eval(const struct edits *e, const struct params *p, float x, float z, bool iterative, float out[4])
{
	out[0] = 0.0f;
	out[1] = 0.0f;
	out[2] = 1e30f;
	out[3] = 0.0f;
	const struct curve_hash *h = &e->hash;
	if (e->quads.nquads == 0 || !h->pivot)
		return;
	float pos[2] = { x, z };
	if (iterative) {
		accumulate(e, p, pos, h->index + h->all_offset, h->nall, true, out);
		return;
	}
	int c = curve_hash_cell(h, x, z);
	if (c < 0 || h->pivot[2 * c + 1] == 0)
		return;
	accumulate(e, p, pos, h->index + h->pivot[2 * c], h->pivot[2 * c + 1], false, out);
}

/* curves.glsl tunnel_eval: (fill, tube) of the tunnel and bridge curves at (x, y, z) */
static void tunnel_ref(const struct edits *e, float x, float y, float z, float out[2])
{
	out[0] = -1e30f;
	out[1] = 1e30f;
	const struct curve_hash *h = &e->hash;
	int cell = curve_hash_cell(h, x, z);
	if (cell < 0)
		return;
	const int32_t *list = h->index + h->pivot[2 * cell];
	const float pos[2] = { x, z };
	for (int i = 0; i < h->pivot[2 * cell + 1]; i++) {
		int f = list[i];
		float c[3][4], cl[4];
		for (int k = 0; k < 3; k++)
			memcpy(c[k], e->quads.ctrl[f + k], sizeof(float) * 4);
		const float *prm = e->quads.prm[f];
		if (prm[2] < (float)CURVE_TUNNEL || !near(c, prm, pos))
			continue;
		carve_ref_closest(c, pos, cl);
		float ad = fabsf(cl[0]), below = cl[2] - y;
		if (prm[2] == (float)CURVE_BRIDGE) { /* a deck: w wide, λ thick, its top the curve */
			out[0] = fmaxf(out[0], fminf(fminf(below, prm[1] - below), prm[0] - ad));
			continue;
		}
		float dy = y - (cl[2] + 0.5f * prm[0]);
		out[0] = fmaxf(out[0], fminf(below, prm[0] + fminf(below, prm[1]) - ad));
		out[1] = fminf(out[1], fmaxf(sqrtf(ad * ad + dy * dy) - prm[0], below));
	}
}

float carve_ref_density(const struct edits *e, const struct params *p, float x, float y, float z, float d)
{
	if (e->quads.nquads == 0 || !e->hash.pivot)
		return d;
	float ev[4], tn[2];
	carve_ref_eval(e, p, x, z, false, ev);
	float k = ev[1] * p->curve_strength;
	d += k * ((ev[0] - y) - d);
	tunnel_ref(e, x, y, z, tn);
	return d + p->curve_strength * (fminf(fmaxf(d, tn[0]), tn[1]) - d);
}

/* ---- heightmap.glsl ------------------------------------------------------------ */

static float hm_texel(const struct heightmap *hm, int x, int z)
{
	x = x < 0 ? 0 : (x > hm->w - 1 ? hm->w - 1 : x);
	z = z < 0 ? 0 : (z > hm->h - 1 ? hm->h - 1 : z);
	return hm->v[(size_t)z * (size_t)hm->w + (size_t)x];
}

float heightmap_ref_base(const struct edits *e, const struct params *p, float x, float z)
{
	const struct heightmap *hm = &e->hm;
	if (!hm->w)
		return 0.0f;
	float gx = x / p->heightmap_scale + 0.5f * (float)(hm->w - 1);
	float gz = z / p->heightmap_scale + 0.5f * (float)(hm->h - 1);
	float g0x = floorf(gx), g0z = floorf(gz);
	float fx = gx - g0x, fz = gz - g0z;
	int cx = (int)g0x, cz = (int)g0z;
	float h00 = hm_texel(hm, cx, cz), h10 = hm_texel(hm, cx + 1, cz);
	float h01 = hm_texel(hm, cx, cz + 1), h11 = hm_texel(hm, cx + 1, cz + 1);
	float a = h00 + (h10 - h00) * fx;
	float b = h01 + (h11 - h01) * fx;
	float v = a + (b - a) * fz;
	return p->heightmap_base + v * (p->heightmap_height * (1.0f / 65535.0f));
}

void carve_ref_bake(const struct edits *e, const struct params *p, const struct bake_opts *o, float *out)
{
	float tx = o->size[0] / (float)o->res[0], tz = o->size[1] / (float)o->res[1];
	for (int j = 0; j < o->res[1]; j++)
		for (int i = 0; i < o->res[0]; i++) {
			float x = o->origin[0] + ((float)i + 0.5f) * tx;
			float z = o->origin[1] + ((float)j + 0.5f) * tz;
			float ev[4];
			carve_ref_eval(e, p, x, z, o->iterative, ev);
			float base = e->hm.w ? heightmap_ref_base(e, p, x, z) : 0.0f;
			out[(size_t)j * (size_t)o->res[0] + (size_t)i] = ev[1] * (ev[0] - base);
		}
}
