// isoterra — classify every owner cell: triangle count from the case byte
// (corner bit n = corner n inside) and the vertices it owns on edges 3, 0, 8;
// write HistoPyramid level 0 (packed bytes) and level 1 (sums of four).
layout(local_size_x = 64) in;
#include "common.glsl"
#include "hp.glsl"
uniform uint u_words;   // real level-0 words: ceil(owner cells / 4)
uniform uint u_words_padded;

uint cell_byte(uint cell)
{
	ivec3 o = u_cells + 1;
	if (cell >= uint(o.x * o.y * o.z))
		return 0u;
	ivec3 c = ivec3(int(cell) % o.x, (int(cell) / o.x) % o.y, int(cell) / (o.x * o.y));
	uint tris = 0u;
	if (all(lessThan(c, u_cells)))
		tris = mc_tricount[cell_case(c)];
	bool in0 = D(c) > u_iso;
	uint m = 0u;
	if (c.x < u_cells.x && c.y <= u_cells.y && c.z <= u_cells.z && in0 != (D(c + ivec3(1, 0, 0)) > u_iso))
		m |= 1u;
	if (c.y < u_cells.y && c.x <= u_cells.x && c.z <= u_cells.z && in0 != (D(c + ivec3(0, 1, 0)) > u_iso))
		m |= 2u;
	if (c.z < u_cells.z && c.x <= u_cells.x && c.y <= u_cells.y && in0 != (D(c + ivec3(0, 0, 1)) > u_iso))
		m |= 4u;
	return tris | (m << 3);
}

void main()
{
	uint g = lin_id();
	if (g >= u_words_padded)
		return;
	uint w = 0u;
	uvec2 sum = uvec2(0u);
	if (g < u_words) {
		for (uint j = 0u; j < 4u; ++j) {
			uint b = cell_byte(4u * g + j);
			w |= b << (8u * j);
			sum += uvec2(b & 7u, uint(bitCount(b >> 3)));
		}
		hp_l0[g] = w;
	}
	hp[u_hp_off[1] + g] = sum;
}
