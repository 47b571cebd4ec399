// isoterra — a mesh's indirect draw command split into parts of at most
// u_part indices (vertices, for a mesh without indices), one command a
// part (app/render/parts.c).  A software rasterizer bins every triangle of
// a draw before it rasterizes any; the renderer finishes each part before
// it draws the next, so only one part's bins are held at a time.  The
// parts draw the same triangles in the same order; those past the end of
// the mesh draw nothing.
layout(local_size_x = WG_SIZE) in;
layout(std430, binding = BIND_STATUS) readonly restrict buffer Src { uint src[]; };
layout(std430, binding = BIND_AUX_OUT) writeonly restrict buffer Parts { uint parts[]; };
uniform uint u_src;    // the command's first word in Src
uniform uint u_part;   // indices (vertices) a part
uniform uint u_parts;  // parts to write
uniform int u_indexed; // 1: DrawElementsIndirectCommand, 0: DrawArraysIndirectCommand

void main()
{
	uint i = gl_GlobalInvocationID.x;
	if (i >= u_parts)
		return;
	uint count = src[u_src];
	uint done = min(count, i * u_part);
	uint o = 5u * i;
	parts[o] = min(count - done, u_part);
	parts[o + 1u] = src[u_src + 1u];        // instances
	parts[o + 2u] = src[u_src + 2u] + done; // first index (vertex)
	// the base vertex and base instance; an array command's fourth word
	// must be zero
	parts[o + 3u] = u_indexed != 0 ? src[u_src + 3u] : 0u;
	parts[o + 4u] = u_indexed != 0 ? src[u_src + 4u] : 0u;
}
