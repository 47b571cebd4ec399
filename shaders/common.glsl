// isoterra — grid uniforms and helpers shared by the extraction passes, and
// the engine's side of the field seam (app/extract/field.h): a field's
// program includes this file first and defines  float density(vec3 ws);
// compiled with FIELD_PASS_DENSITY, this file gives it the density pass.

// A field's program: its work group comes first (lin_id() needs it).
#if defined(FIELD_PASS_DENSITY)
layout(local_size_x = WG_SIZE) in; // WG_SIZE sign words of one z slab (see sign bits below)
#elif defined(FIELD_PASS_VERTICES)
layout(local_size_x = WG_SIZE) in; // mc_vertices.comp's
#elif defined(FIELD_PASS_BOUND)
layout(local_size_x = WG_SIZE) in; // block_bound.glsl: one candidate block a group
#endif

uniform ivec3 u_cells;   // cells per axis
uniform vec3 u_origin;   // world position of global corner (0,0,0)
uniform float u_cell;    // world size of a cell
uniform ivec3 u_base;    // global index of this grid's corner (0,0,0)
uniform int u_margin;    // density samples kept around the corners (>= 1)

ivec3 dens_dims() { return u_cells + 1 + 2 * u_margin; }

// 1D invocation index over a (possibly 2D-split) dispatch of WG_SIZE-wide groups.
uint lin_id()
{
	return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x +
	       gl_LocalInvocationID.x;
}

// i / d and i % d for 0 <= i, 0 < d: a float quotient corrected to the
// exact one (a SIMD driver runs integer division lane by lane; the float
// estimate is off by at most one below 2^24, the loops cover the rest)
ivec2 divmod(int i, int d)
{
	int q = int(float(i) / float(d));
	int r = i - q * d;
	while (r < 0) {
		q--;
		r += d;
	}
	while (r >= d) {
		q++;
		r -= d;
	}
	return ivec2(q, r);
}

// The cell of linear index i over a grid of o cells (x fastest)
ivec3 cell_of(int i, ivec3 o)
{
	ivec2 a = divmod(i, o.x), b = divmod(a.x, o.y);
	return ivec3(a.y, b.y, b.x);
}

// Sign bits: one bit per density sample, 1 = inside (d > u_iso), written
// by the density pass beside the densities so classification reads 32
// samples a word.  Slab z holds its dim.x * dim.y samples x fastest, padded
// to a multiple of SIGN_SLAB_ALIGN (64) bits,
// so sample (x, y, z) of the density grid is bit z * sign_slab_bits() +
// x + dim.x * y.
uint sign_slab_bits()
{
	ivec3 d = dens_dims();
	return uint((d.x * d.y + SIGN_SLAB_ALIGN - 1) / SIGN_SLAB_ALIGN * SIGN_SLAB_ALIGN);
}

#ifdef FIELD_PASS_DENSITY
// The density pass: the field at every corner of the grid plus the margin
// (for gradients, and the ambient-occlusion rays of world blocks), and the
// sign bits.  Each invocation computes the 32 samples of one sign word, in
// slab order, and writes the word itself: no shared memory and no barrier
// (a barrier is a switch of every invocation's context on a CPU driver:
// packing the bits through shared memory cost llvmpipe 10 ns a sample, more
// than an octave of noise).  Dispatch: (ceil(words of a slab / WG_SIZE),
// slabs) groups of WG_SIZE.
//
// Far samples (DENSITY_CUT, app/extract/field.h): the field may stop a
// sample's octaves once their sign is settled, and says so in
// g_density_cut; the pass writes those flags as bits beside the signs, and
// the field's tag for the sample (g_density_tag) into the 4 lowest bits of
// its value, where the refine variant finds it (g_refine_tag) to go on
// from where the sample was cut.
// After the last slab, the debris filter marks the samples next to a sign
// change, refine_mark.comp lists the cut samples within one step of those
// (two of a sign change), and the refine variant (DENSITY_REFINE)
// computes them whole: the vertex pass interpolates the two ends of a
// crossing edge and takes central differences around each, all within
// that reach.
float density(vec3 ws); // the field's
#ifdef DENSITY_REFINE // reads what the density pass stored
layout(std430, binding = BIND_DENSITY) restrict buffer DensOut { float dens_out[]; };
#else
layout(std430, binding = BIND_DENSITY) restrict writeonly buffer DensOut { float dens_out[]; };
#endif
uniform float u_density_bias; // subtracted (coarse LOD blocks erode a little)
uniform uint u_sign_words;    // the sign buffer's capacity in words
uniform int u_z0;             // first z slab of this dispatch (a block's density over two frames)
#ifdef DENSITY_CUT
bool g_density_cut;   // set by the field: this sample's finest octaves were left out
int g_density_tag;    // and what it needs to go on from there (0..15), kept in the value's 4 lowest bits
#endif
#ifdef DENSITY_REFINE
float g_refine_stored; // the cut sample's value, as the density pass stored it
int g_refine_tag;      // its tag, or -1: compute the sample from scratch
#endif

