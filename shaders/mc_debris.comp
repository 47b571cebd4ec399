// isoterra — the debris filter, between the density pass and classification:
// the sign bits of the density grid less one-sample debris.  An inside
// sample none of whose six neighbours is inside counts as outside (such a
// one-sample island would float as a speck of eight triangles), and an
// outside sample all of whose six neighbours are inside counts as inside (a
// bubble in the rock, never seen); a neighbour beyond the grid's samples
// counts as outside.  One invocation per sign word (32 samples of a z slab,
// as the density pass wrote them): the word, its two neighbours along the
// slab (x), two unaligned runs of 32 bits a row away (y) and the words a
// slab away (z); word-wide operations, no loop over the samples.  Only
// classification and the index pass read the bits: an edge that crossed at
// a flipped sample has both ends on one side now, so the vertex pass (which
// interpolates the densities of crossing edges) needs no change.  Mirrored
// in app/extract/mc_ref.c (inside()).  Dispatch: (ceil(words of a slab /
// WG_SIZE), slabs) groups of WG_SIZE.
layout(local_size_x = WG_SIZE) in;
#define PASS_READS_SIGNS 1 // common.glsl's Signs (BIND_SIGNS): here the raw bits
#include "common.glsl"
layout(std430, binding = BIND_SIGNS_OUT) restrict writeonly buffer Filtered { uint filtered[]; };
uniform uint u_sign_words; // both buffers' capacity in words
#ifdef DEBRIS_NEAR
// After a density pass that cut far samples (common.glsl): the raw samples
// with a six-neighbour of the other sign (one beyond the grid does not
// count: no edge leads there), for the refine passes, after the cut bits
// in the same buffer.
layout(std430, binding = BIND_CUT) restrict writeonly buffer Near { uint near_out[]; };
#endif

uint raw_word(uint w) { return w < u_sign_words ? signs[w] : 0u; }

// 32 raw bits from bit b on (any alignment), bit 0 = sample b
uint raw_run32(uint b)
{
	uint w = b >> 5u, s = b & 31u;
	uint v = raw_word(w) >> s;
	return s == 0u ? v : v | (raw_word(w + 1u) << (32u - s));
}

// the bits j of a word for which 0 <= first + j < limit (first may be negative)
uint bits_below(int first, int limit)
{
	int k = limit - first; // bits 0 .. k-1
	return k <= 0 ? 0u : k >= 32 ? ~0u : (1u << uint(k)) - 1u;
}

void main()
{
	ivec3 dim = dens_dims();
	int n = dim.x * dim.y; // samples of a slab
	uint words = sign_slab_bits() / 32u;
	uint wv = gl_WorkGroupID.x * uint(WG_SIZE) + gl_LocalInvocationID.x;
	if (wv >= words)
		return;
	int z = int(gl_WorkGroupID.y);
	uint w0 = uint(z) * words; // the slab's first word
	int b0 = int(wv) * 32;     // this word's first sample in the slab
	uint c = raw_word(w0 + wv);
	uint valid = bits_below(b0, n);
	// x: the samples before and after along the slab, not across a row's end
	uint prev = wv > 0u ? raw_word(w0 + wv - 1u) : 0u;
	uint next = wv + 1u < words ? raw_word(w0 + wv + 1u) : 0u;
	uint xm = (c << 1) | (prev >> 31), xp = (c >> 1) | (next << 31);
	int x = divmod(b0, dim.x).y;
	uint xm_ok = ~0u, xp_ok = ~0u; // the bits whose neighbour exists
	for (int j = x == 0 ? 0 : dim.x - x; j < 32; j += dim.x)
		xm_ok &= ~(1u << uint(j)); // x == 0: no sample at x - 1
	for (int j = dim.x - 1 - x; j < 32; j += dim.x)
		xp_ok &= ~(1u << uint(j)); // x == dim.x - 1: none at x + 1
	xm &= xm_ok;
	xp &= xp_ok;
	// y: a row (dim.x samples) before and after, inside the slab
	uint ym = b0 >= dim.x ? raw_run32(w0 * 32u + uint(b0 - dim.x))
	                      : (dim.x - b0 < 32 ? raw_run32(w0 * 32u) << uint(dim.x - b0) : 0u);
	uint yp = raw_run32(w0 * 32u + uint(b0 + dim.x)) & bits_below(b0 + dim.x, n);
	// z: the same word a slab before and after, inside the grid
	uint zm = z > 0 ? raw_word(w0 - words + wv) : 0u;
	uint zp = z + 1 < dim.z ? raw_word(w0 + words + wv) : 0u;
	uint any6 = xm | xp | ym | yp | zm | zp, all6 = xm & xp & ym & yp & zm & zp;
	uint wi = w0 + wv;
	if (wi < u_sign_words) {
		filtered[wi] = ((c & any6) | (~c & all6)) & valid;
#ifdef DEBRIS_NEAR
		// a neighbour beyond the grid is no sign change (no edge leads there)
		uint ym_ok = ~bits_below(b0 - dim.x, 0), yp_ok = bits_below(b0 + dim.x, n);
		uint zm_ok = z > 0 ? ~0u : 0u, zp_ok = z + 1 < dim.z ? ~0u : 0u;
		near_out[u_sign_words + wi] = (((c ^ xm) & xm_ok) | ((c ^ xp) & xp_ok) | ((c ^ ym) & ym_ok) |
					       ((c ^ yp) & yp_ok) | ((c ^ zm) & zm_ok) | ((c ^ zp) & zp_ok)) & valid;
#endif
	}
}
