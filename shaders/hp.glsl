// isoterra — HistoPyramid over the owner cells of the grid (Dyken & Ziegler,
// in a 1D, 4-to-1 form that works for any cell count).
//
// Level 0 is implicit: one byte per owner cell, packed four to a uint
//   bits 0..2 = triangles emitted by the cell (0..5)
//   bits 3..5 = mask of the vertices it owns on its +x, +y, +z edges
// Level 1 (the sums of a word's four bytes) is not stored: a word's counts
// are a multiply and a bit count (word_count), no dearer than a load, and
// its two words a cell were the largest part of the pyramid's bytes.
// Level k >= 2 holds uvec2(triangles, vertices) sums of four level k-1
// nodes.  One buffer holds it all (one storage block of the ES 3.1
// minimum's four): level 0 first, two words a uvec2, four words (two
// uvec2) a level-2 node, then level k at u_hp_off[k], then the prefix sums
// of levels 2..top (hp_top.comp, hp_downsweep.comp).  The top level
// (u_hp_top, 2 or more) has one node: the totals.
#ifdef HP_COHERENT
layout(std430, binding = BIND_HP) coherent restrict buffer Hp { uvec2 hp[]; };
#else
layout(std430, binding = BIND_HP) restrict buffer Hp { uvec2 hp[]; };
#endif
uniform uint u_hp_off[16];
uniform int u_hp_top;
uniform uint u_pre_base; // prefix sums (hp_top.comp, hp_downsweep.comp) start here
uniform uint u_hp_n2;    // real level-2 nodes

// level-0 word i (four owner cells)
uint hp_l0(uint i) { return hp[i >> 1u][i & 1u]; }
uint l0_byte(uint cell) { return (hp_l0(cell >> 2) >> (8u * (cell & 3u))) & 255u; }
uint byte_count(uint b, int comp) { return comp == 0 ? (b & 7u) : uint(bitCount(b >> 3)); }
// the outputs of a word's four cells: the bytes' low three bits summed (at
// most 20: no carry between bytes), or the bits 3..5 counted
uint word_count(uint w, int comp)
{
	return comp == 0 ? ((w & 0x07070707u) * 0x01010101u) >> 24 : uint(bitCount(w & 0x38383838u));
}

// Output number key of component comp (0 triangles, 1 vertices) -> the cell
// that emits it and its rank among that cell's outputs.
void hp_traverse(uint key, int comp, out uint cell, out uint rank)
{
	// the level-2 node: the last whose down-swept prefix is <= key (an
	// empty node shares its prefix with the next), by a binary search of
	// the prefixes: log2(nodes) loads where the walk down the levels takes
	// three a level, each step without a branch (a SIMD driver runs a
	// divergent loop as long as its slowest lane).  The exponent is
	// counted down: a step halved each turn, 17 turns from 65 537 nodes on,
	// came out wrong under Mesa 22.3's llvmpipe.
	uint i = 0u, base = u_pre_base + u_hp_off[2], n = u_hp_n2, below = 0u;
	for (int s = findMSB(n - 1u); s >= 0; --s) { // findMSB(0u) = -1: no step
		uint m = i + (1u << uint(s));
		uint v = hp[base + min(m, n - 1u)][comp];
		bool right = m < n && v <= key;
		i = right ? m : i;
		below = right ? v : below;
	}
	key -= below;
	// its four words (two loads): which one, then which byte
	uvec2 a = hp[2u * i], b = hp[2u * i + 1u];
	uint c0 = word_count(a.x, comp), c1 = c0 + word_count(a.y, comp), c2 = c1 + word_count(b.x, comp);
	uint j = uint(key >= c0) + uint(key >= c1) + uint(key >= c2);
	key -= j == 0u ? 0u : j == 1u ? c0 : j == 2u ? c1 : c2;
	uint w = j == 0u ? a.x : j == 1u ? a.y : j == 2u ? b.x : b.y;
	i = 4u * i + j;
	uint b0 = byte_count(w & 255u, comp), b1 = b0 + byte_count((w >> 8) & 255u, comp),
	     b2 = b1 + byte_count((w >> 16) & 255u, comp);
	j = uint(key >= b0) + uint(key >= b1) + uint(key >= b2);
	cell = 4u * i + j;
	rank = key - (j == 0u ? 0u : j == 1u ? b0 : j == 2u ? b1 : b2);
}

// Number of outputs of component comp emitted by cells before `cell`: the
// down-swept prefix of its level-2 node (valid after hp_top.comp and
// hp_downsweep.comp) plus the words before its own in that node and the
// bytes before it in its word; w gets the cell's word (the node's four
// words are read at once).
uint hp_prefix_w(uint cell, int comp, out uint w)
{
	uint i = cell >> 2, g = i >> 2;
	uvec2 a = hp[2u * g], b = hp[2u * g + 1u];
	uint n = i & 3u;
	w = n == 0u ? a.x : n == 1u ? a.y : n == 2u ? b.x : b.y;
	uint sum = hp[u_pre_base + u_hp_off[2] + g][comp];
	sum += (n > 0u ? word_count(a.x, comp) : 0u) + (n > 1u ? word_count(a.y, comp) : 0u) +
	       (n > 2u ? word_count(b.x, comp) : 0u);
	uint before = (1u << (8u * (cell & 3u))) - 1u; // the bytes before the cell's in its word
	return sum + word_count(w & before, comp);
}
uint hp_prefix_fast(uint cell, int comp)
{
	uint w;
	return hp_prefix_w(cell, comp, w);
}

// The same, read bottom-up from the pyramid (no down-sweep needed): the
// tests' reference for the above.
uint hp_prefix(uint cell, int comp)
{
	uint i = cell >> 2;
	uint sum = word_count(hp_l0(i) & ((1u << (8u * (cell & 3u))) - 1u), comp);
	for (uint m = i & ~3u; m < i; ++m)
		sum += word_count(hp_l0(m), comp);
	i >>= 2;
	for (int k = 2; k < u_hp_top; ++k) {
		uint base = u_hp_off[k];
		for (uint m = i & ~3u; m < i; ++m)
			sum += hp[base + m][comp];
		i >>= 2;
	}
	return sum;
}
