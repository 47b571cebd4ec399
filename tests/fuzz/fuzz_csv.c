/* isoterra — libFuzzer harness: CSV curves (app/edit/csv_curves.c: a header,
 * then one row per point); the assertions are fuzz_curves.h's. */
#include "fuzz_curves.h"

#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct curve_set s = {0};
	char err[512] = "";
	fuzz_check_curves(curves_parse_csv((const char *)data, size, "fuzz.csv", &s, err, sizeof(err)), &s, err);
	return 0;
}
