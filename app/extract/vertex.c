/* isoterra — the GPU mesh's 16-byte vertex decoded on the CPU (read-backs:
 * tests, mesh export).  Mirrors unpack_normal/unpack_ao/unpack_sun of
 * shaders/vertex.glsl.  See vertex.h. */
#include "vertex.h"
#include "gpu.h" /* abi.h: the layout's constants */

#include <math.h>
#include <string.h>

void vertex_unpack(const uint32_t v[4], float pos[3], float nrm[3], float *ao, float *sun)
{
	memcpy(pos, v, 3 * sizeof(float));
	uint32_t w = v[3], mask = (1u << VERTEX_OCT_BITS) - 1u;
	float ex = (float)(w & mask) * (2.0f / VERTEX_OCT_STEPS) - 1.0f;
	float ey = (float)((w >> VERTEX_OCT_BITS) & mask) * (2.0f / VERTEX_OCT_STEPS) - 1.0f;
	float n[3] = { ex, ey, 1.0f - fabsf(ex) - fabsf(ey) };
	float t = n[2] < 0.0f ? -n[2] : 0.0f;
	n[0] += n[0] >= 0.0f ? -t : t;
	n[1] += n[1] >= 0.0f ? -t : t;
	float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
	for (int a = 0; a < 3; a++)
		nrm[a] = n[a] / len;
	if (ao)
		*ao = (float)((w >> (2 * VERTEX_OCT_BITS)) & 31u) / 31.0f;
	if (sun)
		*sun = (float)(w >> (2 * VERTEX_OCT_BITS + 5)) / 31.0f;
}
