// isoterra — the refine list: after a density pass that cut far samples
// (common.glsl, DENSITY_CUT) and the debris filter that marked the samples
// next to a sign change (mc_debris.comp, DEBRIS_NEAR), the cut samples
// within one six-neighbour step of a marked one -- within two of a sign
// change, where the vertex pass reads values (a crossing edge's two ends
// and the central differences around each) -- listed for the field's
// refine variant (DENSITY_REFINE), which computes them whole.  An
// invocation per sign word, as the density pass (dispatch: (ceil(words of
// a slab / WG_SIZE), slabs) groups of WG_SIZE): the marks of the word, of
// its neighbours along x, of the rows before and after and of the slabs
// before and after, word-wide.  A row's end or a slab's padding brings
// other samples than the neighbours: that only lists more.  Layout of the
// list: abi.h (RF_*); a word whose samples find no room in it is listed
// whole, its cut bits left to say which.
layout(local_size_x = WG_SIZE) in;
#include "common.glsl"
// the cut bits, then the near bits, u_sign_words each
layout(std430, binding = BIND_CUT) restrict buffer CutNear { uint cut_near[]; };
layout(std430, binding = BIND_REFINE) restrict buffer Refine { uint rf[]; };
uniform uint u_sign_words;  // the sign buffers' capacity in words
uniform uint u_refine_cap;  // the list's sample entries
uniform uint u_max_groups;  // the dispatch's largest x

uint near_word(int w) // a word of the near bits; beyond the grid: none
{
	return w >= 0 && uint(w) < u_sign_words ? cut_near[u_sign_words + uint(w)] : 0u;
}

// 32 near bits from bit b on (any alignment, b may be negative)
uint near_run(int b)
{
	int w = b >> 5; // floor division, also below 0
	uint s = uint(b & 31);
	uint v = near_word(w) >> s;
	return s == 0u ? v : v | (near_word(w + 1) << (32u - s));
}

// the refine pass's groups for n invocations
uint groups(uint n)
{
	return min((n + uint(WG_SIZE) - 1u) / uint(WG_SIZE), u_max_groups);
}

void main()
{
	ivec3 dim = dens_dims();
	uint words = sign_slab_bits() / 32u;
	uint wv = gl_WorkGroupID.x * uint(WG_SIZE) + gl_LocalInvocationID.x;
	if (wv >= words)
		return;
	uint wi = gl_WorkGroupID.y * words + wv;
	if (wi >= u_sign_words)
		return;
	int w = int(wi), b0 = w * 32, slab = int(words);
	uint c = near_word(w), prev = near_word(w - 1), next = near_word(w + 1);
	uint band = c | (c << 1) | (prev >> 31) | (c >> 1) | (next << 31) | near_run(b0 - dim.x) | near_run(b0 + dim.x) |
		    near_word(w - slab) | near_word(w + slab);
	uint need = cut_near[wi] & band;
	if (need == 0u)
		return;
	uint n = uint(bitCount(need));
	uint base = atomicAdd(rf[RF_SAMPLES], n);
	uint fit = base >= u_refine_cap ? 0u : min(n, u_refine_cap - base);
	for (uint k = 0u; k < fit; k++) {
		int j = findLSB(need);
		need &= need - 1u;
		rf[RF_HEAD + base + k] = wi * 32u + uint(j);
	}
	if (fit > 0u)
		atomicMax(rf[RF_DISPATCH], groups(base + fit));
	if (need != 0u) { // no room left: the word's own entry, its cut bits the rest
		uint e = atomicAdd(rf[RF_WORDS], 1u);
		rf[RF_HEAD + u_refine_cap + e] = wi;
		cut_near[wi] = need;
		atomicMax(rf[RF_DISPATCH], groups(u_refine_cap + 32u * (e + 1u)));
	}
}
