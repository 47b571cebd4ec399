// isoterra — after atomic append or no compaction: clamp the appended count
// to the capacity and write the DrawArraysIndirect command.
layout(local_size_x = 1) in;
#include "common.glsl"
#include "mc_status.glsl"
uniform int u_nocompact;

void main()
{
	uint tris = st[ST_APPEND_COUNTER];
	st_write_counts(tris, 3u * tris);
	if (u_nocompact != 0) {
		uint ncells = uint(u_cells.x * u_cells.y * u_cells.z);
		st[ST_DRAW_ARRAYS] = 15u * ncells;
		st[ST_TRIS_WRITTEN] = 5u * ncells;
		st[ST_VERTS_WRITTEN] = 15u * ncells;
		st[ST_OVERFLOW] = 0u;
	}
}
