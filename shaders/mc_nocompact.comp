// isoterra — comparison method: no compaction.  Every cell writes its 15
// vertex slots (5 triangles); unused slots become degenerate triangles.
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
	if (n != 0u)
		atomicAdd(st[ST_APPEND_COUNTER], n);
	vec4 zero = vec4(u_origin, 1.0);
	for (uint r = 0u; r < 5u; ++r) {
		for (int k = 0; k < 3; ++k) {
			vec4 p = zero, nr = vec4(0.0, 1.0, 0.0, 0.0);
			if (r < n) {
				ivec4 eo = mc_edge_owner[mc_tri(cs, int(r) * 3 + k)];
				edge_vertex(c + eo.xyz, eo.w, p, nr);
			}
			verts[15u * id + 3u * r + uint(k)] = Vertex(p.xyz, pack_vertex_word(nr.xyz, 1.0, 1.0));
		}
	}
}
