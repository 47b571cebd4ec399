/* isoterra — GeoTIFF heightmaps: the interface of the reader module
 * (geotiff.c), built with GDAL as isoterra-geotiff.so and loaded by
 * heightmap.c only when a GeoTIFF is asked for.  GDAL and the libraries it
 * brings (98 on Debian 12) would otherwise be mapped, relocated and partly
 * resident in every run: 26 MB of resident memory for a feature most runs
 * never use. */
#ifndef ISOTERRA_GEOTIFF_H
#define ISOTERRA_GEOTIFF_H

#include <stddef.h>

#define GEOTIFF_MODULE "isoterra-geotiff.so"
/* the entry point's name carries its version: a module from another
 * version of the program is refused by name, not called */
#define GEOTIFF_SYMBOL "isoterra_geotiff_load_v1"

/* Band 1 of the raster at path as w x h floats (malloc'd: the caller frees
 * *v), its valid range [min, max] mapped onto 0..65535, no-data samples at
 * 0; sides of 2 .. max_side.  0, or -1 with err (naming path). */
typedef int (*geotiff_load_fn)(const char *path, int max_side, float **v, int *w, int *h, char *err, size_t errlen);
int isoterra_geotiff_load_v1(const char *path, int max_side, float **v, int *w, int *h, char *err, size_t errlen);

#endif
