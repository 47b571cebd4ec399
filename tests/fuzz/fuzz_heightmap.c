/* isoterra — libFuzzer harness: PNG heightmaps (app/edit/heightmap.c over
 * libpng through app/core/image.c: gray, RGB, palette, 8 or 16 bits,
 * interlaced, truncated).  A file that loads is 2x2 to 16384x16384 finite
 * samples in 0..65535. */
#include "edits.h"
#include "fuzz_file.h"

#include <math.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct heightmap hm;
	char err[512];
	err[0] = 0;
	if (heightmap_load(fuzz_file(data, size, ".png"), &hm, err, sizeof(err)) < 0) {
		if (!err[0] || hm.v)
			abort(); /* an error says what it is, and leaves nothing */
		return 0;
	}
	if (hm.w < 2 || hm.h < 2 || hm.w > 16384 || hm.h > 16384)
		abort();
	for (size_t i = 0; i < (size_t)hm.w * (size_t)hm.h; i++)
		if (!(hm.v[i] >= 0.0f && hm.v[i] <= 65535.0f))
			abort();
	heightmap_free(&hm);
	return 0;
}
