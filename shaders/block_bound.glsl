// isoterra — the streaming world's coarse pre-pass (the extraction engine's
// side; pipeline_bound in app/extract/pipeline.c): GPU Gems 3 ch.1 skips
// blocks with no surface, learnt before their density is paid for.  One
// work group per candidate block: the field's bound (density_bound, the
// field's program) over BOUND_SUB^3 sub-boxes of the block's box, reduced
// to the block's range; the verdict is 1 (all air) or 2 (all rock) only
// when the whole range lies on one side of the iso value, else 0 (may have
// a surface: generate it).  Compiled with FIELD_PASS_BOUND into the field's
// program.
//
// Input (BIND_AUX_IN), two vec4 a block: (box low corner, octaves kept at
// the centres), (box high corner, density bias); output (BIND_AUX_OUT): a
// uint verdict a block.

vec2 density_bound(vec3 c, vec3 e, int keep); // the field's

layout(std430, binding = BIND_AUX_IN) restrict readonly buffer BoundIn { vec4 bound_in[]; };
layout(std430, binding = BIND_AUX_OUT) restrict writeonly buffer BoundOut { uint bound_out[]; };
uniform uint u_bound_count;

#define BOUND_SUB 24
shared float s_red[WG_SIZE]; // the reductions (WG_SIZE floats: app/gpu/gl_limits.c)
#if (WG_SIZE & (WG_SIZE - 1)) != 0
#error "group_reduce halves WG_SIZE: a power of two"
#endif

// the work group's minimum (sign 1) or maximum (sign -1) of v
float group_reduce(float v, float sign)
{
	uint l = gl_LocalInvocationID.x;
	s_red[l] = v * sign;
	memoryBarrierShared();
	barrier();
	for (uint h = uint(WG_SIZE) / 2u; h > 0u; h >>= 1u) {
		if (l < h)
			s_red[l] = min(s_red[l], s_red[l + h]);
		memoryBarrierShared();
		barrier();
	}
	float r = s_red[0] * sign;
	barrier(); // every lane has read it before the next reduction writes
	return r;
}

void main()
{
	uint b = gl_WorkGroupID.x, l = gl_LocalInvocationID.x;
	if (b >= u_bound_count)
		return;
	vec4 lo = bound_in[2u * b], hi = bound_in[2u * b + 1u];
	int keep = int(lo.w);
	vec3 e = (hi.xyz - lo.xyz) * (0.5 / float(BOUND_SUB));
	float mn = 3.0e38, mx = -3.0e38;
	for (uint k = l; k < uint(BOUND_SUB * BOUND_SUB * BOUND_SUB); k += uint(WG_SIZE)) {
		uvec3 s = uvec3(k % uint(BOUND_SUB), (k / uint(BOUND_SUB)) % uint(BOUND_SUB),
				k / uint(BOUND_SUB * BOUND_SUB));
		vec3 c = lo.xyz + (2.0 * vec3(s) + 1.0) * e;
		vec2 r = density_bound(c, e, keep);
		mn = min(mn, r.x);
		mx = max(mx, r.y);
	}
	mn = group_reduce(mn, 1.0);
	mx = group_reduce(mx, -1.0);
	if (l == 0u) {
		float dlo = mn - hi.w, dhi = mx - hi.w;
		bound_out[b] = dhi < u_iso ? 1u : dlo > u_iso ? 2u : 0u;
	}
}
