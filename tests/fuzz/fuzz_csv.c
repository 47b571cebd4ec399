/* isoterra — libFuzzer harness: CSV curves (app/edit/csv_curves.c: a header,
 * then one row per point).  A file that loads gives paths of at least
 * two finite points. */
#include "curves.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct curve_set s = {0};
	char err[512];
	err[0] = 0;
	if (curves_parse_csv((const char *)data, size, "fuzz.csv", &s, err, sizeof(err)) < 0) {
		if (!err[0] || s.npaths)
			abort(); /* an error says what it is, and leaves nothing */
		return 0;
	}
	for (int i = 0; i < s.npaths; i++) {
		if (s.paths[i].npts < 2)
			abort();
		for (int k = 0; k < 3 * s.paths[i].npts; k++)
			if (!isfinite(s.paths[i].pts[k]))
				abort();
	}
	curve_set_free(&s);
	return 0;
}
