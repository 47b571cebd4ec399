// isoterra — HistoPyramid over the owner cells of the grid (Dyken & Ziegler,
// in a 1D, 4-to-1 form that works for any cell count).
//
// Level 0 is implicit: one byte per owner cell, packed four to a uint
//   bits 0..2 = triangles emitted by the cell (0..5)
//   bits 3..5 = mask of the vertices it owns on its +x, +y, +z edges
// Level k >= 1 holds uvec2(triangles, vertices) sums of four level k-1
// nodes.  One buffer holds it all (one storage block of the ES 3.1
// minimum's four): level 0 first, two words a uvec2, then level k at
// u_hp_off[k], then the prefix sums of levels 2..top (hp_downsweep.comp).
// The top level (u_hp_top) has one node: the totals.
#ifdef HP_COHERENT
layout(std430, binding = BIND_HP) coherent restrict buffer Hp { uvec2 hp[]; };
#else
layout(std430, binding = BIND_HP) restrict buffer Hp { uvec2 hp[]; };
#endif
uniform uint u_hp_off[16];
uniform int u_hp_top;
uniform uint u_pre_base; // prefix sums (hp_downsweep.comp) start here
uniform uint u_hp_n2;    // real level-2 nodes (when u_hp_top >= 2)

// level-0 word i (four owner cells)
uint hp_l0(uint i) { return hp[i >> 1u][i & 1u]; }
uint l0_byte(uint cell) { return (hp_l0(cell >> 2) >> (8u * (cell & 3u))) & 255u; }
uint byte_count(uint b, int comp) { return comp == 0 ? (b & 7u) : uint(bitCount(b >> 3)); }

// Output number key of component comp (0 triangles, 1 vertices) -> the cell
// that emits it and its rank among that cell's outputs.
void hp_traverse(uint key, int comp, out uint cell, out uint rank)
{
	uint i = 0u;
	if (u_hp_top >= 2) {
		// the level-2 node: the last whose down-swept prefix is <= key (an
		// empty node shares its prefix with the next), by a binary search
		// of the prefixes: log2(nodes) loads where the walk down the levels
		// takes three a level, each step without a branch (a SIMD driver
		// runs a divergent loop as long as its slowest lane)
		uint base = u_pre_base + u_hp_off[2], n = u_hp_n2, below = 0u;
		// (the exponent counted down: a step halved each turn, 17 turns
		// from 65 537 nodes on, came out wrong under Mesa 22.3's llvmpipe)
		for (int s = findMSB(n - 1u); s >= 0; --s) { // findMSB(0u) = -1: no step
			uint m = i + (1u << uint(s));
			uint v = hp[base + min(m, n - 1u)][comp];
			bool right = m < n && v <= key;
			i = right ? m : i;
			below = right ? v : below;
		}
		key -= below;
		// its level-1 children: three loads and compares
		uint b = u_hp_off[1] + 4u * i;
		uint c0 = hp[b][comp], c1 = c0 + hp[b + 1u][comp], c2 = c1 + hp[b + 2u][comp];
		uint j = uint(key >= c0) + uint(key >= c1) + uint(key >= c2);
		key -= j == 0u ? 0u : j == 1u ? c0 : j == 2u ? c1 : c2;
		i = 4u * i + j;
	}
	uint w = hp_l0(i);
	uint b0 = byte_count(w & 255u, comp), b1 = b0 + byte_count((w >> 8) & 255u, comp),
	     b2 = b1 + byte_count((w >> 16) & 255u, comp);
	uint j = uint(key >= b0) + uint(key >= b1) + uint(key >= b2);
	cell = 4u * i + j;
	rank = key - (j == 0u ? 0u : j == 1u ? b0 : j == 2u ? b1 : b2);
}

// Number of outputs of component comp emitted by cells before `cell`, from
// the down-swept prefix sums of level 2 (valid after hp_downsweep.comp)
// plus the left siblings at level 1 and the bytes before it in its word w
// (hp_prefix_word: a caller that has read the word; hp_prefix_fast reads it).
uint hp_prefix_word(uint cell, uint w, int comp)
{
	uint i = cell >> 2, sum = 0u;
	if (u_hp_top >= 2) {
		sum = hp[u_pre_base + u_hp_off[2] + (i >> 2)][comp];
		uint s = u_hp_off[1] + (i & ~3u), n = i & 3u; // left siblings: loads without a loop
		sum += (n > 0u ? hp[s][comp] : 0u) + (n > 1u ? hp[s + 1u][comp] : 0u) + (n > 2u ? hp[s + 2u][comp] : 0u);
	}
	uint below = (1u << (8u * (cell & 3u))) - 1u; // the bytes before the cell's in its word
	return sum + (comp == 0 ? ((w & below & 0x07070707u) * 0x01010101u) >> 24 : uint(bitCount(w & below & 0x38383838u)));
}
uint hp_prefix_fast(uint cell, int comp) { return hp_prefix_word(cell, hp_l0(cell >> 2), comp); }

// The same, read bottom-up from the pyramid (no down-sweep needed).
uint hp_prefix(uint cell, int comp)
{
	uint w = hp_l0(cell >> 2);
	uint sum = 0u;
	for (uint j = 0u; j < (cell & 3u); ++j)
		sum += byte_count((w >> (8u * j)) & 255u, comp);
	uint i = cell >> 2;
	for (int k = 1; k < u_hp_top; ++k) {
		uint base = u_hp_off[k];
		for (uint m = i & ~3u; m < i; ++m)
			sum += hp[base + m][comp];
		i >>= 2;
	}
	return sum;
}
