// isoterra — the 16-byte vertex the extraction writes and the renderer reads
// (app/gpu/abi.h VERTEX_BYTES; the CPU side is app/extract/vertex.c): the
// position as three floats and one word with the unit normal, octahedral,
// 12 + 12 bits (bits 0-23), and the ambient visibility, 8 bits (24-31).
// Half of the vec4 + vec4 it replaces: a block slot, the draws and the
// read-backs move half the bytes.
struct Vertex { vec3 pos; uint nao; };

#define OCT_STEPS 4094.0 // codes 0..4094: 0.0 is code 2047 exactly

uint pack_normal_ao(vec3 n, float ao)
{
	n /= abs(n.x) + abs(n.y) + abs(n.z);
	vec2 e = n.xy;
	if (n.z < 0.0)
		e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
	uvec2 q = uvec2(round(clamp(e * 0.5 + 0.5, 0.0, 1.0) * OCT_STEPS));
	uint a = uint(round(clamp(ao, 0.0, 1.0) * 255.0));
	return q.x | (q.y << 12) | (a << 24);
}

vec3 unpack_normal(uint w)
{
	vec2 e = vec2(float(w & 4095u), float((w >> 12) & 4095u)) * (2.0 / OCT_STEPS) - 1.0;
	vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
	float t = max(-n.z, 0.0);
	n.x += n.x >= 0.0 ? -t : t;
	n.y += n.y >= 0.0 ? -t : t;
	return normalize(n);
}

float unpack_ao(uint w)
{
	return float(w >> 24) / 255.0;
}
