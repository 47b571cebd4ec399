// isoterra — 3D quadratic Bézier curves (roads, rivers, railways) looked up
// through a uniform 2D spatial hash, after Nascimento (2020) ch. 6-7.
// Mirrored term by term in app/edit/carve_ref.c; change both together.
//
// Resources (app/edit/curves_gl.c; built on the CPU by app/edit/curves.c):
// one storage block, BIND_CURVES, of four sections (starts in uvec4 units:
// u_curve_sect), so that a pass that carves takes one of the boards' eight:
//   pivot  per hash cell (start, count) into the index section, two a uvec4
//   index  per cell entry the first control point of a quadratic, four a
//          uvec4; from u_curve_all_offset on, every quadratic once (the
//          no-hash baseline of the benchmark)
//   ctrl   control points (x, y, z, inclination tan α); quadratic f is
//          curve_ctrl(f), (f+1), (f+2)
//   prm    curve_prm(f) = (w/2, λ, kind, surface)
//
//   vec4 curve_eval(vec2 xz);   // (height, Θ of the closest curve, |d| closest, Σ Θ)
//                               // of the surface curves (every kind but tunnel and bridge)
//   vec2 tunnel_eval(vec3 ws);  // (fill, tube) of the tunnel and bridge curves

// HAS_CURVES 0 (carve.glsl): nothing here is compiled, and the pass takes
// no storage block for curves it would never read.
#ifndef HAS_CURVES
#define HAS_CURVES 1
#endif
#if HAS_CURVES
layout(std430, binding = BIND_CURVES) restrict readonly buffer Curves { uvec4 curve_v[]; };
uniform ivec4 u_curve_sect; // section starts: pivot, index, ctrl, prm
ivec2 curve_pivot(int i)
{
	uvec4 v = curve_v[u_curve_sect.x + (i >> 1)];
	return ivec2((i & 1) == 0 ? v.xy : v.zw);
}
int curve_index(int i)
{
	return int(curve_v[u_curve_sect.y + (i >> 2)][i & 3]);
}
vec4 curve_ctrl(int f)
{
	return uintBitsToFloat(curve_v[u_curve_sect.z + f]);
}
vec4 curve_prm(int f)
{
	return uintBitsToFloat(curve_v[u_curve_sect.w + f]);
}

uniform int u_curve_count;        // quadratics; 0 = no curves (nothing is read)
uniform int u_curve_all_offset;   // start of the all-curves list in curve_index
uniform ivec2 u_curve_hash_dim;   // cells in x, z
uniform vec2 u_curve_hash_origin; // x, z of the grid's corner
uniform vec2 u_curve_hash_size;   // extent in x, z
uniform vec2 u_curve_hash_cell;   // cell size in x, z

// CURVE_KIND_TUNNEL: abi.h, enum curve_kind's CURVE_TUNNEL (a _Static_assert in app/edit/curves.h)

#ifndef CURVE_SEGMENTS
#define CURVE_SEGMENTS 32
#endif

float curve_cross(vec2 a, vec2 b)
{
	return a.x * b.y - a.y * b.x;
}

float curve_smooth(float lo, float hi, float x) // smoothstep, also for lo == hi
{
	float t = clamp((x - lo) / max(hi - lo, 1e-6), 0.0, 1.0);
	return t * t * (3.0 - 2.0 * t);
}