// Density grid sample of slab index i (x + dim.x * y): y by a float
// reciprocal corrected once each way (exact while i < 2^23; no integer
// division, which a SIMD driver runs lane by lane).
ivec2 slab_xy(int i, int dx)
{
	int y = int(float(i) * (1.0 / float(dx)));
	int x = i - y * dx;
	if (x < 0) {
		y--;
		x += dx;
	} else if (x >= dx) {
		y++;
		x -= dx;
	}
	return ivec2(x, y);
}

// The value stored for density grid sample id (margin included).
float density_sample(ivec3 id, ivec3 dim)
{
	vec3 ws = u_origin + vec3(u_base + id - u_margin) * u_cell;
	float d = density(ws) - u_density_bias;
	if (u_closed != 0) {
		// air on the border corners (walls where the box cuts rock) and
		// clearly air in the margin (so the walls' gradients point out)
		ivec3 lo = ivec3(u_margin), hi = dim - 1 - u_margin;
		if (any(lessThan(id, lo)) || any(greaterThan(id, hi)))
			d = min(d, u_iso - u_cell);
		else if (any(equal(id, lo)) || any(equal(id, hi)))
			d = min(d, u_iso - 1e-3 * u_cell);
	}
	return d;
}

#ifndef DENSITY_REFINE
layout(std430, binding = BIND_SIGNS_OUT) restrict writeonly buffer SignOut { uint sign_out[]; };
#ifdef DENSITY_CUT
layout(std430, binding = BIND_CUT) restrict writeonly buffer CutOut { uint cut_out[]; };
#endif

void main()
{
	ivec3 dim = dens_dims();
	int n = dim.x * dim.y;
	uint words = sign_slab_bits() / 32u; // a slab's words, padding included
	uint wv = gl_WorkGroupID.x * uint(WG_SIZE) + gl_LocalInvocationID.x;
	if (wv >= words)
		return;
	int z = int(gl_WorkGroupID.y) + u_z0;
	int i0 = int(wv) * 32;
	ivec2 xy = slab_xy(i0, dim.x);
	uint bits = 0u;
#ifdef DENSITY_CUT
	uint cut = 0u;
#endif
	int j = 0;
	do { // tested at the end: no 33rd, masked, sample (see fractal.glsl)
		if (i0 + j < n) {
#ifdef DENSITY_CUT
			g_density_cut = false;
#endif
			float d = density_sample(ivec3(xy, z), dim);
#ifdef DENSITY_CUT
			// the field's tag in the 4 lowest mantissa bits of the value,
			// which is no more than a bound already (a few ulp of it)
			if (g_density_cut)
				d = uintBitsToFloat((floatBitsToUint(d) & ~15u) | uint(g_density_tag));
#endif
			dens_out[i0 + j + n * z] = d;
			bits |= uint(d > u_iso) << uint(j);
#ifdef DENSITY_CUT
			cut |= uint(g_density_cut) << uint(j);
#endif
		}
		if (++xy.x == dim.x) {
			xy.x = 0;
			xy.y++;
		}
	} while (++j < 32);
	uint wi = uint(z) * words + wv;
	if (wi < u_sign_words) {
		sign_out[wi] = bits;
#ifdef DENSITY_CUT
		cut_out[wi] = cut;
#endif
	}
}
#else // DENSITY_REFINE: the listed cut samples near the surface, computed whole
layout(std430, binding = BIND_CUT) restrict readonly buffer CutIn { uint cut_in[]; };
layout(std430, binding = BIND_REFINE) restrict readonly buffer RefineIn { uint rf[]; };
uniform uint u_refine_cap; // sample entries the list holds

