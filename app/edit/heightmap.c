/* isoterra — heightmap files: 16-bit grayscale PNG in and out. */
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

#ifdef ISOTERRA_HAVE_GDAL
#include "geotiff.h"
#include <dlfcn.h>

/* The GeoTIFF module: from $ISOTERRA_MODULE_DIR (the build tree's tests),
 * the program's own folder (an uninstalled build), then the installed
 * ISOTERRA_MODULE_DIR.  Loaded once, kept for the process. */
static geotiff_load_fn geotiff_module(char *err, size_t errlen)
{
	static geotiff_load_fn fn;
	if (fn)
		return fn;
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
		if (h && (fn = (geotiff_load_fn)(uintptr_t)dlsym(h, GEOTIFF_SYMBOL)))
			return fn;
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
	snprintf(err, errlen, "GeoTIFF heightmaps need the module %s (GDAL), not loaded from %s%s%s", GEOTIFF_MODULE,
		 tried, why[0] ? ": " : "", why);
	return NULL;
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
		geotiff_load_fn load = geotiff_module(e, sizeof(e));
		if (!load) {
			snprintf(err, errlen, "heightmap '%s': %s", path, e);
			return -1;
		}
		return load(path, HEIGHTMAP_MAX_SIDE, &hm->v, &hm->w, &hm->h, err, errlen);
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

