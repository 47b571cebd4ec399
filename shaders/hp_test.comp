// isoterra — HistoPyramid test hooks (used by the tests only): build level 2
// from given level-0 words, traverse keys, compute prefix sums.
layout(local_size_x = WG_SIZE) in;
#include "common.glsl"
#include "hp.glsl"
layout(std430, binding = BIND_AUX_OUT) restrict buffer TestOut { uvec2 test_out[]; };
uniform int u_mode;      // 0: level 2 from level 0; 1: traverse; 2: prefix
uniform uint u_n;        // items
uniform uint u_words;
uniform int u_comp;

void main()
{
	uint i = lin_id();
	if (i >= u_n)
		return;
	if (u_mode == 0) { // level 2 (classification's, mc_classify.comp) from the words
		uvec2 s = uvec2(0u);
		for (uint k = 0u; k < 4u; ++k) {
			uint w = 4u * i + k < u_words ? hp_l0(4u * i + k) : 0u;
			s += uvec2(word_count(w, 0), word_count(w, 1));
		}
		hp[u_hp_off[2] + i] = s;
	} else if (u_mode == 1) {
		uint cell, rank;
		hp_traverse(i, u_comp, u_n, cell, rank);
		test_out[i] = uvec2(cell, rank);
	} else {
		test_out[i] = uvec2(hp_prefix(i, u_comp), hp_prefix_fast(i, u_comp));
	}
}
