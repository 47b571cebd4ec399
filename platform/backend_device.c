/* isoterra — headless backend on EGL_EXT_platform_device: enumerate EGL
 * devices, prefer a real GPU (a DRM device that is not Mesa's software
 * device), accept the software device only when nothing else works; or
 * the one device asked for (--device N|PATH, $ISOTERRA_DEVICE). */
#include "platform.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <GLES3/gl31.h>

#include "platform_util.h"

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

static const char *const kind_names[] = { "GPU", "other", "software" };

/* The device's DRM device file (EGL_EXT_device_drm) and render node
 * (EGL_EXT_device_drm_render_node); NULL where it has none. */
static void device_drm_files(const struct device_api *api, EGLDeviceEXT dev, const char **card, const char **render)
{
	const char *exts = api->query_string(dev, EGL_EXTENSIONS);
	*card = *render = NULL;
	if (exts && egl_common_has_ext(exts, "EGL_EXT_device_drm"))
		*card = api->query_string(dev, EGL_DRM_DEVICE_FILE_EXT);
	if (exts && egl_common_has_ext(exts, "EGL_EXT_device_drm_render_node"))
		*render = api->query_string(dev, EGL_DRM_RENDER_NODE_FILE_EXT);
	(void)eglGetError();
}

/* DRM node of the device, its render node first ("/dev/dri/renderD128"),
 * or NULL. */
