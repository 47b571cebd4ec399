// isoterra — HistoPyramid down-sweep: the exclusive prefix sum of every
// node (outputs of all nodes before it at its level), from the top down:
// pre(node) = pre(parent) + counts of its left siblings.  Stored after the
// pyramid (offset u_pre_base) so the index pass finds a cell's first vertex
// with a few loads instead of a walk up every level.
layout(local_size_x = WG_SIZE) in;
#include "common.glsl"
#include "hp.glsl"
uniform int u_level;   // level being written (top-1 .. 2)
uniform uint u_count;  // real nodes at this level

void main()
{
	uint i = lin_id();
	if (i >= u_count)
		return;
	uint base = u_hp_off[u_level];
	uvec2 s = hp[u_pre_base + u_hp_off[u_level + 1] + (i >> 2)];
	for (uint m = i & ~3u; m < i; ++m)
		s += hp[base + m];
	hp[u_pre_base + base + i] = s;
}
