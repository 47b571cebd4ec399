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

// Four cells of one row at once: the 5x2x2 corners they touch are loaded
// once (20 loads instead of 44).
uint row_bytes(ivec3 c)
{
	uint in_bits = 0u; // bit (x + 5*(y + 2*z)) = corner inside
	for (int z = 0; z < 2; ++z)
		for (int y = 0; y < 2; ++y)
			for (int x = 0; x < 5; ++x)
				in_bits |= uint(D(c + ivec3(x, y, z)) > u_iso) << uint(x + 5 * (y + 2 * z));
	uint w = 0u;
	for (int j = 0; j < 4; ++j) {
		ivec3 q = c + ivec3(j, 0, 0);
		uint tris = 0u;
		if (all(lessThan(q, u_cells))) {
			uint cs = 0u;
			for (int n = 0; n < 8; ++n) {
				ivec3 o = mc_corner[n].xyz;
				cs |= ((in_bits >> uint(j + o.x + 5 * (o.y + 2 * o.z))) & 1u) << uint(n);
			}
			tris = mc_tricount[cs];
		}
		uint b0 = (in_bits >> uint(j)) & 1u;
		uint m = 0u;
		if (q.x < u_cells.x && b0 != ((in_bits >> uint(j + 1)) & 1u))
			m |= 1u;
		if (q.y < u_cells.y && b0 != ((in_bits >> uint(j + 5)) & 1u))
			m |= 2u;
		if (q.z < u_cells.z && b0 != ((in_bits >> uint(j + 10)) & 1u))
			m |= 4u;
		w |= (tris | (m << 3)) << (8u * uint(j));
	}
	return w;
}

void main()
{
	uint g = lin_id();
	if (g >= u_words_padded)
		return;
	uint w = 0u;
	uvec2 sum = uvec2(0u);
	if (g < u_words) {
		ivec3 o = u_cells + 1;
		int cell = int(4u * g);
		ivec3 c = ivec3(cell % o.x, (cell / o.x) % o.y, cell / (o.x * o.y));
		if (c.x + 3 < o.x && cell + 3 < o.x * o.y * o.z) {
			w = row_bytes(c);
		} else {
			for (uint j = 0u; j < 4u; ++j)
				w |= cell_byte(4u * g + j) << (8u * j);
		}
		for (uint j = 0u; j < 4u; ++j) {
			uint b = (w >> (8u * j)) & 255u;
			sum += uvec2(b & 7u, uint(bitCount(b >> 3)));
		}
		hp_l0[g] = w;
	}
	hp[u_hp_off[1] + g] = sum;
}
