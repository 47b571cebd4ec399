// isoterra — one HistoPyramid reduction: each node is the sum of four
// children (triangles and vertices at once).  Nodes past the level's real
// size (padding up to a multiple of four) are zero.
layout(local_size_x = WG_SIZE) in;
#include "common.glsl"
#include "hp.glsl"
uniform int u_level;      // level being written (>= 2)
uniform uint u_count;     // real nodes at this level
uniform uint u_padded;    // nodes to write (multiple of 4, or 1 at the top)

void main()
{
	uint i = lin_id();
	if (i >= u_padded)
		return;
	uvec2 s = uvec2(0u);
	if (i < u_count) {
		uint src = u_hp_off[u_level - 1] + 4u * i;
		s = hp[src] + hp[src + 1u] + hp[src + 2u] + hp[src + 3u];
	}
	hp[u_hp_off[u_level] + i] = s;
}
