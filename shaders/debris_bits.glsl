// isoterra — the bits the debris filter reads (shaders/mc_debris.comp,
// mc_debris_flood.comp): words, unaligned runs, a z slab's runs, of the
// raw sign bits or (src 1) of the candidate bits the first pass keeps for
// every word (abi.h DL_BITS).  The including pass declares u_sign_words,
// binds the raw bits as Signs (common.glsl, PASS_READS_SIGNS) and the
// candidate list as dl.
uint src_word(uint w, int src)
{
	return w >= u_sign_words ? 0u : src == 0 ? signs[w] : dl[DL_BITS(u_sign_words) + w];
}
uint raw_word(uint w) { return src_word(w, 0); }

// 32 bits from bit b on (any alignment), bit 0 = sample b
uint src_run32(uint b, int src)
{
	uint w = b >> 5u, s = b & 31u;
	uint v = src_word(w, src) >> s;
	return s == 0u ? v : v | (src_word(w + 1u, src) << (32u - s));
}
uint raw_run32(uint b) { return src_run32(b, 0); }

// the bits j of a word for which 0 <= first + j < limit (first may be negative)
uint bits_below(int first, int limit)
{
	int k = limit - first; // bits 0 .. k-1
	return k <= 0 ? 0u : k >= 32 ? ~0u : (1u << uint(k)) - 1u;
}

// Samples start .. start + 31 of slab zz (0 outside the slab or the grid)
uint src_slab_run(int zz, int start, int n, uint words, int src)
{
	if (zz < 0 || zz >= dens_dims().z || start <= -32)
		return 0u;
	uint base = uint(zz) * words * 32u;
	uint v = start >= 0 ? src_run32(base + uint(start), src) : src_run32(base, src) << uint(-start);
	return v & bits_below(start, n) & ~bits_below(start, 0);
}
uint slab_run(int zz, int start, int n, uint words) { return src_slab_run(zz, start, n, words, 0); }
