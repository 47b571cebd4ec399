/* isoterra — libFuzzer harness: binary PLY meshes (app/output/ply.c,
 * ply_read: the header, then exactly the vertices and triangles it
 * announces).  A mesh that loads only references vertices it has. */
#include "ply.h"
#include "fuzz_file.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct mesh m;
	char err[512];
	err[0] = 0;
	if (ply_read(&m, fuzz_file(data, size, ".ply"), err, sizeof(err)) < 0) {
		if (!err[0] || m.pos || m.idx)
			abort(); /* an error says what it is, and leaves nothing */
		return 0;
	}
	for (size_t i = 0; i < 3 * (size_t)m.ntris; i++)
		if (m.idx[i] >= m.nverts)
			abort();
	mesh_free(&m);
	return 0;
}
