// isoterra — the debris filter's second pass: the words mc_debris.comp
// listed (abi.h DL_*), each with its candidates, samples that may belong
// to a component of inside samples spanning at most DEBRIS_SPAN samples
// along each axis (abi.h).  For each candidate the box of raw bits around
// it (DEBRIS_BOX^2 runs, read as the growth reaches them) and the growth
// of its component within the box (debris_island);
// debris leaves the filtered bits.  A listed word is one entry, so an
// invocation owns its word of the filtered bits.  Rare work (200
// candidates in the same-field benchmark's 128^3 grid), kept out of the
// first pass: its box and growth there, even never run, cost llvmpipe
// 5 ms a 128^3 grid.
// Dispatched from the list's header (no read-back); the entries past the
// dispatch's invocations are taken in strides.
layout(local_size_x = WG_SIZE) in;
#define PASS_READS_SIGNS 1 // common.glsl's Signs (BIND_SIGNS): the raw bits
#include "common.glsl"
layout(std430, binding = BIND_SIGNS_OUT) restrict buffer Filtered { uint filtered[]; };
layout(std430, binding = BIND_DEBRIS) restrict readonly buffer Candidates { uint dl[]; };
uniform uint u_sign_words; // the sign buffers' capacity in words
#include "debris_bits.glsl"

// the candidate whose box debris_island reads: its slab, y, x, the row
// bits that exist
int b_z, b_y, b_x, b_n, b_r, b_dimy;
uint b_words, b_xmask;
// a row of the box: its inside samples that are candidates in bits 0 ..
// B - 1, those that are not in bits 16 .. 15 + B
uint debris_box_row(int dz, int dy)
{
	int yy = b_y + dy - DEBRIS_SPAN;
	if (yy < 0 || yy >= b_dimy)
		return 0u;
	int zz = b_z + dz - DEBRIS_SPAN, start = yy * b_r + b_x - DEBRIS_SPAN;
	uint inside = src_slab_run(zz, start, b_n, b_words, 0) & b_xmask, cand = src_slab_run(zz, start, b_n, b_words, 1);
	return (inside & cand) | ((inside & ~cand) << 16u);
}
#include "debris_island.glsl"

void main()
{
	ivec3 dim = dens_dims();
	int n = dim.x * dim.y, r = dim.x;
	uint words = sign_slab_bits() / 32u;
	uint count = dl[DL_COUNT], stride = gl_NumWorkGroups.x * uint(WG_SIZE);
	for (uint e = gl_WorkGroupID.x * uint(WG_SIZE) + gl_LocalInvocationID.x; e < count; e += stride) {
		uint wi = dl[DL_HEAD + 2u * e], cand = dl[DL_HEAD + 2u * e + 1u];
		int z = int(wi / words), b0 = int(wi % words) * 32;
		uint drop = 0u;
		while (cand != 0u) {
			int j = findLSB(cand);
			cand &= cand - 1u;
			ivec2 yx = divmod(b0 + j, r); // the sample's y, x in its slab
			// its row's samples dx = -S .. S that exist
			const int S = DEBRIS_SPAN, B = DEBRIS_BOX;
			b_z = z;
			b_y = yx.x;
			b_x = yx.y;
			b_n = n;
			b_r = r;
			b_dimy = dim.y;
			b_words = words;
			b_xmask = bits_below(yx.y - S, r) & ~bits_below(yx.y - S, 0) & ((1u << uint(B)) - 1u);
			if (debris_island())
				drop |= 1u << uint(j);
		}
		if (drop != 0u && wi < u_sign_words)
			filtered[wi] &= ~drop;
	}
}
