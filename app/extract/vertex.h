/* isoterra — the 16-byte vertex of the GPU mesh, read on the CPU: the
 * position (three floats) and one word with the normal (octahedral,
 * 11 + 11 bits), the ambient visibility and the sun's visibility (5 bits
 * each).  The GPU side, and the layout's reasons, are shaders/vertex.glsl;
 * the layout's constants (VERTEX_BYTES, VERTEX_OCT_*) are in abi.h. */
#ifndef ISOTERRA_VERTEX_H
#define ISOTERRA_VERTEX_H

#include <stdint.h>

/* Vertex v (4 words as read from the buffer) -> position, unit normal,
 * ambient visibility and sun visibility in [0, 1] (ao and sun may be
 * NULL). */
void vertex_unpack(const uint32_t v[4], float pos[3], float nrm[3], float *ao, float *sun);

#endif
