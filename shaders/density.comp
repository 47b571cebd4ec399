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
	float d = density(ws);
	if (u_closed != 0) {
		// air on the border corners (walls where the box cuts rock) and
		// clearly air in the margin (so the walls' gradients point out)
		if (any(equal(id, ivec3(0))) || any(equal(id, dim - 1)))
			d = min(d, u_iso - u_cell);
		else if (any(equal(id, ivec3(1))) || any(equal(id, dim - 2)))
			d = min(d, u_iso - 1e-3 * u_cell);
	}
	dens_out[id.x + dim.x * (id.y + dim.y * id.z)] = d;
}
