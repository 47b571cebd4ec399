/* isoterra — tests: georeferenced DEMs (GeoTIFF through the GDAL module)
 * and routes in one frame.  Rasters are written here with GDAL's C API: a
 * geographic one (EPSG:4326, 3 arc-seconds) and a projected one (UTM
 * 33N, EPSG:32633, 30 m), each with a peak at a known sample.  The
 * expected east-north-up positions are computed here, independently of
 * app/edit/geo_enu.c: geodetic -> ECEF -> the origin's east/north by the
 * textbook formulas, UTM -> lon/lat by GDAL's OSR.
 *
 *   test_dem                   the checks (needs ISOTERRA_MODULE_DIR)
 *   test_dem --make DIR        writes DIR/geo.tif, utm.tif, rgb.tif,
 *                              route.geojson, route.gpx (for test_dem_cli.sh)
 *   test_dem --ground-share P  prints the share of P's pixels that are not
 *                              sky (sky: blue over red and green) */
#include "edits.h"
#include "core.h"
#include "tcheck.h"
#include "geo_module.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

/* the geographic DEM: 3" samples, top-left corner (GEO_W0, GEO_N0) */
#define GEO_W 201
#define GEO_H 161
#define GEO_RES (1.0 / 1200.0)
#define GEO_W0 7.30
#define GEO_N0 45.90
#define GEO_PI 140 /* the peak's sample */
#define GEO_PJ 50
/* the UTM DEM: 30 m samples, top-left corner (UTM_X0, UTM_Y0) */
#define UTM_W 181
#define UTM_H 151
#define UTM_RES 30.0
#define UTM_X0 400000.0
#define UTM_Y0 5100000.0
#define UTM_PI 50
#define UTM_PJ 100

/* ---- the expectation: ECEF and the local east-north of WGS84 ---------------- */

static void ecef(double lon, double lat, double x[3])
{
	const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
	double N = a / sqrt(1.0 - e2 * sin(lat * DEG) * sin(lat * DEG));
	x[0] = N * cos(lat * DEG) * cos(lon * DEG);
	x[1] = N * cos(lat * DEG) * sin(lon * DEG);
	x[2] = N * (1.0 - e2) * sin(lat * DEG);
}

static void expect_enu(double lon0, double lat0, double lon, double lat, double *e, double *n)
{
	double o[3], p[3];
	ecef(lon0, lat0, o);
	ecef(lon, lat, p);
	double d[3] = { p[0] - o[0], p[1] - o[1], p[2] - o[2] };
	*e = -sin(lon0 * DEG) * d[0] + cos(lon0 * DEG) * d[1];
	*n = -sin(lat0 * DEG) * cos(lon0 * DEG) * d[0] - sin(lat0 * DEG) * sin(lon0 * DEG) * d[1] + cos(lat0 * DEG) * d[2];
}

/* UTM 33N (x, y) -> lon/lat through OSR; 0 or -1 */
static int utm_to_lonlat(double *x, double *y, int n)
{
	OGRSpatialReferenceH u = OSRNewSpatialReference(NULL), w = OSRNewSpatialReference(NULL);
	int rc = -1;
	if (u && w && OSRImportFromEPSG(u, 32633) == OGRERR_NONE && OSRImportFromEPSG(w, 4326) == OGRERR_NONE) {
		OSRSetAxisMappingStrategy(u, OAMS_TRADITIONAL_GIS_ORDER);
		OSRSetAxisMappingStrategy(w, OAMS_TRADITIONAL_GIS_ORDER);
		OGRCoordinateTransformationH t = OCTNewCoordinateTransformation(u, w);
		if (t && OCTTransform(t, n, x, y, NULL))
			rc = 0;
		if (t)
			OCTDestroyCoordinateTransformation(t);
	}
	if (u)
		OSRRelease(u);
	if (w)
		OSRRelease(w);
	return rc;
}

/* ---- rasters ------------------------------------------------------------------ */

/* a hill of 2500 m over 400 m at sample (pi, pj), the lowest corner below
 * sea level (-20 m) */
