// isoterra — read the pyramid's totals on the GPU, clamp them to the output
// capacities and write the indirect dispatch and draw commands (no CPU
// read-back in the frame loop).
layout(local_size_x = 1) in;
#include "common.glsl"
#include "hp.glsl"
#include "mc_status.glsl"

void main()
{
	uvec2 total = hp[u_hp_off[u_hp_top]];
	st_write_counts(total.x, total.y);
}
