// isoterra — the 16-byte vertex the extraction writes and the renderer reads
// (app/gpu/abi.h VERTEX_BYTES; the CPU side is app/extract/vertex.c): the
// position as three floats and one word with the unit normal, octahedral,
// 11 + 11 bits (bits 0-21, VERTEX_OCT_BITS), the ambient visibility, 5 bits
// (22-26), and the sun's visibility (sun.glsl), 5 bits (27-31).
// Half of the vec4 + vec4 it replaces: a block slot, the draws and the
// read-backs move half the bytes.  Eleven bits per coordinate keep the
// normal within 0.1 degrees; the two visibilities are smooth and
// interpolated over the triangle, 32 levels each.
struct Vertex { vec3 pos; uint nao; };

#define OCT_STEPS float(VERTEX_OCT_STEPS) // codes 0..2046: 0.0 is code 1023 exactly
#define OCT_MASK ((1u << VERTEX_OCT_BITS) - 1u)

uint pack_vertex_word(vec3 n, float ao, float sun)
{
	n /= abs(n.x) + abs(n.y) + abs(n.z);
	vec2 e = n.xy;
	if (n.z < 0.0)
		e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
	uvec2 q = uvec2(round(clamp(e * 0.5 + 0.5, 0.0, 1.0) * OCT_STEPS));
	uint a = uint(round(clamp(ao, 0.0, 1.0) * 31.0));
	uint s = uint(round(clamp(sun, 0.0, 1.0) * 31.0));
	return q.x | (q.y << VERTEX_OCT_BITS) | (a << (2 * VERTEX_OCT_BITS)) | (s << (2 * VERTEX_OCT_BITS + 5));
}

vec3 unpack_normal(uint w)
{
	vec2 e = vec2(float(w & OCT_MASK), float((w >> VERTEX_OCT_BITS) & OCT_MASK)) * (2.0 / OCT_STEPS) - 1.0;
	vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
	float t = max(-n.z, 0.0);
	n.x += n.x >= 0.0 ? -t : t;
	n.y += n.y >= 0.0 ? -t : t;
	return normalize(n);
}

float unpack_ao(uint w)
{
	return float((w >> (2 * VERTEX_OCT_BITS)) & 31u) / 31.0;
}

float unpack_sun(uint w)
{
	return float(w >> (2 * VERTEX_OCT_BITS + 5)) / 31.0;
}