static float relief(int i, int j, int pi, int pj)
{
	double d2 = (double)((i - pi) * (i - pi) + (j - pj) * (j - pj));
	return (float)(400.0 + 2500.0 * exp(-d2 / 60.0) - 420.0 * exp(-(double)(i * i + j * j) / 400.0));
}

static int write_dem(const char *path, int w, int h, int pi, int pj, const double gt[6], int epsg)
{
	GDALDriverH drv = GDALGetDriverByName("GTiff");
	GDALDatasetH ds = drv ? GDALCreate(drv, path, w, h, 1, GDT_Float32, NULL) : NULL;
	if (!ds)
		return -1;
	float *v = malloc(sizeof(float) * (size_t)w * (size_t)h);
	OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
	char *wkt = NULL;
	int rc = -1;
	if (v && s && OSRImportFromEPSG(s, epsg) == OGRERR_NONE && OSRExportToWkt(s, &wkt) == OGRERR_NONE &&
	    GDALSetProjection(ds, wkt) == CE_None && GDALSetGeoTransform(ds, (double *)gt) == CE_None) {
		for (int j = 0; j < h; j++)
			for (int i = 0; i < w; i++)
				v[(size_t)j * w + i] = relief(i, j, pi, pj);
		GDALRasterBandH b = GDALGetRasterBand(ds, 1);
		if (b && GDALRasterIO(b, GF_Write, 0, 0, w, h, v, w, h, GDT_Float32, 0, 0) == CE_None &&
		    GDALSetRasterUnitType(b, "metre") == CE_None)
			rc = 0;
	}
	CPLFree(wkt);
	if (s)
		OSRRelease(s);
	free(v);
	GDALClose(ds);
	return rc;
}

static const double geo_gt[6] = { GEO_W0, GEO_RES, 0, GEO_N0, 0, -GEO_RES };
static const double utm_gt[6] = { UTM_X0, UTM_RES, 0, UTM_Y0, 0, -UTM_RES };

/* an RGB picture with the geographic georeference: JPEG-compressed when
 * GDAL's GTiff has JPEG */
static int write_rgb(const char *path)
{
	GDALDriverH drv = GDALGetDriverByName("GTiff");
	char *opts[] = { "COMPRESS=JPEG", "PHOTOMETRIC=YCBCR", NULL };
	GDALDatasetH ds = drv ? GDALCreate(drv, path, 64, 64, 3, GDT_Byte, opts) : NULL;
	if (!ds && drv)
		ds = GDALCreate(drv, path, 64, 64, 3, GDT_Byte, NULL);
	if (!ds)
		return -1;
	unsigned char px[64 * 64];
	for (int i = 0; i < 64 * 64; i++)
		px[i] = (unsigned char)(i * 7);
	int rc = GDALSetGeoTransform(ds, (double *)geo_gt) == CE_None ? 0 : -1;
	for (int b = 1; b <= 3 && rc == 0; b++)
		if (GDALRasterIO(GDALGetRasterBand(ds, b), GF_Write, 0, 0, 64, 64, px, 64, 64, GDT_Byte, 0, 0) != CE_None)
			rc = -1;
	GDALClose(ds);
	return rc;
}

/* the peak's lon/lat and another sample's of the geographic DEM, as a
 * route: GeoJSON and GPX */
static void geo_sample_lonlat(int i, int j, double *lon, double *lat)
{
	*lon = GEO_W0 + (i + 0.5) * GEO_RES;
	*lat = GEO_N0 - (j + 0.5) * GEO_RES;
}