// Parameter t in [0,1] of the point of the XZ quadratic p0 p1 p2 closest to
// pos.  With A = p1-p0, B = p0-2p1+p2, D = p0-pos the squared distance is
// |D + 2At + Bt²|², its derivative / 4 the cubic
//   (B·B) t³ + 3(A·B) t² + (2A·A + D·B) t + D·A
// (the thesis's Eq. 7.8 corrected), solved in closed form after Quilez
// (Cardano for one real root, the trigonometric form for three) when the
// curve bends (B·B > 0.01 A·A); a nearly straight curve starts from the
// projection onto its start tangent instead (the cubic is ill-conditioned
// there).  Each root gets Newton steps on the cubic, is clamped to [0,1],
// and the endpoints are candidates too: the nearest candidate wins.
float quad_closest_t(vec2 p0, vec2 p1, vec2 p2, vec2 pos)
{
	vec2 A = p1 - p0;
	vec2 B = p0 - 2.0 * p1 + p2;
	vec2 D = p0 - pos;
	float aa = dot(A, A), bb = dot(B, B), ab = dot(A, B);
	float c1 = 2.0 * aa + dot(D, B), c0 = dot(D, A);
	vec3 t;
	int steps;
	if (bb > 0.01 * aa) {
		float kk = 1.0 / bb;
		float kx = kk * ab;
		float ky = kk * c1 * (1.0 / 3.0);
		float kz = kk * c0;
		float p = ky - kx * kx;
		float q = kx * (2.0 * kx * kx - 3.0 * ky) + kz;
		float h = q * q + 4.0 * p * p * p;
		if (h >= 0.0) {
			h = sqrt(h);
			vec2 x = (vec2(h, -h) - q) * 0.5;
			vec2 uv = sign(x) * pow(abs(x), vec2(1.0 / 3.0));
			t = vec3(uv.x + uv.y - kx);
		} else {
			float z = sqrt(-p);
			float v = acos(clamp(q / (p * z * 2.0), -1.0, 1.0)) * (1.0 / 3.0);
			float m = cos(v);
			float n = sin(v) * 1.7320508;
			t = vec3(m + m, -n - m, n - m) * z - kx;
		}
		steps = 1;
	} else {
		t = vec3(aa > 0.0 ? -c0 / (2.0 * aa) : 0.0);
		steps = 3;
	}
	t = clamp(t, 0.0, 1.0);
	for (int i = 0; i < steps; i++) {
		vec3 f = ((bb * t + 3.0 * ab) * t + c1) * t + c0;
		vec3 df = (3.0 * bb * t + 6.0 * ab) * t + c1;
		vec3 nt = t - f / df;
		t = clamp(mix(t, nt, greaterThan(df, vec3(1e-30))), 0.0, 1.0);
	}
	float best = 0.0;
	vec2 e = D;
	float bd = dot(e, e);
	e = D + 2.0 * A + B;
	float dd = dot(e, e);
	if (dd < bd) { bd = dd; best = 1.0; }
	for (int i = 0; i < 3; i++) {
		float ti = t[i];
		e = D + (2.0 * A + B * ti) * ti;
		dd = dot(e, e);
		if (dd < bd) { bd = dd; best = ti; }
	}
	return best;
}

// Closest point of quadratic f to pos: (signed XZ distance, t, height,
// inclination); the sign is + on the left of the direction of travel.
vec4 curve_closest(int f, vec2 pos)
{
	vec4 c0 = curve_ctrl(f), c1 = curve_ctrl(f + 1), c2 = curve_ctrl(f + 2);
	float t = quad_closest_t(c0.xz, c1.xz, c2.xz, pos);
	float u = 1.0 - t;
	float w0 = u * u, w1 = 2.0 * u * t, w2 = t * t;
	vec2 A = c1.xz - c0.xz, B = c0.xz - 2.0 * c1.xz + c2.xz;
	vec2 off = pos - (c0.xz + (2.0 * A + B * t) * t);
	vec2 tang = A + B * t;
	float d = sqrt(dot(off, off));
	float side = curve_cross(tang, off) >= 0.0 ? 1.0 : -1.0;
	return vec4(side * d, t, w0 * c0.y + w1 * c1.y + w2 * c2.y, w0 * c0.w + w1 * c1.w + w2 * c2.w);
}

#ifdef CURVE_ITERATIVE
// The benchmark's baseline: the curve as CURVE_SEGMENTS line segments, the
// point projected onto each (no closed form).
vec4 curve_closest_iter(int f, vec2 pos)
{
	vec4 c0 = curve_ctrl(f), c1 = curve_ctrl(f + 1), c2 = curve_ctrl(f + 2);
	float best = 1e30, bt = 0.0;
	vec2 bo = vec2(0.0), btan = vec2(1.0, 0.0);
	vec2 a = c0.xz;
	for (int s = 1; s <= CURVE_SEGMENTS; s++) {
		float t1 = float(s) / float(CURVE_SEGMENTS);
		float u = 1.0 - t1;
		vec2 b = u * u * c0.xz + 2.0 * u * t1 * c1.xz + t1 * t1 * c2.xz;
		vec2 ab = b - a, ap = pos - a;
		float l = max(dot(ab, ab), 1e-30);
		float k = clamp(dot(ap, ab) / l, 0.0, 1.0);
		vec2 off = ap - ab * k;
		float dd = dot(off, off);
		if (dd < best) {
			best = dd;
			bt = (float(s - 1) + k) / float(CURVE_SEGMENTS);
			bo = off;
			btan = ab;
		}
		a = b;
	}
	float u = 1.0 - bt;
	float w0 = u * u, w1 = 2.0 * u * bt, w2 = bt * bt;
	float side = curve_cross(btan, bo) >= 0.0 ? 1.0 : -1.0;
	return vec4(side * sqrt(best), bt, w0 * c0.y + w1 * c1.y + w2 * c2.y, w0 * c0.w + w1 * c1.w + w2 * c2.w);
}
#define CURVE_CLOSEST curve_closest_iter
#else
#define CURVE_CLOSEST curve_closest
#endif

