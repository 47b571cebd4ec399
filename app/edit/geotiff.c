/* isoterra — the GeoTIFF reader module (geotiff.h): any raster GDAL
 * opens, built as isoterra-geotiff.so and loaded by heightmap.c when a
 * GeoTIFF heightmap is asked for; with a geotransform and a CRS, its
 * samples resampled onto the local east-north-up grid (geo_enu.h) through
 * GDAL's OSR.  Also the CRS-to-lon/lat transform of other inputs. */
#include "geotiff.h"
#include "geo_enu.h"

#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* the lattice of exactly transformed nodes, every LATTICE nodes: positions
 * between are interpolated (the transforms are smooth: under 1 mm off over
 * a lattice cell of 16 samples of 100 m) */
#define LATTICE 16

static const char *gdal_msg(const char *fallback)
{
	const char *m = CPLGetLastErrorMsg();
	return m && m[0] ? m : fallback;
}

/* A band of colours rather than heights: why in why, else NULL. */
static const char *colour_raster(GDALDatasetH ds, GDALRasterBandH band, char *why, size_t len)
{
	int nb = GDALGetRasterCount(ds);
	GDALColorInterp ci = GDALGetRasterColorInterpretation(band);
	const char *comp = GDALGetMetadataItem(ds, "COMPRESSION", "IMAGE_STRUCTURE");
	bool jpeg = comp && (!strcasecmp(comp, "JPEG") || !strcasecmp(comp, "YCbCr JPEG"));
	if (nb >= 3)
		snprintf(why, len, "%d bands (band 1 %s)", nb, GDALGetColorInterpretationName(ci));
	else if (GDALGetRasterColorTable(band))
		snprintf(why, len, "a palette");
	else if (ci != GCI_GrayIndex && ci != GCI_Undefined)
		snprintf(why, len, "band 1 is %s", GDALGetColorInterpretationName(ci));
	else if (jpeg && GDALGetRasterDataType(band) == GDT_Byte)
		snprintf(why, len, "8-bit JPEG");
	else
		return NULL;
	return why;
}

/* The band's samples in metres (scale, offset, unit), no-data as NaN.
 * -1 with err for a unit that is not a length. */
static int to_metres(GDALRasterBandH band, float *v, size_t n, char *unit, size_t ulen, const char *path, char *err,
		     size_t errlen)
{
	const char *u = GDALGetRasterUnitType(band);
	snprintf(unit, ulen, "%s", u ? u : "");
	double k = 1.0;
	if (!unit[0] || !strcasecmp(unit, "m") || !strcasecmp(unit, "metre") || !strcasecmp(unit, "meter") ||
	    !strcasecmp(unit, "metres") || !strcasecmp(unit, "meters"))
		k = 1.0;
	else if (!strcasecmp(unit, "ft") || !strcasecmp(unit, "foot") || !strcasecmp(unit, "feet"))
		k = 0.3048;
	else if (!strcasecmp(unit, "US survey foot") || !strcasecmp(unit, "ftUS") || !strcasecmp(unit, "us-ft"))
		k = 1200.0 / 3937.0;
	else if (!strcasecmp(unit, "km"))
		k = 1000.0;
	else {
		snprintf(err, errlen, "heightmap '%s': band 1's unit '%s' is not a length (m, ft, US survey foot)", path,
			 unit);
		return -1;
	}
	int ok_s = 0, ok_o = 0, has_nodata = 0;
	double scale = GDALGetRasterScale(band, &ok_s), offset = GDALGetRasterOffset(band, &ok_o);
	double nodata = GDALGetRasterNoDataValue(band, &has_nodata);
	if (!ok_s || scale == 0.0)
		scale = 1.0;
	if (!ok_o)
		offset = 0.0;
	for (size_t i = 0; i < n; i++) {
		bool valid = isfinite(v[i]) && !(has_nodata && (double)v[i] == (double)(float)nodata);
		v[i] = valid ? (float)((v[i] * scale + offset) * k) : NAN;
	}
	return 0;
}

/* Bilinear at pixel position (x, y) (0.5 = the first sample's centre);
 * a no-data corner gives way to the valid ones; NaN when all are. */
