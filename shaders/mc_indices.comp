// isoterra — generate the triangles: find each one's emitting cell in the
// triangle pyramid (hp.glsl hp_traverse), look up its case's edges and turn
// each edge into the index of the vertex its owner cell generated (prefix
// sum of the vertex pyramid).
layout(local_size_x = WG_SIZE) in;
#define PASS_READS_SIGNS 1 // the cell's case from four runs of sign bits
#include "common.glsl"
#include "hp.glsl"
#include "mc_status.glsl"
layout(std430, binding = BIND_INDICES) restrict writeonly buffer Indices { uint idx[]; };

void main()
{
	uint t = lin_id();
	if (t >= st[ST_TRIS_WRITTEN])
		return;
	uint cell, rank;
	hp_traverse(t, 0, st[ST_TRIS_WRITTEN], cell, rank);
	ivec3 o = u_cells + 1;
	ivec3 c = cell_of(int(cell), o);
	int cs = cell_case(c);
	uint vcount = st[ST_VERTS_WRITTEN];
	uint ids[3];
	bool ok = true;
	for (int k = 0; k < 3; ++k) {
		int e = mc_tri(cs, int(rank) * 3 + k);
		ivec4 eo = mc_edge_owner[e];
		ivec3 q = c + eo.xyz;
		uint qc = uint(q.x + o.x * (q.y + o.y * q.z));
		uint w;
		uint first = hp_prefix_w(qc, 1, w); // and the owner's word, for its byte
		uint m = (w >> (8u * (qc & 3u) + 3u)) & 7u;
		ids[k] = first + uint(bitCount(m & ((1u << uint(eo.w)) - 1u)));
		ok = ok && ids[k] < vcount;
	}
	// a triangle whose vertices fell past the vertex capacity degenerates
	idx[3u * t + 0u] = ok ? ids[0] : 0u;
	idx[3u * t + 1u] = ok ? ids[1] : 0u;
	idx[3u * t + 2u] = ok ? ids[2] : 0u;
}
