/* isoterra — GeoTIFF heightmaps: the interface of the reader module
 * (geotiff.c), built with GDAL as isoterra-geotiff.so and loaded by
 * heightmap.c only when a GeoTIFF is asked for.  GDAL and the libraries it
 * brings (98 on Debian 12) would otherwise be mapped, relocated and partly
 * resident in every run: 26 MB of resident memory for a feature most runs
 * never use.  The module also carries the coordinate transforms of GDAL's
 * OSR (PROJ) that other georeferenced inputs need (EPSG-coded curves). */
#ifndef ISOTERRA_GEOTIFF_H
#define ISOTERRA_GEOTIFF_H

#include <stdbool.h>
#include <stddef.h>

#define GEOTIFF_MODULE "isoterra-geotiff.so"
/* the entry points' names carry their version: a module from another
 * version of the program is refused by name, not called */
#define GEOTIFF_SYMBOL "isoterra_geotiff_load_v2"
#define GEOTIFF_TO_LONLAT_SYMBOL "isoterra_geotiff_to_lonlat_v2"

/* A raster read as a heightmap. */
struct geotiff_map {
	float *v;      /* w x h samples (malloc'd: the caller frees), x fastest,
			  row 0 first; the range [zmin, zmax] mapped onto
			  0..65535, no-data samples at 0 */
	int w, h;
	double zmin, zmax; /* the valid samples' range: metres when georef
			      (the band's scale, offset and unit applied) */
	/* georeferenced (a geotransform and a CRS): the samples resampled onto
	 * a regular grid of the local east-north-up frame of WGS84 whose
	 * origin is the raster's centre (geo_enu.h): sample (i, j) at east
	 * (i - (w-1)/2) cell, north ((h-1)/2 - j) cell metres; heights are
	 * the elevations themselves (no earth curvature: sea level stays the
	 * plane 0) */
	bool georef;
	double cell;       /* metres between samples */
	double lon0, lat0; /* the origin (WGS84 degrees) */
	double lonlat[4];  /* the raster's lon/lat box: west, south, east, north */
	int src_w, src_h;  /* the raster's own size */
	double src_res[2]; /* its sample spacing at the centre, metres east and north */
	int epsg;          /* the CRS's EPSG code, 0 when it has none */
	bool projected;    /* a projected CRS (else geographic) */
	char crs[96];      /* its name */
	char unit[32];     /* the band's vertical unit as given ("" unsaid: metres) */
};

/* The raster at path: band 1 as the map above.  A raster of colours (RGB
 * or more bands, a palette, a colour interpretation, 8-bit JPEG) is
 * refused.  The grid's sides are 2 .. max_side.  0, or -1 with err (naming
 * path, one line). */
typedef int (*geotiff_load_fn)(const char *path, int max_side, struct geotiff_map *m, char *err, size_t errlen);
int isoterra_geotiff_load_v2(const char *path, int max_side, struct geotiff_map *m, char *err, size_t errlen);

/* n positions xy (x, y pairs, in place) from the CRS named by crs (any
 * definition OSR reads: "EPSG:32633", WKT, PROJ) to WGS84 lon/lat
 * (degrees); name gets the CRS's name.  0, or -1 with err. */
typedef int (*geotiff_to_lonlat_fn)(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err,
				    size_t errlen);
int isoterra_geotiff_to_lonlat_v2(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err,
				  size_t errlen);

#endif