static int write_routes(const char *dir)
{
	double lon[3], lat[3];
	geo_sample_lonlat(GEO_PI, GEO_PJ, &lon[0], &lat[0]);
	geo_sample_lonlat(60, 120, &lon[1], &lat[1]);
	geo_sample_lonlat(30, 40, &lon[2], &lat[2]);
	char path[600];
	snprintf(path, sizeof(path), "%s/route.geojson", dir);
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	fprintf(f, "{\"type\":\"LineString\",\"coordinates\":[[%.9f,%.9f],[%.9f,%.9f],[%.9f,%.9f]]}\n", lon[0], lat[0],
		lon[1], lat[1], lon[2], lat[2]);
	fclose(f);
	snprintf(path, sizeof(path), "%s/route.gpx", dir);
	if (!(f = fopen(path, "w")))
		return -1;
	fprintf(f, "<gpx version=\"1.1\" xmlns=\"http://www.topografix.com/GPX/1/1\"><trk><trkseg>\n");
	for (int k = 0; k < 3; k++)
		fprintf(f, "<trkpt lat=\"%.9f\" lon=\"%.9f\"/>\n", lat[k], lon[k]);
	fprintf(f, "</trkseg></trk></gpx>\n");
	fclose(f);
	return 0;
}

static int make_all(const char *dir)
{
	char p[600];
	GDALAllRegister();
	snprintf(p, sizeof(p), "%s/geo.tif", dir);
	if (write_dem(p, GEO_W, GEO_H, GEO_PI, GEO_PJ, geo_gt, 4326) < 0)
		return -1;
	snprintf(p, sizeof(p), "%s/utm.tif", dir);
	if (write_dem(p, UTM_W, UTM_H, UTM_PI, UTM_PJ, utm_gt, 32633) < 0)
		return -1;
	snprintf(p, sizeof(p), "%s/rgb.tif", dir);
	if (write_rgb(p) < 0)
		return -1;
	return write_routes(dir);
}

/* ---- checks -------------------------------------------------------------------- */

/* The grid position (metres east, north) of the map's highest sample. */
static void peak_of(const struct heightmap *hm, double *e, double *n)
{
	size_t best = 0;
	for (size_t k = 1; k < (size_t)hm->w * (size_t)hm->h; k++)
		if (hm->v[k] > hm->v[best])
			best = k;
	int i = (int)(best % (size_t)hm->w), j = (int)(best / (size_t)hm->w);
	*e = (i - 0.5 * (hm->w - 1)) * hm->geo.cell;
	*n = (0.5 * (hm->h - 1) - j) * hm->geo.cell;
}

/* A map's peak where its lon/lat says, within one sample. */
static void check_peak(const char *what, const struct heightmap *hm, double lon0, double lat0, double lon, double lat)
{
	double e, n, ee, en;
	peak_of(hm, &e, &n);
	expect_enu(lon0, lat0, lon, lat, &ee, &en);
	double off = hypot(e - ee, n - en) / hm->geo.cell;
	CHECK(off <= 1.0, "%s: the peak at (%.1f, %.1f) m, expected (%.1f, %.1f): %.2f samples off", what, e, n, ee, en,
	      off);
	CHECK(fabs(hm->geo.lon0 - lon0) < 1e-9 && fabs(hm->geo.lat0 - lat0) < 1e-9,
	      "%s: origin lon %.9f lat %.9f, expected the raster's centre %.9f %.9f", what, hm->geo.lon0, hm->geo.lat0,
	      lon0, lat0);
	printf("  %s: %dx%d -> %dx%d at %.2f m; peak %.2f samples from its lon/lat's ENU position (%.1f, %.1f) m\n", what,
	       hm->geo.src_w, hm->geo.src_h, hm->w, hm->h, hm->geo.cell, off, ee, en);
}

static void test_geographic(const char *dir, struct heightmap *hm)
{
	char p[600], err[1024];
	snprintf(p, sizeof(p), "%s/geo.tif", dir);
	CHECK(heightmap_load(p, hm, err, sizeof(err)) == 0, "load %s: %s", p, err);
	if (!hm->v)
		return;
	CHECK(hm->geo.on && hm->geo.epsg == 4326 && !hm->geo.projected, "georeferenced, EPSG:4326, geographic (%d)",
	      hm->geo.epsg);
	double lon, lat;
	geo_sample_lonlat(GEO_PI, GEO_PJ, &lon, &lat);
	check_peak("EPSG:4326 3\"", hm, GEO_W0 + 0.5 * GEO_W * GEO_RES, GEO_N0 - 0.5 * GEO_H * GEO_RES, lon, lat);
	CHECK(hm->geo.zmin < 0.0 && hm->geo.zmax > 2800.0 && hm->geo.zmax <= 2900.0, "elevations %g .. %g m",
	      hm->geo.zmin, hm->geo.zmax);
}

