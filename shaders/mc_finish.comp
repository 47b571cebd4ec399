// isoterra — after atomic append or no compaction: clamp the appended count
// to the capacity and write the DrawArraysIndirect command.
layout(local_size_x = 1) in;
#include "common.glsl"
#include "mc_status.glsl"
uniform int u_nocompact;

void main()
{
	uint tris = st[27];
	st_write_counts(tris, 3u * tris);
	if (u_nocompact != 0) {
		uint ncells = uint(u_cells.x * u_cells.y * u_cells.z);
		st[16] = 15u * ncells;
		st[22] = 5u * ncells;
		st[23] = 15u * ncells;
		st[26] = 0u;
	}
}
