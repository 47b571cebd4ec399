/* isoterra — which parameters the knobs cycle through, and by how much one
 * detent changes them. */
#include "hal.h"

#include <math.h>
#include <string.h>

int knobs_init(struct knobs *k, const char *csv, char *err, size_t errlen)
{
	memset(k, 0, sizeof(*k));
	if (!csv || !csv[0]) {
		for (size_t i = 0; i < param_count && k->count < (int)(sizeof(k->list) / sizeof(k->list[0])); i++)
			if (param_table[i].flags & P_LIVE)
				k->list[k->count++] = &param_table[i];
		return 0;
	}
	char buf[PARAM_STR_MAX];
	snprintf(buf, sizeof(buf), "%s", csv);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ", ", &save); tok; tok = strtok_r(NULL, ", ", &save)) {
		const struct param_info *pi = params_find(tok);
		if (!pi) {
			snprintf(err, errlen, "knob_params: unknown parameter '%s'", tok);
			return -1;
		}
		if (pi->type == PT_STRING) {
			snprintf(err, errlen, "knob_params: '%s' is text, a knob needs a number", tok);
			return -1;
		}
		if (k->count == (int)(sizeof(k->list) / sizeof(k->list[0]))) {
			snprintf(err, errlen, "knob_params: too many parameters");
			return -1;
		}
		k->list[k->count++] = pi;
	}
	if (!k->count) {
		snprintf(err, errlen, "knob_params: no parameter named");
		return -1;
	}
	return 0;
}

/* One detent: integers, enums and booleans by 1; floats by a tenth of the
 * decade of their default (a tenth of the decade of min(range, 10) for a
 * zero default), at most a twentieth of the range. */
double knob_step(const struct param_info *pi)
{
	if (pi->type != PT_FLOAT)
		return 1;
	double range = pi->hi - pi->lo;
	double base = pi->def != 0 ? fabs(pi->def) : fmin(range, 10.0);
	double step = pow(10.0, floor(log10(base))) / 10.0;
	while (step > range / 20.0)
		step /= 10.0;
	return step;
}

bool knob_change(const struct knobs *k, struct params *p, int delta)
{
	if (!k->count || !delta)
		return false;
	const struct param_info *pi = k->list[k->sel];
	double old = params_get_number(p, pi);
	double v;
	if (pi->type == PT_BOOL) {
		v = (delta % 2) ? !old : old;
	} else {
		double step = knob_step(pi);
		v = old + delta * step;
		if (pi->type == PT_FLOAT)
			v = round(v / step) * step;
	}
	params_set_number(p, pi, v);
	return params_get_number(p, pi) != old;
}
