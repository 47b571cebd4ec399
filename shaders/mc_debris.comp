// isoterra — the debris filter's first pass, between the density pass and
// classification: the sign bits of the density grid less debris, a
// component of inside samples that spans at most DEBRIS_SPAN samples along
// each axis (abi.h: it would float as a speck or a rock).  Here: an inside sample none of whose
// six neighbours is inside counts as outside (a speck of eight triangles),
// and so do two inside neighbours that have no other inside neighbour (a
// speck of a dozen); an outside sample all of whose six neighbours are
// inside counts as inside (a bubble in the rock, never seen); a neighbour
// beyond the grid's samples counts as outside.  The samples that may
// belong to larger debris (abi.h DEBRIS_SPAN) are listed for the second pass
// (mc_debris_flood.comp), which grows their components.  One invocation
// per sign word (32 samples of a z slab, as the density pass wrote them):
// the word, its two neighbours along the slab (x), two unaligned runs of
// 32 bits a row away (y) and the words a slab away (z); for a word with a
// sample that has a single inside neighbour, the eighteen runs two steps
// away too (that neighbour's own neighbours); for a word with candidates,
// the rows up to DEBRIS_SPAN steps away that rule them out; word-wide operations, no
// loop over the samples.  Only classification and the index pass read the
// bits: an edge that crossed at a flipped sample has both ends on one side
// now, so the vertex pass (which interpolates the densities of crossing
// edges) needs no change.  Mirrored in app/extract/mc_ref.c
// (mc_ref_inside()).  Dispatch: (ceil(words of a slab / WG_SIZE), slabs)
// groups of WG_SIZE.
layout(local_size_x = WG_SIZE) in;
#define PASS_READS_SIGNS 1 // common.glsl's Signs (BIND_SIGNS): here the raw bits
#include "common.glsl"
layout(std430, binding = BIND_SIGNS_OUT) restrict writeonly buffer Filtered { uint filtered[]; };
// the words with larger debris candidates, for mc_debris_flood.comp (abi.h DL_*)
layout(std430, binding = BIND_DEBRIS) restrict buffer Candidates { uint dl[]; };
uniform uint u_sign_words; // both buffers' capacity in words
uniform uint u_max_groups; // the flood pass's dispatch's largest x
#include "debris_bits.glsl"
#ifdef DEBRIS_NEAR
// After a density pass that cut far samples (common.glsl): the raw samples
// with a six-neighbour of the other sign (one beyond the grid does not
// count: no edge leads there), for the refine passes, after the cut bits
// in the same buffer.
layout(std430, binding = BIND_CUT) restrict writeonly buffer Near { uint near_out[]; };
#endif