static float sample(const float *v, int w, int h, double x, double y)
{
	x -= 0.5;
	y -= 0.5;
	x = x < 0.0 ? 0.0 : x > w - 1 ? w - 1 : x;
	y = y < 0.0 ? 0.0 : y > h - 1 ? h - 1 : y;
	int i = (int)x, j = (int)y;
	i = i > w - 2 ? w - 2 : i;
	j = j > h - 2 ? h - 2 : j;
	double fx = x - i, fy = y - j, s = 0.0, ws = 0.0;
	const double wt[4] = { (1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy };
	const float c[4] = { v[(size_t)j * w + i], v[(size_t)j * w + i + 1], v[(size_t)(j + 1) * w + i],
			     v[(size_t)(j + 1) * w + i + 1] };
	for (int k = 0; k < 4; k++)
		if (!isnan(c[k]) && wt[k] > 0.0) {
			s += wt[k] * c[k];
			ws += wt[k];
		}
	if (ws > 0.0)
		return (float)(s / ws);
	for (int k = 0; k < 4; k++) /* the weights of the valid corners were 0 */
		if (!isnan(c[k]))
			return c[k];
	return NAN;
}

/* The CRS and its transforms to and from WGS84 lon/lat. */
struct crs_xform {
	OGRSpatialReferenceH src, wgs;
	OGRCoordinateTransformationH to_ll, from_ll;
};

static void crs_xform_free(struct crs_xform *x)
{
	if (x->to_ll)
		OCTDestroyCoordinateTransformation(x->to_ll);
	if (x->from_ll)
		OCTDestroyCoordinateTransformation(x->from_ll);
	if (x->src)
		OSRRelease(x->src);
	if (x->wgs)
		OSRRelease(x->wgs);
	memset(x, 0, sizeof(*x));
}

/* src taken over (a clone of the dataset's, or one made from a name). */
static int crs_xform_make(struct crs_xform *x, OGRSpatialReferenceH src, bool inverse, char *err, size_t errlen)
{
	memset(x, 0, sizeof(*x));
	x->src = src;
	x->wgs = OSRNewSpatialReference(NULL);
	if (!x->wgs || OSRImportFromEPSG(x->wgs, 4326) != OGRERR_NONE) {
		snprintf(err, errlen, "GDAL/PROJ has no WGS84 (EPSG:4326): %s", gdal_msg("is PROJ's database installed?"));
		crs_xform_free(x);
		return -1;
	}
	OSRSetAxisMappingStrategy(x->src, OAMS_TRADITIONAL_GIS_ORDER);
	OSRSetAxisMappingStrategy(x->wgs, OAMS_TRADITIONAL_GIS_ORDER);
	x->to_ll = OCTNewCoordinateTransformation(x->src, x->wgs);
	if (inverse && x->to_ll)
		x->from_ll = OCTNewCoordinateTransformation(x->wgs, x->src);
	if (!x->to_ll || (inverse && !x->from_ll)) {
		snprintf(err, errlen, "no transformation between the CRS and WGS84: %s", gdal_msg("PROJ refused it"));
		crs_xform_free(x);
		return -1;
	}
	return 0;
}

/* n points in place through t; -1 when any fails. */
static int transform(OGRCoordinateTransformationH t, double *x, double *y, int n)
{
	int *ok = malloc(sizeof(int) * (size_t)n);
	if (!ok)
		return -1;
	int rc = OCTTransformEx(t, n, x, y, NULL, ok) ? 0 : -1;
	for (int i = 0; i < n && rc == 0; i++)
		if (!ok[i] || !isfinite(x[i]) || !isfinite(y[i]))
			rc = -1;
	free(ok);
	return rc;
}

/* The CRS's name, EPSG code (0 without one) and kind. */
static void crs_describe(OGRSpatialReferenceH s, struct geotiff_map *m)
{
	const char *name = OSRGetName(s);
	snprintf(m->crs, sizeof(m->crs), "%s", name ? name : "unnamed");
	m->projected = OSRIsProjected(s) != 0;
	const char *auth = OSRGetAuthorityName(s, NULL), *code = OSRGetAuthorityCode(s, NULL);
	if (auth && code && !strcasecmp(auth, "EPSG")) {
		m->epsg = atoi(code);
		return;
	}
	OGRSpatialReferenceH c = OSRClone(s); /* identified on a copy: the guess changes it */
	if (c && OSRAutoIdentifyEPSG(c) == OGRERR_NONE) {
		auth = OSRGetAuthorityName(c, NULL);
		code = OSRGetAuthorityCode(c, NULL);
		if (auth && code && !strcasecmp(auth, "EPSG"))
			m->epsg = atoi(code);
	}
	if (c)
		OSRRelease(c);
}

/* Pixel position (0..w, 0..h) -> (e, n) in f, through the CRS. */
static int pixel_to_enu(const double gt[6], const struct crs_xform *x, const struct geo_enu *f, double *px,
			double *py, int n)
{
	for (int i = 0; i < n; i++) {
		double cx = gt[0] + px[i] * gt[1] + py[i] * gt[2], cy = gt[3] + px[i] * gt[4] + py[i] * gt[5];
		px[i] = cx;
		py[i] = cy;
	}
	if (transform(x->to_ll, px, py, n) < 0)
		return -1;
	for (int i = 0; i < n; i++) {
		double e, nn;
		geo_enu_forward(f, px[i], py[i], &e, &nn);
		px[i] = e;
		py[i] = nn;
	}
	return 0;
}

/* The ENU grid over the raster: origin its centre, cell the finer of its
 * sample spacings there, the sides the largest that keep every node
 * within the outer samples' centres (the box inscribed in the raster's
 * outline in ENU, symmetric about the origin).  0 or -1 with err. */
static int enu_grid(const double gt[6], const struct crs_xform *x, int sw, int sh, int max_side, struct geotiff_map *m,
		    struct geo_enu *f, const char *path, char *err, size_t errlen)
{
	double cx = 0.5 * sw, cy = 0.5 * sh, lon = gt[0] + cx * gt[1] + cy * gt[2], lat = gt[3] + cx * gt[4] + cy * gt[5];
	if (transform(x->to_ll, &lon, &lat, 1) < 0 || !(fabs(lat) < 89.0)) {
		snprintf(err, errlen, "heightmap '%s': its centre has no WGS84 lon/lat near enough the equator (%s)", path,
			 gdal_msg("beyond +-89 degrees"));
		return -1;
	}
	m->lon0 = lon;
	m->lat0 = lat;
	geo_enu_init(f, lon, lat);
	/* the outline (the outer samples' centres, 65 points a side), the
	 * spacing at the centre, the corners' lon/lat */
	enum { K = 65, NP = 4 * K + 3 };
	double px[NP], py[NP];
	for (int k = 0; k < K; k++) {
		double t = (double)k / (K - 1);
		px[k] = 0.5, py[k] = 0.5 + t * (sh - 1);                     /* west */
		px[K + k] = sw - 0.5, py[K + k] = 0.5 + t * (sh - 1);        /* east */
		px[2 * K + k] = 0.5 + t * (sw - 1), py[2 * K + k] = 0.5;     /* north */
		px[3 * K + k] = 0.5 + t * (sw - 1), py[3 * K + k] = sh - 0.5; /* south */
	}
	px[4 * K] = cx, py[4 * K] = cy;
	px[4 * K + 1] = cx + 1, py[4 * K + 1] = cy;
	px[4 * K + 2] = cx, py[4 * K + 2] = cy + 1;
	if (pixel_to_enu(gt, x, f, px, py, NP) < 0) {
		snprintf(err, errlen, "heightmap '%s': its outline does not transform to WGS84: %s", path,
			 gdal_msg("out of the CRS's area"));
		return -1;
	}
	double west = -INFINITY, east = INFINITY, north = INFINITY, south = -INFINITY;
	for (int k = 0; k < K; k++) {
		west = fmax(west, px[k]);
		east = fmin(east, px[K + k]);
		north = fmin(north, py[2 * K + k]);
		south = fmax(south, py[3 * K + k]);
	}
	m->src_res[0] = hypot(px[4 * K + 1] - px[4 * K], py[4 * K + 1] - py[4 * K]);
	m->src_res[1] = hypot(px[4 * K + 2] - px[4 * K], py[4 * K + 2] - py[4 * K]);
	double cell = fmin(m->src_res[0], m->src_res[1]);
	double hx = fmin(-west, east), hz = fmin(north, -south);
	if (!(cell > 0.0) || !(hx > 0.0) || !(hz > 0.0)) {
		snprintf(err, errlen, "heightmap '%s': its geotransform gives no area (a sample of %g x %g m)", path,
			 m->src_res[0], m->src_res[1]);
		return -1;
	}
	/* too many nodes for max_side: coarser */
	double most = fmax(hx, hz) / cell * 2.0 + 1.0;
	if (most > max_side)
		cell *= most / (max_side - 1);
	int w = 2 * (int)floor(hx / cell + 1e-9) + 1, h = 2 * (int)floor(hz / cell + 1e-9) + 1;
	if (w < 2 || h < 2 || w > max_side || h > max_side) {
		snprintf(err, errlen, "heightmap '%s' is %.4g x %.4g m at %.4g m a sample: %dx%d; 2x2 to %dx%d samples "
			 "are supported", path, 2 * hx, 2 * hz, cell, w, h, max_side, max_side);
		return -1;
	}
	m->w = w;
	m->h = h;
	m->cell = cell;
	/* the raster's lon/lat box: its corners */
	double lx[4] = { 0, sw, 0, sw }, ly[4] = { 0, 0, sh, sh };
	for (int k = 0; k < 4; k++) {
		double ax = gt[0] + lx[k] * gt[1] + ly[k] * gt[2], ay = gt[3] + lx[k] * gt[4] + ly[k] * gt[5];
		lx[k] = ax;
		ly[k] = ay;
	}
	if (transform(x->to_ll, lx, ly, 4) == 0) {
		m->lonlat[0] = fmin(fmin(lx[0], lx[1]), fmin(lx[2], lx[3]));
		m->lonlat[1] = fmin(fmin(ly[0], ly[1]), fmin(ly[2], ly[3]));
		m->lonlat[2] = fmax(fmax(lx[0], lx[1]), fmax(lx[2], lx[3]));
		m->lonlat[3] = fmax(fmax(ly[0], ly[1]), fmax(ly[2], ly[3]));
	}
	return 0;
}

/* The grid's samples from the raster's (src, sw x sh, metres): each node's
 * raster position exact on a lattice every LATTICE nodes (ENU -> lon/lat
 * -> CRS -> pixel), bilinear between.  0 or -1 with err. */
static int resample(const float *src, int sw, int sh, const double gt[6], const struct crs_xform *x,
		    const struct geo_enu *f, struct geotiff_map *m, const char *path, char *err, size_t errlen)
{
	double inv[6];
	if (!GDALInvGeoTransform((double *)gt, inv)) {
		snprintf(err, errlen, "heightmap '%s': its geotransform cannot be inverted", path);
		return -1;
	}
	int lw = (m->w - 1 + LATTICE - 1) / LATTICE + 1, lh = (m->h - 1 + LATTICE - 1) / LATTICE + 1;
	size_t nl = (size_t)lw * (size_t)lh;
	double *lx = malloc(sizeof(double) * nl), *ly = malloc(sizeof(double) * nl);
	m->v = malloc(sizeof(float) * (size_t)m->w * (size_t)m->h);
	if (!lx || !ly || !m->v) {
		snprintf(err, errlen, "heightmap '%s': out of memory", path);
		goto fail;
	}
	double ci = 0.5 * (m->w - 1), cj = 0.5 * (m->h - 1);
	for (int j = 0; j < lh; j++)
		for (int i = 0; i < lw; i++) {
			double e = (fmin(i * LATTICE, m->w - 1) - ci) * m->cell, n = (cj - fmin(j * LATTICE, m->h - 1)) * m->cell;
			geo_enu_inverse(f, e, n, &lx[(size_t)j * lw + i], &ly[(size_t)j * lw + i]);
		}
	if (transform(x->from_ll, lx, ly, (int)nl) < 0) {
		snprintf(err, errlen, "heightmap '%s': the grid does not transform back to its CRS: %s", path,
			 gdal_msg("out of the CRS's area"));
		goto fail;
	}
	for (size_t k = 0; k < nl; k++) { /* CRS -> pixel */
		double a = inv[0] + lx[k] * inv[1] + ly[k] * inv[2], b = inv[3] + lx[k] * inv[4] + ly[k] * inv[5];
		lx[k] = a;
		ly[k] = b;
	}
	for (int j = 0; j < m->h; j++) {
		int J = j / LATTICE < lh - 1 ? j / LATTICE : lh - 2;
		double v0 = J * LATTICE, v1 = fmin((J + 1) * LATTICE, m->h - 1), fy = (j - v0) / (v1 - v0);
		for (int i = 0; i < m->w; i++) {
			int I = i / LATTICE < lw - 1 ? i / LATTICE : lw - 2;
			double u0 = I * LATTICE, u1 = fmin((I + 1) * LATTICE, m->w - 1), fx = (i - u0) / (u1 - u0);
			size_t a = (size_t)J * lw + I, b = a + 1, c = a + lw, d = c + 1;
			double X = (1 - fy) * ((1 - fx) * lx[a] + fx * lx[b]) + fy * ((1 - fx) * lx[c] + fx * lx[d]);
			double Y = (1 - fy) * ((1 - fx) * ly[a] + fx * ly[b]) + fy * ((1 - fx) * ly[c] + fx * ly[d]);
			m->v[(size_t)j * m->w + i] = sample(src, sw, sh, X, Y);
		}
	}
	free(lx);
	free(ly);
	return 0;
fail:
	free(lx);
	free(ly);
	free(m->v);
	m->v = NULL;
	return -1;
}

/* Samples in metres (NaN: no data) onto 0..65535 over their range. */
static int normalise(struct geotiff_map *m, const char *path, char *err, size_t errlen)
{
	size_t n = (size_t)m->w * (size_t)m->h;
	double lo = INFINITY, hi = -INFINITY;
	for (size_t i = 0; i < n; i++)
		if (!isnan(m->v[i])) {
			lo = fmin(lo, m->v[i]);
			hi = fmax(hi, m->v[i]);
		}
	if (!(lo <= hi)) {
		snprintf(err, errlen, "heightmap '%s': every sample is no-data", path);
		return -1;
	}
	double k = hi > lo ? 65535.0 / (hi - lo) : 0.0;
	for (size_t i = 0; i < n; i++)
		m->v[i] = isnan(m->v[i]) ? 0.0f : (float)((m->v[i] - lo) * k);
	m->zmin = lo;
	m->zmax = hi;
	return 0;
}

int isoterra_geotiff_load_v2(const char *path, int max_side, struct geotiff_map *m, char *err, size_t errlen)
{
	memset(m, 0, sizeof(*m));
	if (GDALGetDriverCount() == 0) /* not registered yet */
		GDALAllRegister();
	CPLPushErrorHandler(CPLQuietErrorHandler);
	CPLErrorReset();
	GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, NULL, NULL, NULL);
	if (!ds) {
		snprintf(err, errlen, "heightmap '%s': GDAL cannot read it as a GeoTIFF: %s", path,
			 gdal_msg("unknown error"));
		CPLPopErrorHandler();
		return -1;
	}
	int rc = -1;
	float *src = NULL;
	struct crs_xform x = { 0 };
	int sw = GDALGetRasterXSize(ds), sh = GDALGetRasterYSize(ds);
	GDALRasterBandH band = GDALGetRasterCount(ds) >= 1 ? GDALGetRasterBand(ds, 1) : NULL;
	char why[96];
	if (!band) {
		snprintf(err, errlen, "heightmap '%s': the GeoTIFF has no raster band", path);
		goto out;
	}
	if (colour_raster(ds, band, why, sizeof(why))) {
		snprintf(err, errlen, "heightmap '%s' is a picture (%s), not elevations: a heightmap is one band of "
			 "heights (a DEM)", path, why);
		goto out;
	}
	if (sw < 2 || sh < 2 || sw > max_side || sh > max_side) {
		snprintf(err, errlen, "heightmap '%s' is %dx%d; 2x2 to %dx%d samples are supported", path, sw, sh,
			 max_side, max_side);
		goto out;
	}
	m->src_w = sw;
	m->src_h = sh;
	src = malloc(sizeof(float) * (size_t)sw * (size_t)sh);
	if (!src) {
		snprintf(err, errlen, "heightmap '%s': out of memory", path);
		goto out;
	}
	CPLErrorReset();
	if (GDALRasterIO(band, GF_Read, 0, 0, sw, sh, src, sw, sh, GDT_Float32, 0, 0) != CE_None) {
		snprintf(err, errlen, "heightmap '%s': GDAL cannot read the samples: %s", path, gdal_msg("read error"));
		goto out;
	}
	double gt[6];
	OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
	m->georef = srs && GDALGetGeoTransform(ds, gt) == CE_None;
	if (to_metres(band, src, (size_t)sw * (size_t)sh, m->unit, sizeof(m->unit), path, err, errlen) < 0)
		goto out;
	if (!m->georef) { /* the samples as they are, one per sample */
		m->v = src;
		m->w = sw;
		m->h = sh;
		src = NULL;
	} else {
		OGRSpatialReferenceH own = OSRClone(srs);
		if (!own) {
			snprintf(err, errlen, "heightmap '%s': out of memory", path);
			goto out;
		}
		crs_describe(own, m);
		struct geo_enu f;
		char e[512];
		if (crs_xform_make(&x, own, true, e, sizeof(e)) < 0) {
			snprintf(err, errlen, "heightmap '%s' (%s): %s", path, m->crs, e);
			goto out;
		}
		if (enu_grid(gt, &x, sw, sh, max_side, m, &f, path, err, errlen) < 0 ||
		    resample(src, sw, sh, gt, &x, &f, m, path, err, errlen) < 0)
			goto out;
	}
	if (normalise(m, path, err, errlen) < 0)
		goto out;
	rc = 0;
out:
	if (rc < 0) {
		free(m->v);
		m->v = NULL;
	}
	crs_xform_free(&x);
	free(src);
	GDALClose(ds);
	CPLPopErrorHandler();
	return rc;
}

