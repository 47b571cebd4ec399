// isoterra — comparison method: stream compaction by atomic-counter append.
// Each cell reserves its triangles with one atomicAdd and writes unshared
// vertices (3 per triangle, non-indexed); order is not deterministic.
layout(local_size_x = WG_SIZE) in;
#define PASS_CASE_FROM_SIGNS 1 // the cases from the debris filter's sign bits, the vertices from the densities
#include "common.glsl"
#include "mc_status.glsl"
#include "vertex.glsl"
layout(std430, binding = BIND_VERTICES) restrict writeonly buffer Verts { Vertex verts[]; };

void main()
{
	uint id = lin_id();
	uint ncells = uint(u_cells.x * u_cells.y * u_cells.z);
	if (id >= ncells)
		return;
	ivec3 c = ivec3(int(id) % u_cells.x, (int(id) / u_cells.x) % u_cells.y, int(id) / (u_cells.x * u_cells.y));
	int cs = cell_case(c);
	uint n = mc_tricount(int(cs));
	if (n == 0u)
		return;
	uint base = atomicAdd(st[ST_APPEND_COUNTER], n);
	for (uint r = 0u; r < n; ++r) {
		uint t = base + r;
		if (t >= u_tri_cap)
			return;
		for (int k = 0; k < 3; ++k) {
			ivec4 eo = mc_edge_owner[mc_tri(cs, int(r) * 3 + k)];
			vec4 p, nr;
			edge_vertex(c + eo.xyz, eo.w, p, nr);
			verts[3u * t + uint(k)] = Vertex(p.xyz, pack_vertex_word(nr.xyz, 1.0, 1.0));
		}
	}
}
