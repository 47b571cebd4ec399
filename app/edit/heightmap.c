/* isoterra — heightmap files: 16-bit grayscale PNG in and out, GeoTIFF
 * in through the GDAL module (geo_module.h). */
#include "edits.h"
#include "core.h"

#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#define HEIGHTMAP_MAX_SIDE 16384

#include "geo_module.h"

#ifdef ISOTERRA_HAVE_GDAL
/* The module's map as the heightmap: samples taken over, georeference
 * copied. */
static void from_module(struct geotiff_map *m, struct heightmap *hm)
{
	hm->v = m->v;
	hm->w = m->w;
	hm->h = m->h;
	m->v = NULL;
	struct heightmap_geo *g = &hm->geo;
	g->on = m->georef;
	if (!g->on)
		return;
	g->cell = m->cell;
	g->lon0 = m->lon0;
	g->lat0 = m->lat0;
	memcpy(g->lonlat, m->lonlat, sizeof(g->lonlat));
	g->zmin = m->zmin;
	g->zmax = m->zmax;
	g->src_w = m->src_w;
	g->src_h = m->src_h;
	memcpy(g->src_res, m->src_res, sizeof(g->src_res));
	g->epsg = m->epsg;
	g->projected = m->projected;
	snprintf(g->crs, sizeof(g->crs), "%s", m->crs);
	snprintf(g->unit, sizeof(g->unit), "%s", m->unit);
}
#endif

int heightmap_load(const char *path, struct heightmap *hm, char *err, size_t errlen)
{
	memset(hm, 0, sizeof(*hm));
	const char *dot = strrchr(path, '.');
	if (dot && (!strcasecmp(dot, ".tif") || !strcasecmp(dot, ".tiff"))) {
#ifdef ISOTERRA_HAVE_GDAL
		if (access(path, R_OK) != 0) {
			snprintf(err, errlen, "cannot open heightmap file '%s' (GeoTIFF, read through GDAL)", path);
			return -1;
		}
		char e[PATH_MAX * 4];
		geotiff_load_fn load = geo_module_load(e, sizeof(e));
		if (!load) {
			snprintf(err, errlen, "heightmap '%s': GeoTIFF heightmaps %s", path, e);
			return -1;
		}
		struct geotiff_map m;
		if (load(path, HEIGHTMAP_MAX_SIDE, &m, err, errlen) < 0)
			return -1;
		from_module(&m, hm);
		return 0;
#else
		snprintf(err, errlen, "heightmap '%s': GeoTIFF needs GDAL, which this build does not use; convert it to a "
			 "16-bit grayscale PNG (gdal_translate -ot UInt16 -of PNG)", path);
		return -1;
#endif
	}
	if (!dot || strcasecmp(dot, ".png")) {
		snprintf(err, errlen, "heightmap '%s': unknown format (a 16-bit grayscale .png is needed)", path);
		return -1;
	}
	return heightmap_read_png(path, "heightmap", hm, err, errlen);
}

int heightmap_read_png(const char *path, const char *what, struct heightmap *hm, char *err, size_t errlen)
{
	memset(hm, 0, sizeof(*hm));
	uint16_t *s = NULL;
	int w = 0, h = 0;
	char e[512];
	/* the size from the header, refused before anything is decoded */
	if (image_read_png_size(path, &w, &h, e, sizeof(e)) < 0) {
		snprintf(err, errlen, "%s: %s (a grayscale PNG is needed)", what, e);
		return -1;
	}
	if (w < 2 || h < 2 || w > HEIGHTMAP_MAX_SIDE || h > HEIGHTMAP_MAX_SIDE) {
		snprintf(err, errlen, "%s '%s' is %dx%d; 2x2 to %dx%d samples are supported", what, path, w, h,
			 HEIGHTMAP_MAX_SIDE, HEIGHTMAP_MAX_SIDE);
		return -1;
	}
	if (image_read_png_gray16(path, &s, &w, &h, e, sizeof(e)) < 0) {
		snprintf(err, errlen, "%s: %s", what, e);
		return -1;
	}
	if (w < 2 || h < 2 || w > HEIGHTMAP_MAX_SIDE || h > HEIGHTMAP_MAX_SIDE) { /* the file changed meanwhile */
		snprintf(err, errlen, "%s '%s' changed while it was read", what, path);
		free(s);
		return -1;
	}
	hm->v = malloc(sizeof(float) * (size_t)w * (size_t)h);
	if (!hm->v) {
		free(s);
		snprintf(err, errlen, "out of memory for the %s '%s'", what, path);
		return -1;
	}
	for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
		hm->v[i] = (float)s[i];
	free(s);
	hm->w = w;
	hm->h = h;
	return 0;
}

void heightmap_free(struct heightmap *hm)
{
	free(hm->v);
	memset(hm, 0, sizeof(*hm));
}


void heightmap_describe(const struct heightmap *hm, const char *path, char *line, size_t len)
{
	const struct heightmap_geo *g = &hm->geo;
	if (!g->on) {
		snprintf(line, len, "%s: %dx%d samples, no georeference (heightmap_scale world units apart)", path, hm->w,
			 hm->h);
		return;
	}
	char code[24] = "";
	if (g->epsg)
		snprintf(code, sizeof(code), ", EPSG:%d", g->epsg);
	snprintf(line, len, "%s: %dx%d samples (%s%s, %s; %.4g x %.4g m a sample), as %dx%d on the east-north grid at "
		 "lon %.6f lat %.6f, %.4g m apart: %.6g x %.6g m, lon [%.6f, %.6f] lat [%.6f, %.6f]; elevation %.6g .. "
		 "%.6g m%s%s%s", path, g->src_w, g->src_h, g->crs, code, g->projected ? "projected" : "geographic",
		 g->src_res[0], g->src_res[1], hm->w, hm->h, g->lon0, g->lat0, g->cell, g->cell * (hm->w - 1),
		 g->cell * (hm->h - 1), g->lonlat[0], g->lonlat[2], g->lonlat[1], g->lonlat[3], g->zmin, g->zmax,
		 g->unit[0] ? " (band unit " : "", g->unit, g->unit[0] ? ")" : "");
}