int isoterra_geotiff_to_lonlat_v2(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err,
				  size_t errlen)
{
	if (n > (size_t)1 << 30) {
		snprintf(err, errlen, "%zu positions: too many to transform", n);
		return -1;
	}
	CPLPushErrorHandler(CPLQuietErrorHandler);
	CPLErrorReset();
	int rc = -1;
	double *x = malloc(sizeof(double) * (n ? n : 1)), *y = malloc(sizeof(double) * (n ? n : 1));
	struct crs_xform t = { 0 };
	OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
	if (!x || !y || !s) {
		snprintf(err, errlen, "out of memory");
		if (s)
			OSRRelease(s);
		goto out;
	}
	if (OSRSetFromUserInput(s, crs) != OGRERR_NONE) {
		snprintf(err, errlen, "'%s' is no CRS GDAL/PROJ knows: %s", crs, gdal_msg("unknown"));
		OSRRelease(s);
		goto out;
	}
	const char *nm = OSRGetName(s);
	snprintf(name, namelen, "%s", nm ? nm : crs);
	if (crs_xform_make(&t, s, false, err, errlen) < 0)
		goto out;
	for (size_t i = 0; i < n; i++) {
		x[i] = xy[2 * i];
		y[i] = xy[2 * i + 1];
	}
	if (n && transform(t.to_ll, x, y, (int)n) < 0) {
		snprintf(err, errlen, "positions outside what %s can transform to WGS84: %s", name,
			 gdal_msg("out of its area"));
		goto out;
	}
	for (size_t i = 0; i < n; i++) {
		xy[2 * i] = x[i];
		xy[2 * i + 1] = y[i];
	}
	rc = 0;
out:
	crs_xform_free(&t);
	free(x);
	free(y);
	CPLPopErrorHandler();
	return rc;
}
