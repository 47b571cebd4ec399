/* isoterra — the GeoTIFF module (geo_module.h) found and loaded: from
 * $ISOTERRA_MODULE_DIR (the build tree's tests), the program's own folder
 * (an uninstalled build), then the installed ISOTERRA_MODULE_DIR.  Loaded
 * once, kept for the process. */
#include "geo_module.h"

#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifdef ISOTERRA_HAVE_GDAL
#include <dlfcn.h>

static void *module(char *err, size_t errlen)
{
	static void *handle;
	if (handle)
		return handle;
	char dirs[3][PATH_MAX];
	int nd = 0;
	const char *env = getenv("ISOTERRA_MODULE_DIR");
	if (env && env[0])
		snprintf(dirs[nd++], PATH_MAX, "%s", env);
	ssize_t n = readlink("/proc/self/exe", dirs[nd], PATH_MAX - 1);
	if (n > 0) {
		dirs[nd][n] = 0;
		char *slash = strrchr(dirs[nd], '/');
		if (slash) {
			*slash = 0;
			nd++;
		}
	}
	snprintf(dirs[nd++], PATH_MAX, "%s", ISOTERRA_MODULE_DIR);
	char tried[3 * PATH_MAX + 64] = "", why[PATH_MAX + 256] = "";
	for (int i = 0; i < nd; i++) {
		char path[PATH_MAX + 32];
		int k = snprintf(path, sizeof(path), "%s/%s", dirs[i], GEOTIFF_MODULE);
		if (k < 0 || (size_t)k >= sizeof(path))
			continue;
		void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
		if (h && dlsym(h, GEOTIFF_SYMBOL) && dlsym(h, GEOTIFF_TO_LONLAT_SYMBOL))
			return handle = h;
		if (h) {
			k = snprintf(why, sizeof(why), "%s has no %s (another version's module)", path, GEOTIFF_SYMBOL);
			dlclose(h);
		} else if (access(path, F_OK) == 0) {
			k = snprintf(why, sizeof(why), "%s", dlerror());
		}
		size_t u = strlen(tried);
		k = snprintf(tried + u, sizeof(tried) - u, "%s%s", u ? ", " : "", dirs[i]);
		if (k < 0 || (size_t)k >= sizeof(tried) - u)
			break;
	}
	snprintf(err, errlen, "need the module %s (GDAL), not loaded from %s%s%s", GEOTIFF_MODULE, tried,
		 why[0] ? ": " : "", why);
	return NULL;
}

geotiff_load_fn geo_module_load(char *err, size_t errlen)
{
	void *h = module(err, errlen);
	return h ? (geotiff_load_fn)(uintptr_t)dlsym(h, GEOTIFF_SYMBOL) : NULL;
}

int geo_crs_to_lonlat(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err, size_t errlen)
{
	char e[PATH_MAX * 4];
	void *h = module(e, sizeof(e));
	if (!h) {
		snprintf(err, errlen, "CRS %s: its transform to lon/lat (GDAL's OSR) %s", crs, e);
		return -1;
	}
	geotiff_to_lonlat_fn fn = (geotiff_to_lonlat_fn)(uintptr_t)dlsym(h, GEOTIFF_TO_LONLAT_SYMBOL);
	return fn(crs, xy, n, name, namelen, err, errlen);
}
#else
geotiff_load_fn geo_module_load(char *err, size_t errlen)
{
	snprintf(err, errlen, "GeoTIFF needs GDAL, which this build does not use");
	return NULL;
}

int geo_crs_to_lonlat(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err, size_t errlen)
{
	(void)xy;
	(void)n;
	(void)name;
	(void)namelen;
	snprintf(err, errlen, "CRS %s: EPSG-coded coordinates are transformed through GDAL, which this build does not "
		 "use (lon/lat and world units work without it)", crs);
	return -1;
}
#endif
