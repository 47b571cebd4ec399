/* isoterra — backend table and selection ("auto"). */
#include "platform.h"
#include "platform_util.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Display backends behind their meson options (-Dgbm, -Dwayland, -Dx11),
 * then the headless ones. */
static const struct platform_backend *const backends[] = {
#ifdef ISOTERRA_HAVE_GBM
	&platform_backend_gbm,
#endif
#ifdef ISOTERRA_HAVE_WAYLAND
	&platform_backend_wayland,
#endif
#ifdef ISOTERRA_HAVE_X11
	&platform_backend_x11,
#endif
	&platform_backend_device,
	&platform_backend_surfaceless,
};
#define NBACKENDS (ARRAY_SIZE(backends))

const char *platform_backend_names(void)
{
	static char names[128];
	if (!names[0]) {
		size_t len = 0;
		for (size_t i = 0; i < NBACKENDS; i++) {
			int n = snprintf(names + len, sizeof(names) - len, "%s%s", i ? " " : "", backends[i]->name);
			if (n < 0 || (size_t)n >= sizeof(names) - len)
				break;
			len += (size_t)n;
		}
	}
	return names;
}

static void reset(struct platform *p)
{
	memset(p, 0, sizeof(*p));
	p->dpy = EGL_NO_DISPLAY;
	p->ctx = EGL_NO_CONTEXT;
	p->surface = EGL_NO_SURFACE;
	p->config = NULL;
}

static int try_backend(struct platform *p, const struct platform_backend *b,
                       const struct platform_options *opt, char *err, size_t errlen)
{
	reset(p);
	p->backend = b;
	if (b->open(p, opt, err, errlen) < 0) {
		reset(p);
		return -1;
	}
	plog_debug("platform '%s': %s", b->name, p->device_desc);
	return 0;
}

static const struct platform_backend *find_backend(const char *name)
{
	for (size_t i = 0; i < NBACKENDS; i++)
		if (strcmp(backends[i]->name, name) == 0)
			return backends[i];
	return NULL;
}

static bool env_set(const char *name)
{
	const char *v = getenv(name);
	return v && v[0];
}

/* auto: what the environment offers — a Wayland compositor (WAYLAND_DISPLAY),
 * an X server (DISPLAY), a DRM card with a connected output — else headless:
 * a device that is a real GPU, else surfaceless, else any EGL device (Mesa's
 * software device).  A display backend that fails is reported and skipped. */
static int open_auto(struct platform *p, const struct platform_options *opt, char *err, size_t errlen)
{
	static const struct {
		const char *backend, *env;
	} displays[] = { { "wayland", "WAYLAND_DISPLAY" }, { "x11", "DISPLAY" }, { "gbm", NULL } };
	for (size_t i = 0; i < ARRAY_SIZE(displays); i++) {
		const struct platform_backend *b = find_backend(displays[i].backend);
		if (!b || (displays[i].env && !env_set(displays[i].env)) || !b->probe())
			continue;
		char why[256];
		if (try_backend(p, b, opt, why, sizeof(why)) == 0)
			return 0;
		plog_warn("platform auto: %s: %s; trying the next platform", b->name, why);
	}
	char e_dev[256] = "no EGL device is a GPU", e_sl[256] = "EGL_MESA_platform_surfaceless not supported by this EGL";
	bool tried_device = false;
	if (platform_backend_device.probe()) {
		tried_device = true;
		if (try_backend(p, &platform_backend_device, opt, e_dev, sizeof(e_dev)) == 0)
			return 0;
	}
	if (platform_backend_surfaceless.probe() &&
	    try_backend(p, &platform_backend_surfaceless, opt, e_sl, sizeof(e_sl)) == 0)
		return 0;
	if (!tried_device && try_backend(p, &platform_backend_device, opt, e_dev, sizeof(e_dev)) == 0)
		return 0;
	snprintf(err, errlen, "no usable EGL platform (device: %.200s; surfaceless: %.200s)", e_dev, e_sl);
	return -1;
}

/* EGL displays are per process and eglTerminate is not reference counted
 * (no EGL_KHR_display_reference): closing one of two platforms on the same
 * display would pull the context from under the other. */
static bool is_open;

struct platform *platform_open(const struct platform_options *opt, char *err, size_t errlen)
{
	static const struct platform_options defaults = { .name = "auto" };
	if (!opt)
		opt = &defaults;
	if (is_open) {
		snprintf(err, errlen, "a platform is already open (one at a time per process)");
		return NULL;
	}
	const char *name = opt->name && opt->name[0] ? opt->name : "auto";
	const struct platform_backend *b = NULL;
	if (opt->outputs && opt->outputs[0]) {
		/* KMS connectors: the gbm backend's (auto: that one) */
		if (strcmp(name, "auto") && strcmp(name, "gbm")) {
			snprintf(err, errlen, "--outputs '%.64s' names KMS connectors: it needs --platform gbm (or auto), not '%s'",
			         opt->outputs, name);
			return NULL;
		}
		b = find_backend("gbm");
		if (!b) {
			snprintf(err, errlen, "--outputs '%.64s': this build has no gbm platform (compiled in: %s)", opt->outputs,
			         platform_backend_names());
			return NULL;
		}
	} else if (strcmp(name, "auto") == 0 && opt->device && opt->device[0]) {
		b = &platform_backend_device; /* a device asked for: that EGL device */
	} else if (strcmp(name, "auto") != 0) {
		b = find_backend(name);
		if (!b) {
			snprintf(err, errlen, "unknown platform '%s' (compiled in: %s)", name, platform_backend_names());
			return NULL;
		}
	}
	struct platform *p = calloc(1, sizeof(*p));
	if (!p) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	egl_common_debug_callback(true, opt->debug);
	int rc = b ? try_backend(p, b, opt, err, errlen) : open_auto(p, opt, err, errlen);
	if (rc < 0) {
		egl_common_debug_callback(false, false);
		free(p);
		return NULL;
	}
	is_open = true;
	return p;
}

void platform_close(struct platform *p)
{
	if (!p)
		return;
	if (p->backend)
		p->backend->close(p);
	egl_common_debug_callback(false, false);
	free(p);
	is_open = false;
}

int platform_present(struct platform *p)
{
	int rc = p->backend->present(p);
	if (rc == 0)
		p->presented++;
	return rc;
}

int platform_dispatch(struct platform *p)
{
	return p->backend->dispatch ? p->backend->dispatch(p) : 0;
}
