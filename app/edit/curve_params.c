/* isoterra — what the curve file readers share: kinds and per-path
 * parameters by name, with the same range checks in both formats. */
#include "curves_internal.h"

#include <math.h>
#include <string.h>

const char *const curve_param_names[CURVE_NPARAMS] = { "width", "falloff", "inclination", "smoothing" };

int curve_kind_parse(const char *s)
{
	for (int k = 0; k < CURVE_KIND_COUNT; k++)
		if (!strcmp(s, curve_kind_names[k]))
			return k;
	return -1;
}

const char *curve_param_check(const char *name, double v)
{
	if (!isfinite(v))
		return "is not a finite number";
	if (!strcmp(name, "width") && !(v > 0.0 && v <= 1e6))
		return "must be in (0, 1e6]";
	if (!strcmp(name, "falloff") && !(v >= 0.0 && v <= 1e6))
		return "must be in [0, 1e6]";
	if (!strcmp(name, "smoothing") && !(v >= 0.0 && v <= 1.0))
		return "must be in [0, 1]";
	if (!strcmp(name, "inclination") && !(fabs(v) <= 1e6))
		return "must be in [-1e6, 1e6]";
	return NULL;
}

float *curve_param_slot(struct curve_path *p, int i)
{
	return i == 0 ? &p->width : i == 1 ? &p->falloff : i == 2 ? &p->inclination : &p->smoothing;
}

