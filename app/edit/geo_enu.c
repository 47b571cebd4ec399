/* isoterra — the local east-north-up frame of WGS84 (geo_enu.h): geodetic
 * to ECEF, rotated onto the origin's east and north; the inverse by
 * fixed-point iteration over the forward map. */
#include "geo_enu.h"

#include <math.h>

#define WGS84_A 6378137.0
#define WGS84_F (1.0 / 298.257223563)
#define DEG (3.14159265358979323846 / 180.0)

static void ecef(double lon, double lat, double out[3])
{
	double e2 = WGS84_F * (2.0 - WGS84_F), sl = sin(lat * DEG), cl = cos(lat * DEG);
	double N = WGS84_A / sqrt(1.0 - e2 * sl * sl);
	out[0] = N * cl * cos(lon * DEG);
	out[1] = N * cl * sin(lon * DEG);
	out[2] = N * (1.0 - e2) * sl;
}

/* ECEF to lon/lat (degrees): the latitude iterated (Heiskanen-Moritz),
 * the height discarded. */
static void geodetic(const double x[3], double *lon, double *lat)
{
	double e2 = WGS84_F * (2.0 - WGS84_F), p = hypot(x[0], x[1]);
	double phi = atan2(x[2], p * (1.0 - e2));
	for (int i = 0; i < 6; i++) {
		double s = sin(phi), N = WGS84_A / sqrt(1.0 - e2 * s * s);
		double h = fabs(cos(phi)) > 1e-9 ? p / cos(phi) - N : fabs(x[2]) - N * (1.0 - e2);
		phi = atan2(x[2], p * (1.0 - e2 * N / (N + h)));
	}
	*lon = atan2(x[1], x[0]) / DEG;
	*lat = phi / DEG;
}

void geo_enu_init(struct geo_enu *f, double lon0, double lat0)
{
	f->lon0 = lon0;
	f->lat0 = lat0;
	ecef(lon0, lat0, f->o);
	double sl = sin(lon0 * DEG), cl = cos(lon0 * DEG), sp = sin(lat0 * DEG), cp = cos(lat0 * DEG);
	f->east[0] = -sl;
	f->east[1] = cl;
	f->east[2] = 0.0;
	f->north[0] = -sp * cl;
	f->north[1] = -sp * sl;
	f->north[2] = cp;
}

void geo_enu_forward(const struct geo_enu *f, double lon, double lat, double *e, double *n)
{
	double x[3];
	ecef(lon, lat, x);
	double d[3] = { x[0] - f->o[0], x[1] - f->o[1], x[2] - f->o[2] };
	*e = f->east[0] * d[0] + f->east[1] * d[1] + f->east[2] * d[2];
	*n = f->north[0] * d[0] + f->north[1] * d[1] + f->north[2] * d[2];
}

void geo_enu_inverse(const struct geo_enu *f, double e, double n, double *lon, double *lat)
{
	/* the tangent plane's point (e, n) taken down onto the ellipsoid moves
	 * its east and north by O(d^3 / R^2): aim that much further, again */
	double ge = e, gn = n;
	for (int i = 0; i < 8; i++) {
		double x[3];
		for (int k = 0; k < 3; k++)
			x[k] = f->o[k] + ge * f->east[k] + gn * f->north[k];
		geodetic(x, lon, lat);
		double fe, fn;
		geo_enu_forward(f, *lon, *lat, &fe, &fn);
		if (fabs(fe - e) < 1e-5 && fabs(fn - n) < 1e-5)
			break;
		ge += e - fe;
		gn += n - fn;
	}
}
