// isoterra — grid uniforms and helpers shared by the extraction passes, and
// the engine's side of the field seam (app/extract/field.h): a field's
// program includes this file first and defines  float density(vec3 ws);
// compiled with FIELD_PASS_DENSITY, this file gives it the density pass.

// A field's program: its work group comes first (lin_id() needs it).
#if defined(FIELD_PASS_DENSITY)
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
#elif defined(FIELD_PASS_VERTICES)
layout(local_size_x = 64) in; // mc_vertices.comp's
#endif

uniform ivec3 u_cells;   // cells per axis
uniform vec3 u_origin;   // world position of global corner (0,0,0)
uniform float u_cell;    // world size of a cell
uniform ivec3 u_base;    // global index of this grid's corner (0,0,0)
uniform int u_margin;    // density samples kept around the corners (>= 1)

ivec3 dens_dims() { return u_cells + 1 + 2 * u_margin; }

// 1D invocation index over a (possibly 2D-split) dispatch of 64-wide groups.
uint lin_id()
{
	return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x +
	       gl_LocalInvocationID.x;
}

#ifdef FIELD_PASS_DENSITY
// The density pass: the field at every corner of the grid plus the margin
// (for gradients, and the ambient-occlusion rays of world blocks).
float density(vec3 ws); // the field's
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
#else // every other pass reads the densities
layout(std430, binding = BIND_DENSITY) restrict readonly buffer Dens { float dens[]; };
// density at corner c (each component -1 .. n+1)
float D(ivec3 c)
{
	ivec3 d = dens_dims();
	c += u_margin;
	return dens[c.x + d.x * (c.y + d.y * c.z)];
}
vec3 grad_at(ivec3 c)
{
	return vec3(D(c + ivec3(1, 0, 0)) - D(c - ivec3(1, 0, 0)),
		    D(c + ivec3(0, 1, 0)) - D(c - ivec3(0, 1, 0)),
		    D(c + ivec3(0, 0, 1)) - D(c - ivec3(0, 0, 1)));
}

// Marching Cubes tables (mc_tables.c), uploaded verbatim.
layout(std430, binding = BIND_MC_TABLES) restrict readonly buffer McTables {
	uint mc_tricount[256];
	int mc_tri[256 * 15];
	ivec4 mc_edge_owner[12]; // owner offset xyz, slot
	ivec4 mc_corner[8];
};

int cell_case(ivec3 c)
{
	int cs = 0;
	for (int n = 0; n < 8; n++)
		cs |= int(D(c + mc_corner[n].xyz) > u_iso) << n;
	return cs;
}

// Vertex on the edge from corner c along axis a (0,1,2): position, normal.
void edge_vertex(ivec3 c, int a, out vec4 pos, out vec4 nrm)
{
	ivec3 c1 = c;
	c1[a] += 1;
	float d0 = D(c), d1 = D(c1);
	float t = (d0 - u_iso) / (d0 - d1);
	vec3 p = vec3(u_base + c);
	p[a] += t;
	pos = vec4(u_origin + p * u_cell, 1.0);
	vec3 g0 = grad_at(c), g1 = grad_at(c1);
	vec3 g = g0 + (g1 - g0) * t;
	float len = length(g);
	nrm = vec4(len > 1e-20 ? -g / len : vec3(0.0, 1.0, 0.0), 1.0); // w: ambient visibility
}
#endif // FIELD_PASS_DENSITY
