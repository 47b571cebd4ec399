/* isoterra — the local east-north-up frame of WGS84 at one point: the
 * tangent plane's east and north, in metres, of positions on the
 * ellipsoid (geo_enu.c).  The one horizontal frame every georeferenced
 * input is put in: a DEM's samples (the GeoTIFF module) and lon/lat
 * curves (curves_geo.c).  Pure arithmetic: the core and the module both
 * build it. */
#ifndef ISOTERRA_GEO_ENU_H
#define ISOTERRA_GEO_ENU_H

struct geo_enu {
	double lon0, lat0; /* the origin, degrees */
	double o[3];       /* its ECEF position, metres */
	double east[3], north[3];
};

/* The frame whose origin is (lon0, lat0) on the ellipsoid (degrees). */
void geo_enu_init(struct geo_enu *f, double lon0, double lat0);
/* East and north (metres) of the ellipsoid's point at (lon, lat). */
void geo_enu_forward(const struct geo_enu *f, double lon, double lat, double *e, double *n);
/* The ellipsoid's point whose east and north are (e, n): its lon/lat
 * (degrees, lon within [-180, 180]); a millimetre or better within a few
 * hundred kilometres of the origin. */
void geo_enu_inverse(const struct geo_enu *f, double e, double n, double *lon, double *lat);

#endif