// An invocation per entry of the list refine_mark.comp wrote (dispatched
// from its header): first the sample entries, from u_refine_cap on 32 per
// word entry.  Every invocation evaluates the field once, and only for a
// sample that needs it (no loop whose length differs from lane to lane).
void main()
{
	uint S = min(rf[RF_SAMPLES], u_refine_cap), W = rf[RF_WORDS];
	uint T = W > 0u ? u_refine_cap + 32u * W : S; // the entries' invocations
	uint stride = gl_NumWorkGroups.x * gl_NumWorkGroups.y * uint(WG_SIZE);
	ivec3 dim = dens_dims();
	int n = dim.x * dim.y;
	int words = int(sign_slab_bits() / 32u);
	uint k = lin_id();
	do { // more than one round only past the dispatch's largest size
		bool valid;
		uint b;
		if (k < u_refine_cap) {
			valid = k < S;
			b = rf[RF_HEAD + k]; // within the list's entries (k < u_refine_cap)
		} else {
			uint e = (k - u_refine_cap) >> 5u, j = (k - u_refine_cap) & 31u;
			uint w = e < W ? rf[RF_HEAD + u_refine_cap + e] : 0u;
			valid = e < W && ((cut_in[w] >> j) & 1u) != 0u;
			b = w * 32u + j;
		}
		if (valid) {
			ivec2 zw = divmod(int(b >> 5u), words); // slab, word in it
			int i = zw.y * 32 + int(b & 31u);
			ivec3 id = ivec3(slab_xy(i, dim.x), zw.x);
			g_refine_stored = dens_out[i + n * zw.x];
			g_refine_tag = int(floatBitsToUint(g_refine_stored) & 15u);
			// a closed volume's border: the value may be the wall's, not the field's
			if (u_closed != 0 && (any(lessThanEqual(id, ivec3(u_margin))) || any(greaterThanEqual(id, dim - 1 - u_margin))))
				g_refine_tag = -1;
			dens_out[i + n * zw.x] = density_sample(id, dim);
		}
		k += stride;
	} while (k < T);
}
#endif // DENSITY_REFINE
#elif defined(FIELD_PASS_BOUND)
#include "block_bound.glsl"
#else // every other pass reads the densities, or their sign bits (or both)
#if defined(PASS_READS_SIGNS) || defined(PASS_CASE_FROM_SIGNS)
// PASS_CASE_FROM_SIGNS: the comparison methods (mc_atomic.comp,
// mc_nocompact.comp) read the debris filter's sign bits for the cells'
// cases beside the densities for the vertices, at a point of their own
#ifdef PASS_READS_SIGNS
layout(std430, binding = BIND_SIGNS) restrict readonly buffer Signs { uint signs[]; };
#else
layout(std430, binding = BIND_CASE_SIGNS) restrict readonly buffer Signs { uint signs[]; };
#endif
// len (1..32) sign bits from bit b on, bit 0 = sample b
uint sign_run(uint b, uint len)
{
	uint w = b >> 5u, s = b & 31u;
	uint v = signs[w] >> s;
	if (s + len > 32u)
		v |= signs[w + 1u] << (32u - s);
	return len >= 32u ? v : v & ((1u << len) - 1u);
}
// the sign bit of corner c (each component -margin .. n+margin)
uint sign_bit_index(ivec3 c)
{
	ivec3 d = dens_dims();
	c += u_margin;
	return uint(c.z) * sign_slab_bits() + uint(c.x + d.x * c.y);
}
#endif // PASS_READS_SIGNS || PASS_CASE_FROM_SIGNS
#ifndef PASS_READS_SIGNS
layout(std430, binding = BIND_DENSITY) restrict readonly buffer Dens { float dens[]; };
// density at corner c (each component -1 .. n+1)
float D(ivec3 c)
{
	ivec3 d = dens_dims();
	c += u_margin;
	return dens[c.x + d.x * (c.y + d.y * c.z)];
}
vec3 grad_at(ivec3 c)
{
	return vec3(D(c + ivec3(1, 0, 0)) - D(c - ivec3(1, 0, 0)),
		    D(c + ivec3(0, 1, 0)) - D(c - ivec3(0, 1, 0)),
		    D(c + ivec3(0, 0, 1)) - D(c - ivec3(0, 0, 1)));
}