static void test_projected(const char *dir)
{
	char p[600], err[1024];
	struct heightmap hm;
	snprintf(p, sizeof(p), "%s/utm.tif", dir);
	CHECK(heightmap_load(p, &hm, err, sizeof(err)) == 0, "load %s: %s", p, err);
	if (!hm.v)
		return;
	CHECK(hm.geo.on && hm.geo.epsg == 32633 && hm.geo.projected && strstr(hm.geo.crs, "UTM zone 33N"),
	      "EPSG:32633 projected (%s, %d)", hm.geo.crs, hm.geo.epsg);
	double x[2] = { UTM_X0 + 0.5 * UTM_W * UTM_RES, UTM_X0 + (UTM_PI + 0.5) * UTM_RES };
	double y[2] = { UTM_Y0 - 0.5 * UTM_H * UTM_RES, UTM_Y0 - (UTM_PJ + 0.5) * UTM_RES };
	CHECK(utm_to_lonlat(x, y, 2) == 0, "UTM to lon/lat through OSR");
	check_peak("EPSG:32633 30 m", &hm, x[0], y[0], x[1], y[1]);
	heightmap_free(&hm);
}

/* A route through the peak and two other samples lands on them: its
 * projected points at the samples' grid positions, within one sample
 * (GeoJSON lon/lat, GPX, and the same points in UTM 33N, EPSG-coded). */
static void check_route(const char *what, struct curve_set *s, const struct heightmap *hm, const struct params *p,
			int mode, const char *crs)
{
	struct edits ed;
	memset(&ed, 0, sizeof(ed));
	ed.hm = *hm;
	bool ll;
	const char *why;
	double c[2];
	char err[512], name[128];
	struct curves_geo_frame fr = { hm->geo.lon0, hm->geo.lat0, 1.0f };
	if (crs)
		CHECK(curves_from_crs(s, crs, geo_crs_to_lonlat, name, sizeof(name), err, sizeof(err)) == 0,
		      "%s: %s", what, err);
	CHECK(curves_geo_project(s, mode, p->curves_geo_scale, &fr, &ll, &why, c, err, sizeof(err)) == 0 && ll,
	      "%s: project: %s", what, err);
	const int at[3][2] = { { GEO_PI, GEO_PJ }, { 60, 120 }, { 30, 40 } };
	double worst = 0.0;
	for (int k = 0; k < 3 && s->npaths == 1 && s->paths[0].npts == 3; k++) {
		double lon, lat, e, n;
		geo_sample_lonlat(at[k][0], at[k][1], &lon, &lat);
		expect_enu(hm->geo.lon0, hm->geo.lat0, lon, lat, &e, &n);
		const float *q = s->paths[0].pts + 3 * k;
		worst = fmax(worst, hypot(q[0] - e, -q[2] - n) / hm->geo.cell);
	}
	CHECK(s->npaths == 1 && s->paths[0].npts == 3 && worst <= 1.0, "%s: %.4f samples from the DEM's samples", what,
	      worst);
	/* and on the map: the route's first point is the map's peak */
	double pe, pn;
	peak_of(hm, &pe, &pn);
	double off = s->npaths ? hypot(s->paths[0].pts[0] - pe, -s->paths[0].pts[2] - pn) / hm->geo.cell : 99.0;
	CHECK(off <= 1.0, "%s: its first point %.2f samples from the map's peak", what, off);
	printf("  %s: worst %.4f samples from the samples' ENU positions, %.2f from the map's peak sample\n", what, worst,
	       off);
	curve_set_free(s);
}

