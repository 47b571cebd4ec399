// isoterra — density pass: the density function at every corner of the grid
// plus a one-sample margin (for gradients).
#define DENSITY_WRITER 1
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#include "common.glsl"
#include "density.glsl"
layout(std430, binding = BIND_DENSITY) restrict writeonly buffer DensOut { float dens_out[]; };
uniform float u_density_bias; // subtracted (coarse LOD blocks erode a little)

void main()
{
	ivec3 dim = dens_dims();
	ivec3 id = ivec3(gl_GlobalInvocationID);
	if (any(greaterThanEqual(id, dim)))
		return;
	vec3 ws = u_origin + vec3(u_base + id - u_margin) * u_cell;
	float d = density(ws) - u_density_bias;
	if (u_closed != 0) {
		// air on the border corners (walls where the box cuts rock) and
		// clearly air in the margin (so the walls' gradients point out)
		ivec3 lo = ivec3(u_margin), hi = dim - 1 - u_margin;
		if (any(lessThan(id, lo)) || any(greaterThan(id, hi)))
			d = min(d, u_iso - u_cell);
		else if (any(equal(id, lo)) || any(equal(id, hi)))
			d = min(d, u_iso - 1e-3 * u_cell);
	}
	dens_out[id.x + dim.x * (id.y + dim.y * id.z)] = d;
}
