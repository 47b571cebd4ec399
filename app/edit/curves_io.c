/* isoterra — curve input: the file, its format chosen by the extension
 * (GeoJSON: geojson.c, GPX: gpx.c, CSV: csv_curves.c). */
#include "curves.h"
#include "curves_internal.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_FILE_BYTES (64u << 20)

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
	bool gpx = dot && !strcasecmp(dot, ".gpx");
	if (!csv && !geo && !gpx) {
		snprintf(err, errlen, "curves file '%s': unknown format (use .geojson, .json, .gpx or .csv)", path);
		return -1;
	}
	size_t len;
	char *text = read_all(path, &len, err, errlen);
	if (!text)
		return -1;
	int rc = csv ? curves_parse_csv(text, len, path, s, err, errlen)
		 : gpx ? curves_parse_gpx(text, len, path, s, err, errlen)
		       : curves_parse_geojson(text, len, path, s, err, errlen);
	free(text);
	return rc;
}