static void test_routes(const char *dir, const struct heightmap *hm, const struct params *p)
{
	char path[600], err[512];
	struct curve_set s;
	snprintf(path, sizeof(path), "%s/route.geojson", dir);
	if (curves_load(path, &s, err, sizeof(err)) == 0)
		check_route("GeoJSON lon/lat", &s, hm, p, CURVES_CRS_AUTO, NULL);
	else
		CHECK(0, "%s", err);
	snprintf(path, sizeof(path), "%s/route.gpx", dir);
	if (curves_load(path, &s, err, sizeof(err)) == 0)
		check_route("GPX", &s, hm, p, CURVES_CRS_AUTO, NULL);
	else
		CHECK(0, "%s", err);
	/* the same three points in UTM 33N metres (x east, y north) */
	double lon[3], lat[3];
	geo_sample_lonlat(GEO_PI, GEO_PJ, &lon[0], &lat[0]);
	geo_sample_lonlat(60, 120, &lon[1], &lat[1]);
	geo_sample_lonlat(30, 40, &lon[2], &lat[2]);
	OGRSpatialReferenceH u = OSRNewSpatialReference(NULL), w = OSRNewSpatialReference(NULL);
	OGRCoordinateTransformationH t = NULL;
	if (u && w && OSRImportFromEPSG(u, 32633) == OGRERR_NONE && OSRImportFromEPSG(w, 4326) == OGRERR_NONE) {
		OSRSetAxisMappingStrategy(u, OAMS_TRADITIONAL_GIS_ORDER);
		OSRSetAxisMappingStrategy(w, OAMS_TRADITIONAL_GIS_ORDER);
		t = OCTNewCoordinateTransformation(w, u);
	}
	CHECK(t && OCTTransform(t, 3, lon, lat, NULL), "lon/lat to UTM through OSR");
	char json[512];
	snprintf(json, sizeof(json), "{\"type\":\"LineString\",\"coordinates\":[[%.3f,%.3f],[%.3f,%.3f],[%.3f,%.3f]]}",
		 lon[0], lat[0], lon[1], lat[1], lon[2], lat[2]);
	if (curves_parse_geojson(json, strlen(json), "utm.geojson", &s, err, sizeof(err)) == 0)
		check_route("GeoJSON EPSG:32633", &s, hm, p, CURVES_CRS_NAMED, "EPSG:32633");
	else
		CHECK(0, "%s", err);
	if (t)
		OCTDestroyCoordinateTransformation(t);
	if (u)
		OSRRelease(u);
	if (w)
		OSRRelease(w);
	/* an unknown code: one clear message */
	snprintf(json, sizeof(json), "{\"type\":\"LineString\",\"coordinates\":[[1,2],[3,4]]}");
	if (curves_parse_geojson(json, strlen(json), "x.geojson", &s, err, sizeof(err)) == 0) {
		char name[64];
		CHECK(curves_from_crs(&s, "EPSG:999999", geo_crs_to_lonlat, name, sizeof(name), err,
				      sizeof(err)) < 0 && strstr(err, "EPSG:999999"), "unknown EPSG code refused: %s", err);
		curve_set_free(&s);
	}
}

/* The fitted placement: true scale, the relief doubled by
 * vertical_exaggeration 2 (the CPU mirror of the shader's height at the
 * peak), the volume over the map, the sea level's water. */
