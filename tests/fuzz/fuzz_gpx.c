/* isoterra — libFuzzer harness: GPX curves (app/edit/gpx.c over libexpat);
 * the assertions are fuzz_curves.h's. */
#include "fuzz_curves.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct curve_set s = {0};
	char err[512] = "";
	fuzz_check_curves(curves_parse_gpx((const char *)data, size, "fuzz.gpx", &s, err, sizeof(err)), &s, err);
	return 0;
}