// Profile (§7.3): Θ = 1 within w/2 of the centre line, falling to 0 at
// w/2 + λ.  Eq. 7.11 with its sign typo corrected, Ψ = (d - (w/2 + λ)) / -λ,
// through Perlin's quintic Θ = 6Ψ⁵ - 15Ψ⁴ + 10Ψ³ (Eq. 7.12).
float curve_theta(float d, float hw, float lam)
{
	float psi = clamp((hw + lam - d) / max(lam, 1e-3), 0.0, 1.0);
	return psi * psi * psi * (psi * (psi * 6.0 - 15.0) + 10.0);
}

// The curves entries [start, start+count) of curve_index at pos (§7.4):
// heights averaged with weights Θ_i, blended toward the closest curve's
// height by smoothstep(blend_lo, blend_hi, Θ_closest), then the closest
// curve's lateral inclination: h -= I |d| / sqrt(I² + 1) · s^exp · side with
// s = smoothstep(incl_lo, incl_hi, Θ_closest).
float curve_seg_d2(vec2 p, vec2 a, vec2 b)
{
	vec2 ab = b - a, ap = p - a;
	float t = clamp(dot(ap, ab) / max(dot(ab, ab), 1e-20), 0.0, 1.0);
	vec2 d = ap - ab * t;
	return dot(d, d);
}

// Broad phase: a quadratic lies in its control triangle, so it cannot reach
// pos when pos is outside the triangle's box padded by the reach, or
// outside the triangle and farther than the reach (+ a relative margin, so
// rounding never drops a curve with Θ > 0) from its edges.
bool curve_near(int f, vec2 pos)
{
	vec4 prm = curve_prm(f);
	vec2 q0 = curve_ctrl(f).xz, q1 = curve_ctrl(f + 1).xz, q2 = curve_ctrl(f + 2).xz;
	float reach = prm.x + prm.y;
	vec2 lo = min(min(q0, q1), q2) - reach, hi = max(max(q0, q1), q2) + reach;
	if (pos.x < lo.x || pos.y < lo.y || pos.x > hi.x || pos.y > hi.y)
		return false;
	float e0 = curve_cross(q1 - q0, pos - q0), e1 = curve_cross(q2 - q1, pos - q1), e2 = curve_cross(q0 - q2, pos - q2);
	if ((e0 >= 0.0 && e1 >= 0.0 && e2 >= 0.0) || (e0 <= 0.0 && e1 <= 0.0 && e2 <= 0.0))
		return true;
	float r = reach * 1.001 + 1e-3;
	return min(min(curve_seg_d2(pos, q0, q1), curve_seg_d2(pos, q1, q2)), curve_seg_d2(pos, q2, q0)) <= r * r;
}

