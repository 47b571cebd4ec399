/* isoterra — what the curve harnesses (fuzz_csv.c, fuzz_geojson.c) assert
 * of a parser's result: an error says what it is and leaves nothing; a
 * file that loads gives paths of at least two finite points. */
#ifndef ISOTERRA_FUZZ_CURVES_H
#define ISOTERRA_FUZZ_CURVES_H

#include "curves.h"

#include <math.h>
#include <stdlib.h>

static inline void fuzz_check_curves(int rc, struct curve_set *s, const char *err)
{
	if (rc < 0) {
		if (!err[0] || s->npaths)
			abort();
		return;
	}
	for (int i = 0; i < s->npaths; i++) {
		if (s->paths[i].npts < 2)
			abort();
		for (int k = 0; k < 3 * s->paths[i].npts; k++)
			if (!isfinite(s->paths[i].pts[k]))
				abort();
	}
	curve_set_free(s);
}

#endif