// cand less the samples of word c (its first sample b0 of slab z) that
// lie in a run of DEBRIS_SPAN + 1 inside samples along y: a before it and
// DEBRIS_SPAN - a after.  p1, m1: the bits a row after and before.  Each
// step's run loaded only while a candidate needs it.
uint not_in_y_run(uint cand, uint c, uint p1, uint m1, int z, int b0, int n, uint words)
{
	const int S = DEBRIS_SPAN;
	int r = dens_dims().x;
	uint rp[S + 1], rm[S + 1]; // rp[k]: inside through k after
	rp[0] = rm[0] = c;
	rp[1] = c & p1;
	rm[1] = c & m1;
	for (int k = 2; k <= S; k++) {
		rp[k] = (rp[k - 1] & cand) != 0u ? rp[k - 1] & slab_run(z, b0 + k * r, n, words) : 0u;
		rm[k] = (rm[k - 1] & cand) != 0u ? rm[k - 1] & slab_run(z, b0 - k * r, n, words) : 0u;
	}
	for (int k = 0; k <= S; k++)
		cand &= ~(rm[k] & rp[S - k]);
	return cand;
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
	uint wi = w0 + wv;         // this word
	int b0 = int(wv) * 32;     // its first sample in the slab
	uint c = raw_word(wi);
	uint valid = bits_below(b0, n);
	// x: the samples before and after along the slab, not across a row's end
	uint prev = wv > 0u ? raw_word(wi - 1u) : 0u;
	uint next = wv + 1u < words ? raw_word(wi + 1u) : 0u;
	uint xm = (c << 1) | (prev >> 31), xp = (c >> 1) | (next << 31);
	int x = divmod(b0, dim.x).y;
	uint xm_ok = ~0u, xp_ok = ~0u; // the bits whose neighbour exists
	for (int j = x == 0 ? 0 : dim.x - x; j < 32; j += dim.x)
		xm_ok &= ~(1u << uint(j)); // x == 0: no sample at x - 1
	// the row ends past the word, for the runs along x below: ln bit u = a
	// row's last sample at bit 32 + u, fp bit 31 - u = a row's first
	// sample at bit -1 - u (u < DEBRIS_SPAN - 1)
	uint ln = 0u, fp = 0u;
	for (int j = dim.x - 1 - x; j < 32 + DEBRIS_SPAN - 1; j += dim.x) {
		if (j < 32)
			xp_ok &= ~(1u << uint(j)); // x == dim.x - 1: none at x + 1
		else
			ln |= 1u << uint(j - 32);
	}
	for (int j = (x == 0 ? 0 : dim.x - x) - dim.x; j >= -(DEBRIS_SPAN - 1); j -= dim.x)
		fp |= 1u << uint(32 + j);
	xm &= xm_ok;
	xp &= xp_ok;
	uint last = ~xp_ok, first = ~xm_ok;
	// the bits with no sample 2 along the row (a row's end within one)
	uint no2p = last | (last >> 1) | (ln << 31), no2m = first | (first << 1) | (fp >> 31);
	// y: a row (dim.x samples) before and after, inside the slab
	uint ym = b0 >= dim.x ? raw_run32(w0 * 32u + uint(b0 - dim.x))
	                      : (dim.x - b0 < 32 ? raw_run32(w0 * 32u) << uint(dim.x - b0) : 0u);
	uint yp = raw_run32(w0 * 32u + uint(b0 + dim.x)) & bits_below(b0 + dim.x, n);
	// z: the same word a slab before and after, inside the grid
	uint zm = z > 0 ? raw_word(wi - words) : 0u;
	uint zp = z + 1 < dim.z ? raw_word(wi + words) : 0u;
	uint any6 = xm | xp | ym | yp | zm | zp, all6 = xm & xp & ym & yp & zm & zp;
	// Two-sample islands: a sample whose only inside neighbour (along d)
	// has no inside neighbour but it (the runs at d + e, e != -d)
	uint n1_xm = c & xm & ~(xp | ym | yp | zm | zp), n1_xp = c & xp & ~(xm | ym | yp | zm | zp);
	uint n1_ym = c & ym & ~(xm | xp | yp | zm | zp), n1_yp = c & yp & ~(xm | xp | ym | zm | zp);
	uint n1_zm = c & zm & ~(xm | xp | ym | yp | zp), n1_zp = c & zp & ~(xm | xp | ym | yp | zm);
	uint iso2 = 0u;
	int r = dim.x;
#define RUN(dx, dy, dz, ok) (slab_run(z + (dz), b0 + (dx) + (dy) * r, n, words) & (ok))
	if ((n1_xm | n1_xp | n1_ym | n1_yp | n1_zm | n1_zp) != 0u) {
		uint okm2 = ~no2m, okm1 = xm_ok, okp1 = xp_ok, okp2 = ~no2p;
		uint xm2 = RUN(-2, 0, 0, okm2), xp2 = RUN(2, 0, 0, okp2);
		uint ym2 = RUN(0, -2, 0, ~0u), yp2 = RUN(0, 2, 0, ~0u), zm2 = RUN(0, 0, -2, ~0u), zp2 = RUN(0, 0, 2, ~0u);
		uint xmym = RUN(-1, -1, 0, okm1), xmyp = RUN(-1, 1, 0, okm1), xpym = RUN(1, -1, 0, okp1),
		     xpyp = RUN(1, 1, 0, okp1);
		uint xmzm = RUN(-1, 0, -1, okm1), xmzp = RUN(-1, 0, 1, okm1), xpzm = RUN(1, 0, -1, okp1),
		     xpzp = RUN(1, 0, 1, okp1);
		uint ymzm = RUN(0, -1, -1, ~0u), ymzp = RUN(0, -1, 1, ~0u), ypzm = RUN(0, 1, -1, ~0u),
		     ypzp = RUN(0, 1, 1, ~0u);
		iso2 = (n1_xm & ~(xm2 | xmym | xmyp | xmzm | xmzp)) | (n1_xp & ~(xp2 | xpym | xpyp | xpzm | xpzp)) |
		       (n1_ym & ~(ym2 | xmym | xpym | ymzm | ymzp)) | (n1_yp & ~(yp2 | xmyp | xpyp | ypzm | ypzp)) |
		       (n1_zm & ~(zm2 | xmzm | xpzm | ymzm | ypzm)) | (n1_zp & ~(zp2 | xmzp | xpzp | ymzp | ypzp));
	}
	// Larger debris, of up to S = DEBRIS_SPAN samples along each axis (the
	// next pass, mc_debris_flood.comp, grows their components): an inside
	// sample left is a candidate unless along x or y it lies in a run of
	// S + 1 inside samples (which would make a span of more): a samples
	// before it and S - a after, for some a.  x from the words at hand (in
	// rock that rules out every sample), then y while a candidate is left
	// (on the ground that does).  Not z: on terrain the samples a z run
	// would rule out are few (rods lying along z), and its loads cost more
	// than the flood's growth they would save (docs/PIPELINE.md).  The
	// word's candidates are listed.
	const int S = DEBRIS_SPAN;
	uint cand = c & any6 & ~iso2 & valid;
	if (cand != 0u) {
		uint rp[S + 1], rm[S + 1], nop = last, nom = first; // rp[k]: inside through k after
		rp[0] = rm[0] = c;
		rp[1] = c & xp;
		rm[1] = c & xm;
		for (int k = 2; k <= S; k++) {
			// no sample k along: a row's end within the k - 1 before
			nop |= (last >> uint(k - 1)) | (ln << uint(33 - k));
			nom |= (first << uint(k - 1)) | (fp >> uint(33 - k));
			rp[k] = rp[k - 1] & ((c >> uint(k)) | (next << uint(32 - k))) & ~nop;
			rm[k] = rm[k - 1] & ((c << uint(k)) | (prev >> uint(32 - k))) & ~nom;
		}
		for (int k = 0; k <= S; k++)
			cand &= ~(rm[k] & rp[S - k]);
	}
	if (cand != 0u)
		cand = not_in_y_run(cand, c, yp, ym, z, b0, n, words);
#undef RUN
	if (cand != 0u && wi < u_sign_words) { // an entry a word: room for every word
		uint e = atomicAdd(dl[DL_COUNT], 1u);
		dl[DL_HEAD + 2u * e] = wi;
		dl[DL_HEAD + 2u * e + 1u] = cand;
		atomicMax(dl[DL_DISPATCH], min(e / uint(WG_SIZE) + 1u, u_max_groups));
	}
	if (wi < u_sign_words) {
		dl[DL_BITS(u_sign_words) + wi] = cand; // every word's: the flood's growth reads them
		filtered[wi] = ((c & any6 & ~iso2) | (~c & all6)) & valid;
#ifdef DEBRIS_NEAR
		// a neighbour beyond the grid is no sign change (no edge leads there)
		uint ym_ok = ~bits_below(b0 - dim.x, 0), yp_ok = bits_below(b0 + dim.x, n);
		uint zm_ok = z > 0 ? ~0u : 0u, zp_ok = z + 1 < dim.z ? ~0u : 0u;
		near_out[u_sign_words + wi] = (((c ^ xm) & xm_ok) | ((c ^ xp) & xp_ok) | ((c ^ ym) & ym_ok) |
					       ((c ^ yp) & yp_ok) | ((c ^ zm) & zm_ok) | ((c ^ zp) & zp_ok)) & valid;
#endif
	}
}
