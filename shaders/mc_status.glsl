// isoterra — the status / indirect command buffer; its words are named in
// app/gpu/abi.h (ST_*), shared with the host.
layout(std430, binding = BIND_STATUS) restrict buffer Status { uint st[ST_WORDS]; };
uniform uint u_tri_cap;
uniform uint u_vert_cap;
uniform uint u_max_groups; // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0] we may use
uniform uint u_first_index; // where this mesh's indices start in the element buffer
uniform uint u_base_vertex; // added to its indices when drawn

uvec3 groups_for(uint n)
{
	uint g = (n + uint(WG_SIZE) - 1u) / uint(WG_SIZE);
	if (g == 0u)
		return uvec3(0u, 1u, 1u);
	uint gx = min(g, u_max_groups);
	return uvec3(gx, (g + gx - 1u) / gx, 1u);
}

void st_write_counts(uint tris_needed, uint verts_needed)
{
	uint tris = min(tris_needed, u_tri_cap);
	uint verts = min(verts_needed, u_vert_cap);
	st[ST_DRAW_ELEMENTS + 0] = 3u * tris; // count
	st[ST_DRAW_ELEMENTS + 1] = 1u;       // instances
	st[ST_DRAW_ELEMENTS + 2] = u_first_index;
	st[ST_DRAW_ELEMENTS + 3] = u_base_vertex;
	st[ST_DRAW_ELEMENTS + 4] = 0u;       // base instance
	uvec3 gv = groups_for(verts), gt = groups_for(tris);
	st[ST_DISPATCH_VERTS + 0] = gv.x; st[ST_DISPATCH_VERTS + 1] = gv.y; st[ST_DISPATCH_VERTS + 2] = gv.z;
	st[ST_DISPATCH_TRIS + 0] = gt.x; st[ST_DISPATCH_TRIS + 1] = gt.y; st[ST_DISPATCH_TRIS + 2] = gt.z;
	st[ST_DRAW_ARRAYS + 0] = 3u * tris;
	st[ST_DRAW_ARRAYS + 1] = 1u;
	st[ST_DRAW_ARRAYS + 2] = 0u;
	st[ST_DRAW_ARRAYS + 3] = 0u;
	st[ST_TRIS_NEEDED] = tris_needed;
	st[ST_VERTS_NEEDED] = verts_needed;
	st[ST_TRIS_WRITTEN] = tris;
	st[ST_VERTS_WRITTEN] = verts;
	st[ST_TRI_CAP] = u_tri_cap;
	st[ST_VERT_CAP] = u_vert_cap;
	st[ST_OVERFLOW] = (tris < tris_needed || verts < verts_needed) ? 1u : 0u;
}