static void test_fit(const struct heightmap *hm, struct params *p)
{
	struct edits ed;
	memset(&ed, 0, sizeof(ed));
	ed.hm = *hm;
	double pe, pn;
	peak_of(hm, &pe, &pn);
	struct params a = *p, b = *p;
	heightmap_fit(hm, &a);
	b.vertical_exaggeration = 2.0f;
	heightmap_fit(hm, &b);
	float ya = heightmap_ref_base(&ed, &a, (float)pe, (float)-pn), yb = heightmap_ref_base(&ed, &b, (float)pe, (float)-pn);
	CHECK(fabs(ya - hm->geo.zmax) < 0.01 * hm->geo.zmax, "true scale: the peak at %.2f m, the map's top %.2f m", ya,
	      hm->geo.zmax);
	CHECK(fabs(yb / ya - 2.0) < 1e-4, "vertical_exaggeration 2: the peak at %.2f, %.5f times %.2f", yb, yb / ya, ya);
	CHECK(fabsf(a.heightmap_scale - (float)hm->geo.cell) < 1e-3f, "heightmap_scale %g = the cell %g m",
	      a.heightmap_scale, hm->geo.cell);
	float top = a.vol_y + 0.5f * a.vol_height * a.vol_size, bottom = a.vol_y - 0.5f * a.vol_height * a.vol_size;
	CHECK(fabsf(a.vol_size - (float)(hm->geo.cell * (hm->w < hm->h ? hm->w - 1 : hm->h - 1))) < 1.0f && bottom < hm->geo.zmin && top > hm->geo.zmax,
	      "volume %g m, y %g .. %g over the elevations %g .. %g", a.vol_size, bottom, top, hm->geo.zmin, hm->geo.zmax);
	CHECK(a.water && a.water_level == 0.0f, "the map spans sea level: water at 0 (%d, %g)", a.water, a.water_level);
	struct params g = *p;
	g.vol_size = 500.0f;
	heightmap_fit(hm, &g);
	CHECK(g.vol_size == 500.0f, "a vol_size given stays (%g)", g.vol_size);
	printf("  fit: volume %.0f m, y %.0f .. %.0f; peak %.1f m, x2 %.1f m\n", a.vol_size, bottom, top, ya, yb);
}

static void test_refused(const char *dir)
{
	char p[600], err[1024];
	struct heightmap hm;
	snprintf(p, sizeof(p), "%s/rgb.tif", dir);
	CHECK(heightmap_load(p, &hm, err, sizeof(err)) < 0 && !hm.v && strstr(err, "rgb.tif") &&
		      strstr(err, "not elevations") && !strchr(err, '\n'),
	      "an RGB GeoTIFF refused: %s", err);
}

/* ---- the picture's ground ------------------------------------------------------- */

static int ground_share(const char *path)
{
	struct image img;
	char err[512];
	if (image_read_png(&img, path, err, sizeof(err)) < 0) {
		fprintf(stderr, "%s\n", err);
		return 2;
	}
	size_t n = (size_t)img.width * (size_t)img.height, ground = 0;
	for (size_t i = 0; i < n; i++) {
		const uint8_t *c = img.rgba + 4 * i;
		ground += !(c[2] > c[0] + 40 && c[2] > c[1] + 15);
	}
	printf("%.4f\n", (double)ground / (double)n);
	image_free(&img);
	return 0;
}

int main(int argc, char **argv)
{
	if (argc == 3 && !strcmp(argv[1], "--make"))
		return make_all(argv[2]) < 0 ? 1 : 0;
	if (argc == 3 && !strcmp(argv[1], "--ground-share"))
		return ground_share(argv[2]);
	char dir[] = "/tmp/isoterra-dem-XXXXXX";
	if (!mkdtemp(dir)) {
		perror("mkdtemp");
		return 1;
	}
	CHECK(make_all(dir) == 0, "write the rasters and routes in %s", dir);
	struct params p;
	params_defaults(&p);
	p.field = FIELD_HEIGHTMAP;
	struct heightmap hm;
	memset(&hm, 0, sizeof(hm));
	test_geographic(dir, &hm);
	test_projected(dir);
	if (hm.v) {
		test_routes(dir, &hm, &p);
		test_fit(&hm, &p);
	}
	test_refused(dir);
	heightmap_free(&hm);
	const char *names[] = { "geo.tif", "utm.tif", "rgb.tif", "route.geojson", "route.gpx" };
	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
		char pth[600];
		snprintf(pth, sizeof(pth), "%s/%s", dir, names[i]);
		remove(pth);
	}
	rmdir(dir);
	return tc_done("dem");
}
