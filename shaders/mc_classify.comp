// isoterra — classify every owner cell from the density pass's sign bits:
// triangle count from the case byte (corner bit n = corner n inside) and
// the vertices it owns on edges 3, 0, 8; write HistoPyramid level 0 (packed
// bytes) and level 2 (sums of sixteen; level 1 is not stored, hp.glsl).
// One invocation: 16 owner cells (four level-0 words, one level-2 node).  Per piece of a row (one piece, two where the 16 cross a
// row's end) it reads four runs of sign bits, rows y and y+1 of slabs z and
// z+1, one or two words each: at most one word per cell for rows of 16 cells
// or more.  Cells whose eight corners agree are skipped with a few bit
// operations per piece.
layout(local_size_x = WG_SIZE) in;
#define PASS_READS_SIGNS 1
#include "common.glsl"
#include "hp.glsl"
uniform uint u_level2_nodes; // level 2's padded size (the pads' sums are zero)

// The case byte of cell j of a piece from the runs of rows (y, z) r00,
// (y+1, z) r10, (y, z+1) r01, (y+1, z+1) r11 (corner order as cell_case's).
uint case_of(uint j, uint r00, uint r10, uint r01, uint r11)
{
	uint a = r00 >> j, b = r10 >> j, c = r01 >> j, d = r11 >> j;
	return (a & 1u) | ((b & 1u) << 1) | ((b & 2u) << 1) | ((a & 2u) << 2) | ((c & 1u) << 4) | ((d & 1u) << 5) |
	       ((d & 2u) << 5) | ((c & 2u) << 6);
}

// The bytes of n cells of one row from owner cell c on, or-ed into w at
// byte p (of the invocation's 16).
void piece(ivec3 c, uint n, uint p, inout uvec4 w)
{
	uint len = n + 1u;
	uint r00 = sign_run(sign_bit_index(c), len);
	uint r10 = sign_run(sign_bit_index(c + ivec3(0, 1, 0)), len);
	uint r01 = sign_run(sign_bit_index(c + ivec3(0, 0, 1)), len);
	uint r11 = sign_run(sign_bit_index(c + ivec3(0, 1, 1)), len);
	uint any4 = r00 | r10 | r01 | r11, all4 = r00 & r10 & r01 & r11;
	uint mixed = ((any4 | (any4 >> 1)) & ~(all4 & (all4 >> 1))) & ((1u << n) - 1u);
	if (mixed == 0u)
		return; // every corner of the piece inside, or every one outside
	uint ex = r00 ^ (r00 >> 1), ey = r00 ^ r10, ez = r00 ^ r01; // owned edges cross
	bool yz_tris = c.y < u_cells.y && c.z < u_cells.z;
	do {
		uint j = uint(findLSB(mixed));
		mixed &= mixed - 1u;
		int x = c.x + int(j);
		uint tris = 0u;
		if (yz_tris && x < u_cells.x)
			tris = mc_tricount(int(case_of(j, r00, r10, r01, r11)));
		uint m = (x < u_cells.x ? (ex >> j) & 1u : 0u) | (c.y < u_cells.y ? ((ey >> j) & 1u) << 1 : 0u) |
			 (c.z < u_cells.z ? ((ez >> j) & 1u) << 2 : 0u);
		uint q = p + j;
		w[q >> 2] |= (tris | (m << 3)) << (8u * (q & 3u));
	} while (mixed != 0u);
}

void main()
{
	uint g = lin_id();
	if (g >= u_level2_nodes)
		return;
	uvec4 w = uvec4(0u);
	ivec3 o = u_cells + 1;
	uint owners = uint(o.x * o.y * o.z);
	uint first = 16u * g, end = min(first + 16u, owners);
	// the first piece's cell by a division, the next ones' (the start of
	// the next row or slab) by counting on
	ivec3 c = cell_of(int(first), o);
	for (uint cell = first; cell < end;) {
		uint n = min(end - cell, uint(o.x - c.x));
		piece(c, n, cell - first, w);
		cell += n;
		c = c.y + 1 < o.y ? ivec3(0, c.y + 1, c.z) : ivec3(0, 0, c.z + 1);
	}
	// the four level-0 words, two a uvec2 of the pyramid's buffer (zero
	// past the grid's last cell), and their sums at level 2
	if (g < u_hp_n2) {
		hp[2u * g] = w.xy;
		hp[2u * g + 1u] = w.zw;
	}
	uvec2 sum2 = uvec2(0u);
	for (uint k = 0u; k < 4u; ++k)
		sum2 += uvec2(word_count(w[k], 0), word_count(w[k], 1));
	hp[u_hp_off[2] + g] = sum2;
}
