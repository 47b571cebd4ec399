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
layout(std430, binding = BIND_HP) restrict buffer Hp { uvec2 hp[]; };
uniform uint u_hp_off[16];
uniform int u_hp_top;
uniform uint u_pre_base; // prefix sums (hp_downsweep.comp) start here

// level-0 word i (four owner cells)
uint hp_l0(uint i) { return hp[i >> 1u][i & 1u]; }
uint l0_byte(uint cell) { return (hp_l0(cell >> 2) >> (8u * (cell & 3u))) & 255u; }
uint byte_count(uint b, int comp) { return comp == 0 ? (b & 7u) : uint(bitCount(b >> 3)); }

// Output number key of component comp (0 triangles, 1 vertices) -> the cell
// that emits it and its rank among that cell's outputs.
void hp_traverse(uint key, int comp, out uint cell, out uint rank)
{
	uint i = 0u;
	int k = u_hp_top;
	if (k >= 2) {
		do { // tested at the end: no masked level after the last (fractal.glsl)
			uint base = u_hp_off[k - 1] + 4u * i;
			uint j = 0u;
			for (; j < 3u; ++j) {
				uint c = hp[base + j][comp];
				if (key < c)
					break;
				key -= c;
			}
			i = 4u * i + j;
		} while (--k >= 2);
	}
	uint w = hp_l0(i);
	uint j = 0u;
	for (; j < 3u; ++j) {
		uint c = byte_count((w >> (8u * j)) & 255u, comp);
		if (key < c)
			break;
		key -= c;
	}
	cell = 4u * i + j;
	rank = key;
}

// Number of outputs of component comp emitted by cells before `cell`, from
// the down-swept prefix sums of level 2 (valid after hp_downsweep.comp)
// plus the left siblings at level 1 and the bytes before it in its word.
uint hp_prefix_fast(uint cell, int comp)
{
	uint i = cell >> 2;
	uint w = hp_l0(i);
	uint sum = 0u;
	if (u_hp_top >= 2) {
		sum = hp[u_pre_base + u_hp_off[2] + (i >> 2)][comp];
		for (uint m = i & ~3u; m < i; ++m)
			sum += hp[u_hp_off[1] + m][comp];
	}
	for (uint j = 0u; j < (cell & 3u); ++j)
		sum += byte_count((w >> (8u * j)) & 255u, comp);
	return sum;
}

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