vec4 curve_accumulate(vec2 pos, int start, int count)
{
	float sh = 0.0, sw = 0.0;
	float bd = 1e30, bh = 0.0, bi = 0.0, bth = 0.0, bside = 1.0;
	// A curve that cannot reach pos (curve_near) has no influence (and is
	// never nearer than one that has): skip it.  The box tests run in an inner loop so
	// that each invocation only reaches the closed form for its candidates
	// (SIMD lanes and GPU threads then do max(candidates) solves, not
	// count).
	int end = start + count;
	int i = start;
	for (;;) {
		while (i < end && !curve_near(curve_index(i), pos))
			i++;
		if (i >= end)
			break;
		int f = curve_index(i);
		i++;
		vec4 prm = curve_prm(f);
		if (prm.z >= float(CURVE_KIND_TUNNEL)) // tunnel, bridge: not a surface (tunnel_eval)
			continue;
		vec4 cl = CURVE_CLOSEST(f, pos);
		float ad = abs(cl.x);
		float th = curve_theta(ad, prm.x, prm.y);
		sh += cl.z * th;
		sw += th;
		if (ad < bd) {
			bd = ad;
			bh = cl.z;
			bi = cl.w;
			bth = th;
			bside = cl.x >= 0.0 ? 1.0 : -1.0;
		}
	}
	float avg = sw > 0.0 ? sh / sw : bh;
	float h = mix(avg, bh, curve_smooth(u_curve_blend_lo, u_curve_blend_hi, bth));
	float s = curve_smooth(u_curve_incl_lo, u_curve_incl_hi, bth);
	float sp = s > 0.0 ? pow(s, u_curve_incl_exp) : 0.0;
	h -= bi * bd / sqrt(bi * bi + 1.0) * sp * bside;
	return vec4(h, bth, bd, sw);
}

// The hash cell's list at pos: (start, count) into curve_index, (0, 0)
// outside the hash's rectangle or with no curves.
ivec2 curve_cell(vec2 pos)
{
	vec2 l = pos - u_curve_hash_origin;
	if (u_curve_count == 0 || !(l.x >= 0.0 && l.y >= 0.0 && l.x < u_curve_hash_size.x && l.y < u_curve_hash_size.y))
		return ivec2(0);
	ivec2 c = min(ivec2(floor(l / u_curve_hash_cell)), u_curve_hash_dim - 1);
	return curve_pivot(c.x + c.y * u_curve_hash_dim.x);
}

vec4 curve_eval(vec2 pos)
{
	vec4 none = vec4(0.0, 0.0, 1e30, 0.0);
	if (u_curve_count == 0)
		return none;
#ifdef CURVE_ITERATIVE
	return curve_accumulate(pos, u_curve_all_offset, u_curve_count);
#else
	ivec2 piv = curve_cell(pos);
	if (piv.y == 0)
		return none;
	return curve_accumulate(pos, piv.x, piv.y);
#endif
}

// Tunnels: a tube of radius r = w/2 whose flat floor lies on the curve
// (height h), its axis r/2 above the floor, carved through the rock while
// the rock above stays; where the curve runs above the ground an
// embankment carries the floor (rock under it widening at 45 degrees for
// λ, then straight down).  Over the tunnel curves in reach of ws:
//   tube = min over curves of max(|(lateral, y - h - r/2)| - r, h - y)  (< 0: the tube's air)
//   fill = max over curves of min(h - y, r + min(h - y, λ) - lateral)   (> 0: the embankment)
// A bridge is a deck of its width w and thickness λ whose top is the curve,
// added to the rock (the ground under it stays):
//   fill = max(fill, min(min(h - y, λ - (h - y)), w/2 - lateral))
vec2 tunnel_accumulate(vec3 ws, int start, int count)
{
	vec2 r = vec2(-1e30, 1e30);
	for (int i = start; i < start + count; i++) {
		int f = curve_index(i);
		vec4 prm = curve_prm(f);
		if (prm.z < float(CURVE_KIND_TUNNEL) || !curve_near(f, ws.xz))
			continue;
		vec4 cl = CURVE_CLOSEST(f, ws.xz);
		float ad = abs(cl.x), below = cl.z - ws.y;
		if (prm.z == float(CURVE_KIND_BRIDGE)) {
			r.x = max(r.x, min(min(below, prm.y - below), prm.x - ad));
			continue;
		}
		float dy = ws.y - (cl.z + 0.5 * prm.x);
		r.x = max(r.x, min(below, prm.x + min(below, prm.y) - ad));
		r.y = min(r.y, max(sqrt(ad * ad + dy * dy) - prm.x, below));
	}
	return r;
}

vec2 tunnel_eval(vec3 ws)
{
	vec2 none = vec2(-1e30, 1e30);
	if (u_curve_count == 0)
		return none;
#ifdef CURVE_ITERATIVE
	return tunnel_accumulate(ws, u_curve_all_offset, u_curve_count);
#else
	ivec2 piv = curve_cell(ws.xz);
	return tunnel_accumulate(ws, piv.x, piv.y);
#endif
}
#endif // HAS_CURVES
