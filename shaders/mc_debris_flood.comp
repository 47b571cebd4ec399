// isoterra — the debris filter's second pass: the words mc_debris.comp
// listed (abi.h DL_*), each with its candidates, samples that may belong
// to a component of inside samples spanning at most three samples along
// each axis.  For each candidate the 7x7x7 box of raw bits around it (49
// runs) and the growth of its component within the box (debris_island);
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
#include "debris_island.glsl"
layout(std430, binding = BIND_SIGNS_OUT) restrict buffer Filtered { uint filtered[]; };
layout(std430, binding = BIND_DEBRIS) restrict readonly buffer Candidates { uint dl[]; };
uniform uint u_sign_words; // the sign buffers' capacity in words
#include "debris_bits.glsl"

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
			// its row's samples dx = -3 .. 3 that exist
			uint xmask = bits_below(yx.y - 3, r) & ~bits_below(yx.y - 3, 0) & 0x7Fu;
			uint box[49];
			for (int dz = 0; dz < 7; dz++)
				for (int dy = 0; dy < 7; dy++) {
					int yy = yx.x + dy - 3;
					box[dz * 7 + dy] =
						yy < 0 || yy >= dim.y ? 0u : slab_run(z + dz - 3, yy * r + yx.y - 3, n, words) & xmask;
				}
			if (debris_island(box))
				drop |= 1u << uint(j);
		}
		if (drop != 0u && wi < u_sign_words)
			filtered[wi] &= ~drop;
	}
}
