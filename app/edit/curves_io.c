/* isoterra — curve input: the file (its format chosen by the extension) and
 * the per-path parameters shared by the GeoJSON (geojson.c) and CSV
 * (csv_curves.c) readers. */
#include "curves.h"
#include "curves_internal.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_FILE_BYTES (64u << 20)

/* ---- per-path parameters ------------------------------------------------------ */

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

/* ---- files -------------------------------------------------------------------- */

static char *read_all(const char *path, size_t *len, char *err, size_t errlen)
{
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "cannot open curves file '%s': %s", path, strerror(errno));
		return NULL;
	}
	char *buf = NULL;
	size_t cap = 0, n = 0;
	for (;;) {
		if (n + 65536 + 1 > cap) {
			cap = cap ? cap * 2 : 131072;
			if (cap > MAX_FILE_BYTES + 65536 + 1) {
				snprintf(err, errlen, "curves file '%s' is larger than %u MB", path, MAX_FILE_BYTES >> 20);
				goto fail;
			}
			char *nb = realloc(buf, cap);
			if (!nb) {
				snprintf(err, errlen, "out of memory reading '%s'", path);
				goto fail;
			}
			buf = nb;
		}
		size_t r = fread(buf + n, 1, cap - n - 1, f);
		n += r;
		if (r == 0)
			break;
	}
	if (ferror(f)) {
		snprintf(err, errlen, "error reading curves file '%s'", path);
		goto fail;
	}
	fclose(f);
	buf[n] = 0;
	*len = n;
	return buf;
fail:
	free(buf);
	fclose(f);
	return NULL;
}

int curves_load(const char *path, struct curve_set *s, char *err, size_t errlen)
{
	memset(s, 0, sizeof(*s));
	const char *dot = strrchr(path, '.');
	bool csv = dot && !strcasecmp(dot, ".csv");
	bool geo = dot && (!strcasecmp(dot, ".geojson") || !strcasecmp(dot, ".json"));
	if (!csv && !geo) {
		snprintf(err, errlen, "curves file '%s': unknown format (use .geojson, .json or .csv)", path);
		return -1;
	}
	size_t len;
	char *text = read_all(path, &len, err, errlen);
	if (!text)
		return -1;
	int rc = csv ? curves_parse_csv(text, len, path, s, err, errlen)
		     : curves_parse_geojson(text, len, path, s, err, errlen);
	free(text);
	return rc;
}
