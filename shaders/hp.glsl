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
// (u_hp_top, 2 or more) has one node: the totals.  After the prefix sums,
// the hints (u_hint_base): for every WG_SIZE keys of a component, the
// level-2 node of the first (written by the down-sweep of level 2,
// hp_down_children), so that a traversal searches only the nodes between two
// hints.
#ifdef HP_COHERENT
layout(std430, binding = BIND_HP) coherent restrict buffer Hp { uvec2 hp[]; };
#else
layout(std430, binding = BIND_HP) restrict buffer Hp { uvec2 hp[]; };
#endif
uniform uint u_hp_off[16];
uniform int u_hp_top;
uniform uint u_pre_base; // prefix sums (hp_top.comp, hp_downsweep.comp) start here
uniform uint u_hp_n2;    // real level-2 nodes
uniform uint u_hint_base; // the hints start here: uvec2(triangles, vertices) per WG_SIZE keys
uniform uint u_hint_n;    // hints held (the capacities' keys)

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

// The level-2 node of output key (component comp): the last in [lo, hi]
// whose down-swept prefix is <= key (an empty node shares its prefix with
// the next), the caller knowing it is there; below gets that prefix.  A
// binary search of the prefixes, each step without a branch (a SIMD driver
// runs a divergent loop as long as its slowest lane).  The exponent is
// counted down: a step halved each turn, 17 turns from 65 537 nodes on,
// came out wrong under Mesa 22.3's llvmpipe.
uint hp_node(uint key, int comp, uint lo, uint hi, out uint below)
{
	uint base = u_pre_base + u_hp_off[2], i = lo;
	for (int s = findMSB(hi - lo); s >= 0; --s) { // findMSB(0u) = -1: no step
		uint m = i + (1u << uint(s));
		bool right = m <= hi && hp[base + min(m, hi)][comp] <= key;
		i = right ? m : i;
	}
	below = hp[base + i][comp];
	return i;
}

// The down-sweep, a parent at a time (hp_downsweep.comp, hp_top.comp): the
// prefix sums of the four children of node p of level k + 1, pre(child) =
// pre(p) + the counts of its left siblings (their four counts are read
// once, where a node at a time read them four times over).  Level 2's also
// write the hints: every multiple of WG_SIZE among p's outputs of each
// kind is hinted to the child that holds it (the last whose prefix is at
// most it, as the search finds it).
void hp_down_children(int k, uint p)
{
	uvec2 pre = hp[u_pre_base + u_hp_off[k + 1] + p];
	uint c = u_hp_off[k] + 4u * p;
	uvec2 p1 = pre + hp[c], p2 = p1 + hp[c + 1u], p3 = p2 + hp[c + 2u];
	hp[u_pre_base + c] = pre;
	hp[u_pre_base + c + 1u] = p1;
	hp[u_pre_base + c + 2u] = p2;
	hp[u_pre_base + c + 3u] = p3;
	if (k != 2)
		return;
	uvec2 end = p3 + hp[c + 3u];
	if (end == pre) // most parents: empty
		return;
	for (int comp = 0; comp < 2; ++comp)
		for (uint h = (pre[comp] + uint(WG_SIZE) - 1u) / uint(WG_SIZE); h * uint(WG_SIZE) < end[comp] && h < u_hint_n;
		     ++h) {
			uint key = h * uint(WG_SIZE);
			hp[u_hint_base + h][comp] = 4u * p + uint(key >= p1[comp]) + uint(key >= p2[comp]) + uint(key >= p3[comp]);
		}
}

// Output number key (< count, the keys written) of component comp (0
// triangles, 1 vertices) -> the cell that emits it and its rank among that
// cell's outputs: the level-2 node searched between the hints of its
// WG_SIZE keys and of the next (the same-field benchmark's fBm at 128^3:
// 11 nodes apart, a median; four steps where all 134 000 nodes took 18),
// then its word and byte.
void hp_traverse(uint key, int comp, uint count, out uint cell, out uint rank)
{
	uint k = key / uint(WG_SIZE), below;
	// (keys past the hints held, a target's capacity over the pipeline's:
	// every node)
	uint lo = k < u_hint_n ? hp[u_hint_base + k][comp] : 0u;
	uint hi = (k + 1u) * uint(WG_SIZE) < count && k + 1u < u_hint_n ? hp[u_hint_base + k + 1u][comp] : u_hp_n2 - 1u;
	uint i = hp_node(key, comp, lo, hi, below);
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
