// isoterra — generate each shared vertex once: search the vertex pyramid to
// find the owner cell and which of its edges (3, 0, 8 = +x, +y, +z) it is.
#ifndef FIELD_PASS_VERTICES // in a field's program common.glsl declares it first
layout(local_size_x = WG_SIZE) in;
#endif
#include "common.glsl"
#include "hp.glsl"
#include "mc_status.glsl"
#ifdef WITH_AO
#include "ao.glsl" // reads the field: compiled as part of the field's program (FIELD_PASS_VERTICES)
#endif
#ifdef WITH_SUN
#include "sun.glsl" // the same
#endif
#include "vertex.glsl"
layout(std430, binding = BIND_VERTICES) restrict writeonly buffer Verts { Vertex verts[]; };

void main()
{
	uint v = lin_id();
	if (v >= st[ST_VERTS_WRITTEN])
		return;
	uint cell, rank;
	hp_traverse(v, 1, st[ST_VERTS_WRITTEN], cell, rank);
	uint m = l0_byte(cell) >> 3;
	int axis = 0;
	for (; axis < 2; ++axis) {
		if ((m & (1u << axis)) != 0u) {
			if (rank == 0u)
				break;
			rank--;
		}
	}
	ivec3 o = u_cells + 1;
	ivec3 c = cell_of(int(cell), o);
	vec4 p, n;
	edge_vertex(c, axis, p, n);
#ifdef WITH_AO
	n.w = ao_visibility(p.xyz, n.xyz);
#else
	n.w = 1.0;
#endif
#ifdef WITH_SUN
	float sun = sun_visibility(p.xyz, n.xyz);
#else
	float sun = 1.0;
#endif
	verts[v] = Vertex(p.xyz, pack_vertex_word(n.xyz, n.w, sun));
}
