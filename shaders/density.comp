// isoterra — density pass: the density function at every corner of the grid
// plus a one-sample margin (for gradients).
#define DENSITY_WRITER 1
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "common.glsl"
#include "density.glsl"
layout(std430, binding = 0) restrict writeonly buffer DensOut { float dens_out[]; };

void main()
{
	ivec3 dim = u_cells + 3;
	ivec3 id = ivec3(gl_GlobalInvocationID);
	if (any(greaterThanEqual(id, dim)))
		return;
	vec3 ws = u_origin + vec3(id - 1) * u_cell;
	dens_out[id.x + dim.x * (id.y + dim.y * id.z)] = density(ws);
}
