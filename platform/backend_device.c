/* isoterra — headless backend on EGL_EXT_platform_device: enumerate EGL
 * devices, prefer a real GPU (a DRM device that is not Mesa's software
 * device), accept the software device only when nothing else works. */
#include "platform.h"

#include <stdio.h>
#include <string.h>

#include "log.h"

#define MAX_DEVICES 32

enum dev_kind { DEV_GPU, DEV_OTHER, DEV_SOFTWARE };

struct device_api {
	PFNEGLQUERYDEVICESEXTPROC query_devices;
	PFNEGLQUERYDEVICESTRINGEXTPROC query_string;
};

static int device_api_load(struct device_api *api, char *err, size_t errlen)
{
	const char *cexts = egl_common_client_exts();
	bool base = egl_common_has_ext(cexts, "EGL_EXT_device_base");
	if (!egl_common_has_ext(cexts, "EGL_EXT_platform_device")) {
		snprintf(err, errlen, "EGL_EXT_platform_device not supported by this EGL");
		return -1;
	}
	if (!base && !egl_common_has_ext(cexts, "EGL_EXT_device_enumeration")) {
		snprintf(err, errlen, "EGL_EXT_device_enumeration not supported by this EGL");
		return -1;
	}
	if (!base && !egl_common_has_ext(cexts, "EGL_EXT_device_query")) {
		snprintf(err, errlen, "EGL_EXT_device_query not supported by this EGL");
		return -1;
	}
	api->query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
	api->query_string = (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
	if (!api->query_devices || !api->query_string) {
		snprintf(err, errlen, "eglQueryDevicesEXT/eglQueryDeviceStringEXT not found in this EGL");
		return -1;
	}
	return 0;
}

static int device_list(const struct device_api *api, EGLDeviceEXT *devs, EGLint *n,
                       char *err, size_t errlen)
{
	*n = 0;
	if (!api->query_devices(MAX_DEVICES, devs, n)) {
		snprintf(err, errlen, "eglQueryDevicesEXT failed: %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	if (*n <= 0) {
		snprintf(err, errlen, "no EGL device found");
		return -1;
	}
	return 0;
}

static enum dev_kind device_kind(const struct device_api *api, EGLDeviceEXT dev)
{
	const char *exts = api->query_string(dev, EGL_EXTENSIONS);
	if (!exts) {
		(void)eglGetError();
		return DEV_OTHER;
	}
	if (egl_common_has_ext(exts, "EGL_MESA_device_software"))
		return DEV_SOFTWARE;
	if (egl_common_has_ext(exts, "EGL_EXT_device_drm") ||
	    egl_common_has_ext(exts, "EGL_EXT_device_drm_render_node"))
		return DEV_GPU;
	return DEV_OTHER;
}

/* DRM node of the device ("/dev/dri/renderD128"), or NULL. */
static const char *device_node(const struct device_api *api, EGLDeviceEXT dev)
{
	const char *exts = api->query_string(dev, EGL_EXTENSIONS);
	const char *node = NULL;
	if (exts && egl_common_has_ext(exts, "EGL_EXT_device_drm_render_node"))
		node = api->query_string(dev, EGL_DRM_RENDER_NODE_FILE_EXT);
	if (!node && exts && egl_common_has_ext(exts, "EGL_EXT_device_drm"))
		node = api->query_string(dev, EGL_DRM_DEVICE_FILE_EXT);
	if (!node)
		(void)eglGetError();
	return node;
}

static bool device_probe(void)
{
	struct device_api api;
	EGLDeviceEXT devs[MAX_DEVICES];
	EGLint n;
	char err[160];
	if (device_api_load(&api, err, sizeof(err)) < 0 || device_list(&api, devs, &n, err, sizeof(err)) < 0)
		return false;
	for (EGLint i = 0; i < n; i++)
		if (device_kind(&api, devs[i]) == DEV_GPU)
			return true;
	return false;
}

static void device_close(struct platform *p)
{
	egl_common_release(p);
}

static int open_one(struct platform *p, const struct platform_options *opt,
                    const struct device_api *api, EGLDeviceEXT dev, char *err, size_t errlen)
{
	if (egl_common_open_display(p, EGL_PLATFORM_DEVICE_EXT, dev, err, errlen) < 0 ||
	    egl_common_make_context(p, opt, 0, err, errlen) < 0) {
		device_close(p);
		return -1;
	}
	const char *node = device_node(api, dev);
	size_t len = strlen(p->device_desc);
	if (node && len + strlen(node) + 4 < sizeof(p->device_desc))
		snprintf(p->device_desc + len, sizeof(p->device_desc) - len, " (%s)", node);
	return 0;
}

static int device_open(struct platform *p, const struct platform_options *opt,
                       char *err, size_t errlen)
{
	struct device_api api;
	EGLDeviceEXT devs[MAX_DEVICES];
	EGLint n;
	if (device_api_load(&api, err, errlen) < 0 || device_list(&api, devs, &n, err, errlen) < 0)
		return -1;

	/* Real GPUs first, then unknown kinds, the software device last. */
	char why[256] = "";
	for (int kind = DEV_GPU; kind <= DEV_SOFTWARE; kind++) {
		for (EGLint i = 0; i < n; i++) {
			if ((int)device_kind(&api, devs[i]) != kind)
				continue;
			const char *node = device_node(&api, devs[i]);
			if (open_one(p, opt, &api, devs[i], why, sizeof(why)) == 0) {
				log_debug("EGL device %d of %d%s%s: %s", (int)i, (int)n,
				          node ? " " : "", node ? node : "", p->device_desc);
				return 0;
			}
			log_debug("EGL device %d%s%s: %s", (int)i, node ? " " : "", node ? node : "", why);
			snprintf(err, errlen, "EGL device %d%s%s: %s", (int)i, node ? " " : "",
			         node ? node : "", why);
		}
	}
	return -1;
}

static int device_present(struct platform *p)
{
	(void)p;
	return 0;
}

const struct platform_backend platform_backend_device = {
	.name = "device",
	.probe = device_probe,
	.open = device_open,
	.close = device_close,
	.present = device_present,
};
