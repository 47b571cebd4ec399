// isoterra — HistoPyramid down-sweep: the exclusive prefix sum of every
// node (outputs of all nodes before it at its level), from the top down:
// pre(node) = pre(parent) + counts of its left siblings, an invocation a
// parent (hp.glsl hp_down_children; level 2's also write the traversal's
// hints).  Stored after the pyramid (offset u_pre_base) so the index pass
// finds a cell's first vertex with a few loads instead of a walk up every
// level.
layout(local_size_x = WG_SIZE) in;
#include "common.glsl"
#include "hp.glsl"
uniform int u_level;   // level being written (top-1 .. 2)
uniform uint u_count;  // real nodes at the level above: an invocation each

void main()
{
	uint p = lin_id();
	if (p < u_count)
		hp_down_children(u_level, p);
}
