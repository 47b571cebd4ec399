/* isoterra — the GeoTIFF module's entry points for the core
 * (geo_module.c): found and loaded on first use, so that GDAL is mapped
 * only in runs that read a GeoTIFF or transform an EPSG-coded CRS. */
#ifndef ISOTERRA_GEO_MODULE_H
#define ISOTERRA_GEO_MODULE_H

#include <stddef.h>

#include "geotiff.h"

/* The module's reader, or NULL with err (the folders tried, why each
 * failed; or that the build has no GDAL). */
geotiff_load_fn geo_module_load(char *err, size_t errlen);
/* n positions xy (x, y pairs, in place) from the CRS crs ("EPSG:32633")
 * to WGS84 lon/lat, through the module (GDAL's OSR); name gets the CRS's
 * name.  0, or -1 with err (without GDAL: that EPSG codes need it). */
int geo_crs_to_lonlat(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err, size_t errlen);

#endif