static const char *device_node(const struct device_api *api, EGLDeviceEXT dev)
{
	const char *card, *render;
	device_drm_files(api, dev, &card, &render);
	return render ? render : card;
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

/* Same DRM node: the same name, or (symbolic links, /dev/dri/by-path/...)
 * the same character device. */
static bool same_node(const char *a, const char *b)
{
	if (!a || !b)
		return false;
	if (!strcmp(a, b))
		return true;
	struct stat sa, sb;
	return stat(a, &sa) == 0 && stat(b, &sb) == 0 && S_ISCHR(sa.st_mode) && S_ISCHR(sb.st_mode) &&
	       sa.st_rdev == sb.st_rdev;
}

/* The first device from index `from` on that the spec names (an index,
 * or a DRM node path: several devices may have the node, as when the GPU's
 * vendor EGL and Mesa both list it), or -1, with err when it names none at
 * all.  what: how the user gave it ("--device", "ISOTERRA_DEVICE"). */
static int device_find(const struct device_api *api, const EGLDeviceEXT *devs, EGLint n, const char *spec,
                       EGLint from, const char *what, char *err, size_t errlen)
{
	if (platform_device_check(spec, err, errlen) < 0)
		return -1;
	if (spec[0] != '/') {
		long i = strtol(spec, NULL, 10);
		if (from > 0)
			return -1;
		if (i < n)
			return (int)i;
		if (n == 1)
			snprintf(err, errlen, "%s %s: there is one EGL device, 0 (see --list-devices)", what, spec);
		else
			snprintf(err, errlen, "%s %s: there are %d EGL devices, 0..%d (see --list-devices)", what, spec,
			         (int)n, (int)n - 1);
		return -1;
	}
	for (EGLint i = from; i < n; i++) {
		const char *card, *render;
		device_drm_files(api, devs[i], &card, &render);
		if (same_node(spec, card) || same_node(spec, render))
			return (int)i;
	}
	if (from > 0)
		return -1;
	struct stat st;
	const char *why = stat(spec, &st) < 0 ? strerror(errno) : NULL;
	snprintf(err, errlen, "%s %.200s: no EGL device has this DRM node%s%s (%d device%s; see --list-devices)", what,
	         spec, why ? ": " : "", why ? why : "", (int)n, n == 1 ? "" : "s");
	return -1;
}

/* The device spec given (--device, else $ISOTERRA_DEVICE), or NULL. */
static const char *device_wanted(const struct platform_options *opt, const char **what)
{
	*what = "--device";
	if (opt->device && opt->device[0])
		return opt->device;
	*what = "ISOTERRA_DEVICE";
	const char *env = getenv("ISOTERRA_DEVICE");
	return env && env[0] ? env : NULL;
}

static int device_open(struct platform *p, const struct platform_options *opt,
                       char *err, size_t errlen)
{
	struct device_api api;
	EGLDeviceEXT devs[MAX_DEVICES];
	EGLint n;
	if (device_api_load(&api, err, errlen) < 0 || device_list(&api, devs, &n, err, errlen) < 0)
		return -1;

	const char *what, *want = device_wanted(opt, &what);
	if (want) {
		/* that device; a node's devices in order until one opens */
		for (int i = device_find(&api, devs, n, want, 0, what, err, errlen); i >= 0;
		     i = device_find(&api, devs, n, want, i + 1, what, err, errlen)) {
			const char *node = device_node(&api, devs[i]);
			char why[256];
			if (open_one(p, opt, &api, devs[i], why, sizeof(why)) == 0) {
				plog_debug("EGL device %d of %d%s%s (%s %s): %s", i, (int)n, node ? " " : "",
				          node ? node : "", what, want, p->device_desc);
				return 0;
			}
			plog_debug("EGL device %d%s%s: %s", i, node ? " " : "", node ? node : "", why);
			snprintf(err, errlen, "EGL device %d%s%s (%s %s): %s", i, node ? " " : "", node ? node : "", what,
			         want, why);
		}
		return -1;
	}

	/* Real GPUs first, then unknown kinds, the software device last. */
	char why[256] = "";
	for (int kind = DEV_GPU; kind <= DEV_SOFTWARE; kind++) {
		for (EGLint i = 0; i < n; i++) {
			if ((int)device_kind(&api, devs[i]) != kind)
				continue;
			const char *node = device_node(&api, devs[i]);
			if (open_one(p, opt, &api, devs[i], why, sizeof(why)) == 0) {
				plog_debug("EGL device %d of %d%s%s: %s", (int)i, (int)n,
				          node ? " " : "", node ? node : "", p->device_desc);
				return 0;
			}
			plog_debug("EGL device %d%s%s: %s", (int)i, node ? " " : "", node ? node : "", why);
			snprintf(err, errlen, "EGL device %d%s%s: %s", (int)i, node ? " " : "",
			         node ? node : "", why);
		}
	}
	return -1;
}

/* ---- --list-devices ------------------------------------------------------ */

int platform_list_devices(FILE *f, char *err, size_t errlen)
{
	struct device_api api;
	EGLDeviceEXT devs[MAX_DEVICES];
	EGLint n = 0;
	if (device_api_load(&api, err, errlen) < 0)
		return -1;
	if (!api.query_devices(MAX_DEVICES, devs, &n)) {
		snprintf(err, errlen, "eglQueryDevicesEXT failed: %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	if (n <= 0) {
		fprintf(f, "no EGL device (EGL_EXT_platform_device lists none)\n");
		return 0;
	}
	fprintf(f, "EGL devices, in eglQueryDevicesEXT's order (--platform device --device N|PATH):\n");
	/* what --platform device picks without --device: the first that opens
	 * of the GPUs, then the other kinds, then the software device */
	int pick = -1, pick_kind = DEV_SOFTWARE + 1;
	for (EGLint i = 0; i < n; i++) {
		enum dev_kind kind = device_kind(&api, devs[i]);
		const char *card, *render;
		device_drm_files(&api, devs[i], &card, &render);
		fprintf(f, "%d: %s", (int)i, kind_names[kind]);
		if (card)
			fprintf(f, ", %s", card);
		if (render)
			fprintf(f, ", %s", render);
		if (!card && !render)
			fprintf(f, ", no DRM node");
		fputc('\n', f);
		/* a context on it: the renderer the tests and the program see */
		struct platform p;
		memset(&p, 0, sizeof(p));
		p.dpy = EGL_NO_DISPLAY;
		p.ctx = EGL_NO_CONTEXT;
		p.surface = EGL_NO_SURFACE;
		struct platform_options opt = { .name = "device" };
		char why[256] = "";
		if (egl_common_open_display(&p, EGL_PLATFORM_DEVICE_EXT, devs[i], why, sizeof(why)) == 0) {
			const char *vendor = eglQueryString(p.dpy, EGL_VENDOR);
			const char *dexts = eglQueryString(p.dpy, EGL_EXTENSIONS);
			const char *driver = NULL;
			if (dexts && egl_common_has_ext(dexts, "EGL_MESA_query_driver")) {
				PFNEGLGETDISPLAYDRIVERNAMEPROC name =
					(PFNEGLGETDISPLAYDRIVERNAMEPROC)eglGetProcAddress("eglGetDisplayDriverName");
				driver = name ? name(p.dpy) : NULL;
			}
			fprintf(f, "   EGL: vendor %s%s%s\n", vendor ? vendor : "unknown", driver ? ", driver " : "",
			        driver ? driver : "");
			if (egl_common_make_context(&p, &opt, 0, why, sizeof(why)) == 0) {
				const char *ver = (const char *)glGetString(GL_VERSION);
				fprintf(f, "   GL: %s | %s\n", p.device_desc, ver ? ver : "unknown version");
				if ((int)kind < pick_kind) {
					pick = (int)i;
					pick_kind = (int)kind;
				}
			}
		}
		if (why[0])
			fprintf(f, "   no context: %s\n", why);
		egl_common_release(&p);
		const char *exts = api.query_string(devs[i], EGL_EXTENSIONS);
		if (!exts)
			(void)eglGetError();
		fprintf(f, "   extensions: %s\n", exts && exts[0] ? exts : "(none)");
	}
	if (pick >= 0)
		fprintf(f, "without --device, --platform device opens %d\n", pick);
	else
		fprintf(f, "without --device, --platform device opens none (no device gives an OpenGL ES 3.1 context)\n");
	return 0;
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
