/* isoterra — the GeoTIFF reader module (geotiff.h): any raster GDAL
 * opens, built as isoterra-geotiff.so and loaded by heightmap.c when a
 * GeoTIFF heightmap is asked for. */
#include "geotiff.h"

#include <cpl_error.h>
#include <gdal.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

/* GeoTIFF (any raster GDAL opens) through GDAL: band 1 as floats, the
 * band's valid range [min, max] mapped onto 0..65535 (so heightmap_base /
 * heightmap_height place it as they place a PNG), no-data samples at min. */
int isoterra_geotiff_load_v1(const char *path, int max_side, float **out, int *out_w, int *out_h, char *err, size_t errlen)
{
	if (GDALGetDriverCount() == 0) /* not registered yet */
		GDALAllRegister();
	CPLPushErrorHandler(CPLQuietErrorHandler);
	CPLErrorReset();
	GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, NULL, NULL, NULL);
	if (!ds) {
		const char *m = CPLGetLastErrorMsg();
		snprintf(err, errlen, "heightmap '%s': GDAL cannot read it as a GeoTIFF: %s", path,
			 m && m[0] ? m : "unknown error");
		CPLPopErrorHandler();
		return -1;
	}
	int rc = -1;
	float *v = NULL;
	int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
	if (GDALGetRasterCount(ds) < 1) {
		snprintf(err, errlen, "heightmap '%s': the GeoTIFF has no raster band", path);
		goto out;
	}
	if (w < 2 || h < 2 || w > max_side || h > max_side) {
		snprintf(err, errlen, "heightmap '%s' is %dx%d; 2x2 to %dx%d samples are supported", path, w, h,
			 max_side, max_side);
		goto out;
	}
	GDALRasterBandH band = GDALGetRasterBand(ds, 1);
	v = malloc(sizeof(float) * (size_t)w * (size_t)h);
	if (!band || !v) {
		snprintf(err, errlen, "heightmap '%s': %s", path, v ? "no band 1" : "out of memory");
		goto out;
	}
	CPLErrorReset();
	if (GDALRasterIO(band, GF_Read, 0, 0, w, h, v, w, h, GDT_Float32, 0, 0) != CE_None) {
		const char *m = CPLGetLastErrorMsg();
		snprintf(err, errlen, "heightmap '%s': GDAL cannot read the samples: %s", path,
			 m && m[0] ? m : "read error");
		goto out;
	}
	int has_nodata = 0;
	double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
	size_t n = (size_t)w * (size_t)h;
	float lo = INFINITY, hi = -INFINITY;
	for (size_t i = 0; i < n; i++) {
		if (!isfinite(v[i]) || (has_nodata && (double)v[i] == (double)(float)nodata))
			continue;
		lo = v[i] < lo ? v[i] : lo;
		hi = v[i] > hi ? v[i] : hi;
	}
	if (!(lo <= hi)) {
		snprintf(err, errlen, "heightmap '%s': every sample is no-data", path);
		goto out;
	}
	float k = hi > lo ? 65535.0f / (hi - lo) : 0.0f;
	for (size_t i = 0; i < n; i++) {
		bool valid = isfinite(v[i]) && !(has_nodata && (double)v[i] == (double)(float)nodata);
		v[i] = valid ? (v[i] - lo) * k : 0.0f;
	}
	*out = v;
	*out_w = w;
	*out_h = h;
	v = NULL;
	rc = 0;
out:
	free(v);
	GDALClose(ds);
	CPLPopErrorHandler();
	return rc;
}
