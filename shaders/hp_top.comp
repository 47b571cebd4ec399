// isoterra — the HistoPyramid's small levels in one work group: the
// reduction from level u_first up to the top, the top's prefix (0), then
// the down-sweep from the top down to level u_down_last, a barrier between
// levels instead of a dispatch each (on a CPU driver a dispatch and its
// barrier cost tens of microseconds, a world block's whole pyramid fits
// here).  The host (histopyramid.c hp_build) picks u_first so that level
// holds at most HP_TOP_NODES nodes: at most six levels up and six down.
// ESSL 3.1 allows barrier() only outside control flow in main(): the
// levels are six steps each, written out; a step past the last level does
// nothing but wait.
layout(local_size_x = WG_SIZE) in;
#define HP_COHERENT 1 // one invocation reads what another wrote, after a barrier
#include "common.glsl"
#include "hp.glsl"
uniform int u_first;     // lowest level reduced here (> u_hp_top: none)
uniform int u_down_last; // lowest level down-swept here (>= 2)
uniform uint u_hp_n[16];   // real nodes per level
uniform uint u_hp_pad[16]; // nodes written per level (padding zeroed)

void reduce_level(int k)
{
	uint src = u_hp_off[k - 1], dst = u_hp_off[k];
	for (uint i = gl_LocalInvocationID.x; i < u_hp_pad[k]; i += uint(WG_SIZE)) {
		uvec2 s = uvec2(0u);
		if (i < u_hp_n[k]) {
			uint c = src + 4u * i;
			s = hp[c] + hp[c + 1u] + hp[c + 2u] + hp[c + 3u];
		}
		hp[dst + i] = s;
	}
}

// hp_downsweep.comp's rule, a parent of level k + 1 an invocation
void down_level(int k)
{
	for (uint p = gl_LocalInvocationID.x; p < u_hp_n[k + 1]; p += uint(WG_SIZE))
		hp_down_children(k, p);
}

#define UP(s)                                   \
	if (u_first + s <= u_hp_top)            \
		reduce_level(u_first + s);      \
	memoryBarrierBuffer();                  \
	barrier();
#define DOWN(s)                                 \
	if (u_hp_top - 1 - s >= u_down_last)    \
		down_level(u_hp_top - 1 - s);   \
	memoryBarrierBuffer();                  \
	barrier();

void main()
{
	UP(0) UP(1) UP(2) UP(3) UP(4) UP(5)
	if (gl_LocalInvocationID.x == 0u)
		hp[u_pre_base + u_hp_off[u_hp_top]] = uvec2(0u);
	// level 2 the top: its one node holds every output, the hints all 0
	if (u_hp_top == 2) {
		uvec2 total = hp[u_hp_off[2]];
		uint keys = max(total.x, total.y);
		for (uint h = gl_LocalInvocationID.x; h * uint(WG_SIZE) < keys && h < u_hint_n; h += uint(WG_SIZE))
			hp[u_hint_base + h] = uvec2(0u);
	}
	memoryBarrierBuffer();
	barrier();
	DOWN(0) DOWN(1) DOWN(2) DOWN(3) DOWN(4) DOWN(5)
}
