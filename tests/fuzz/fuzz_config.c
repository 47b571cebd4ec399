/* isoterra — libFuzzer harness: configuration files (app/params/params.c,
 * params_load_config_file: "name = value" lines, comments, quotes, presets,
 * every parameter's value parser).  A file that loads leaves every number
 * inside its range. */
#include "params.h"
#include "fuzz_file.h"

#include <math.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct params p;
	char err[512];
	params_defaults(&p);
	if (params_load_config_file(&p, fuzz_file(data, size, ".conf"), err, sizeof(err)) < 0) {
		if (!err[0])
			abort(); /* an error always says what it is */
		return 0;
	}
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (pi->type != PT_FLOAT && pi->type != PT_INT)
			continue;
		double v = params_get_number(&p, pi);
		double lo = pi->type == PT_FLOAT ? (double)(float)pi->lo : pi->lo; /* the stored float's rounding */
		double hi = pi->type == PT_FLOAT ? (double)(float)pi->hi : pi->hi;
		if (!isfinite(v) || v < lo || v > hi)
			abort();
	}
	return 0;
}