#endif // !PASS_READS_SIGNS

// Marching Cubes tables (mc_tables.c), packed into a uniform block
// (extract/pipeline.c upload_tables): per case two words, its 15 edge ids
// at 4 bits each (15 = none) and its triangle count in bits 60..63.
layout(std140, binding = UBIND_MC_TABLES) uniform McTables {
	uvec4 mc_cases[128]; // cases 2i (xy) and 2i+1 (zw)
	ivec4 mc_edge_owner[12]; // owner offset xyz, slot
	ivec4 mc_corner[8];
};
uvec2 mc_case_words(int cs)
{
	uvec4 v = mc_cases[cs >> 1];
	return (cs & 1) == 0 ? v.xy : v.zw;
}
uint mc_tricount(int cs)
{
	return mc_case_words(cs).y >> 28;
}
// edge id k (0..14) of case cs's triangles, three a triangle
int mc_tri(int cs, int k)
{
	uvec2 w = mc_case_words(cs);
	return int(((k < 8 ? w.x : w.y) >> (4u * uint(k & 7))) & 15u);
}

#if defined(PASS_READS_SIGNS) || defined(PASS_CASE_FROM_SIGNS)
// The case byte of cell c from its corners' sign bits (corner order of
// mc_tables.c: 000 010 110 100 001 011 111 101, xyz).
int cell_case(ivec3 c)
{
	uint a = sign_run(sign_bit_index(c), 2u), b = sign_run(sign_bit_index(c + ivec3(0, 1, 0)), 2u);
	uint e = sign_run(sign_bit_index(c + ivec3(0, 0, 1)), 2u), f = sign_run(sign_bit_index(c + ivec3(0, 1, 1)), 2u);
	return int((a & 1u) | ((b & 1u) << 1) | ((b & 2u) << 1) | ((a & 2u) << 2) | ((e & 1u) << 4) | ((f & 1u) << 5) |
		   ((f & 2u) << 5) | ((e & 2u) << 6));
}
#endif
#ifndef PASS_READS_SIGNS

// Vertex on the edge from corner c along axis a (0,1,2): position, normal.
void edge_vertex(ivec3 c, int a, out vec4 pos, out vec4 nrm)
{
	ivec3 c1 = c;
	c1[a] += 1;
	float d0 = D(c), d1 = D(c1);
	float t = (d0 - u_iso) / (d0 - d1);
	vec3 p = vec3(u_base + c);
	p[a] += t;
	pos = vec4(u_origin + p * u_cell, 1.0);
	vec3 g0 = grad_at(c), g1 = grad_at(c1);
	vec3 g = g0 + (g1 - g0) * t;
	float len = length(g);
	nrm = vec4(len > 1e-20 ? -g / len : vec3(0.0, 1.0, 0.0), 1.0); // w: ambient visibility
}
#endif // !PASS_READS_SIGNS
#endif // FIELD_PASS_DENSITY
