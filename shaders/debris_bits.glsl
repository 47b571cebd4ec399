// isoterra — the raw sign bits as the debris filter reads them
// (shaders/mc_debris.comp, mc_debris_flood.comp): words, unaligned runs,
// a z slab's runs.  The including pass declares u_sign_words and binds the
// raw bits as Signs (common.glsl, PASS_READS_SIGNS).
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

// Samples start .. start + 31 of slab zz (0 outside the slab or the grid)
uint slab_run(int zz, int start, int n, uint words)
{
	if (zz < 0 || zz >= dens_dims().z || start <= -32)
		return 0u;
	uint base = uint(zz) * words * 32u;
	uint v = start >= 0 ? raw_run32(base + uint(start)) : raw_run32(base) << uint(-start);
	return v & bits_below(start, n) & ~bits_below(start, 0);
}
