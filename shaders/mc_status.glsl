// isoterra — the status / indirect command buffer (binding 6).
//   [0..4]   DrawElementsIndirectCommand {count, instances, first, baseVertex, baseInstance}
//   [8..10]  DispatchIndirectCommand for the vertex pass
//   [12..14] DispatchIndirectCommand for the triangle pass
//   [16..19] DrawArraysIndirectCommand {count, instances, first, baseInstance}
//   [20] triangles needed  [21] vertices needed  [22] triangles written
//   [23] vertices written  [24] triangle capacity [25] vertex capacity
//   [26] overflow flag     [27] atomic append counter (triangles)
layout(std430, binding = 6) restrict buffer Status { uint st[32]; };
uniform uint u_tri_cap;
uniform uint u_vert_cap;
uniform uint u_max_groups; // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0] we may use
uniform uint u_first_index; // where this mesh's indices start in the element buffer
uniform uint u_base_vertex; // added to its indices when drawn

uvec3 groups_for(uint n)
{
	uint g = (n + 63u) / 64u;
	if (g == 0u)
		return uvec3(0u, 1u, 1u);
	uint gx = min(g, u_max_groups);
	return uvec3(gx, (g + gx - 1u) / gx, 1u);
}

void st_write_counts(uint tris_needed, uint verts_needed)
{
	uint tris = min(tris_needed, u_tri_cap);
	uint verts = min(verts_needed, u_vert_cap);
	st[0] = 3u * tris;
	st[1] = 1u;
	st[2] = u_first_index;
	st[3] = u_base_vertex;
	st[4] = 0u;
	uvec3 gv = groups_for(verts), gt = groups_for(tris);
	st[8] = gv.x; st[9] = gv.y; st[10] = gv.z;
	st[12] = gt.x; st[13] = gt.y; st[14] = gt.z;
	st[16] = 3u * tris;
	st[17] = 1u;
	st[18] = 0u;
	st[19] = 0u;
	st[20] = tris_needed;
	st[21] = verts_needed;
	st[22] = tris;
	st[23] = verts;
	st[24] = u_tri_cap;
	st[25] = u_vert_cap;
	st[26] = (tris < tris_needed || verts < verts_needed) ? 1u : 0u;
}
