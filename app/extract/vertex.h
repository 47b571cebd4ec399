/* isoterra — the 16-byte vertex of the GPU mesh, read on the CPU: the
 * position (three floats) and one word with the normal (octahedral,
 * 12 + 12 bits) and the ambient visibility (8 bits).  The GPU side, and
 * the layout's reasons, are shaders/vertex.glsl; VERTEX_BYTES is in abi.h. */
#ifndef ISOTERRA_VERTEX_H
#define ISOTERRA_VERTEX_H

#include <stdint.h>

/* Steps of each octahedral coordinate (codes 0..OCT_STEPS). */
#define OCT_STEPS 4094

/* Vertex v (4 words as read from the buffer) -> position, unit normal and
 * ambient visibility in [0, 1] (ao may be NULL). */
void vertex_unpack(const uint32_t v[4], float pos[3], float nrm[3], float *ao);

#endif
