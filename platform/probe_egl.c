/* isoterra — --probe: the EGL client extensions and the EGL devices
 * (EGL_EXT_device_enumeration), as platform_probe.h describes. */
#include "platform.h"
#include "platform_probe.h"

#include <stdio.h>
#include <string.h>

void platform_probe_egl(struct probe_egl *out)
{
	memset(out, 0, sizeof(*out));
	const char *client = egl_common_client_exts();
	snprintf(out->client_exts, sizeof(out->client_exts), "%s", client);
	out->can_enumerate = egl_common_has_ext(client, "EGL_EXT_device_enumeration") ||
			     egl_common_has_ext(client, "EGL_EXT_device_base");
	if (!out->can_enumerate) {
		snprintf(out->err, sizeof(out->err), "EGL has no EGL_EXT_device_enumeration");
		return;
	}
	PFNEGLQUERYDEVICESEXTPROC query = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
	PFNEGLQUERYDEVICESTRINGEXTPROC qstr =
		(PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
	EGLDeviceEXT devs[PROBE_MAX_EGL];
	EGLint n = 0;
	if (!query || !qstr) {
		snprintf(out->err, sizeof(out->err), "eglQueryDevicesEXT is missing");
		return;
	}
	if (!query(PROBE_MAX_EGL, devs, &n)) {
		snprintf(out->err, sizeof(out->err), "eglQueryDevicesEXT failed: %s",
			 egl_common_error_name(eglGetError()));
		return;
	}
	out->ndev = n;
	for (EGLint i = 0; i < n; i++) {
		struct probe_egl_device *d = &out->dev[i];
		const char *exts = qstr(devs[i], EGL_EXTENSIONS);
		(void)eglGetError();
		snprintf(d->exts, sizeof(d->exts), "%s", exts ? exts : "");
		/* the same kinds as the device backend's choice (backend_device.c) */
		d->kind = "other";
		if (egl_common_has_ext(d->exts, "EGL_MESA_device_software"))
			d->kind = "software";
		else if (egl_common_has_ext(d->exts, "EGL_EXT_device_drm") ||
			 egl_common_has_ext(d->exts, "EGL_EXT_device_drm_render_node"))
			d->kind = "GPU";
		const char *s;
		if (egl_common_has_ext(d->exts, "EGL_EXT_device_drm") && (s = qstr(devs[i], EGL_DRM_DEVICE_FILE_EXT)))
			snprintf(d->card, sizeof(d->card), "%s", s);
		if (egl_common_has_ext(d->exts, "EGL_EXT_device_drm_render_node") &&
		    (s = qstr(devs[i], EGL_DRM_RENDER_NODE_FILE_EXT)))
			snprintf(d->render, sizeof(d->render), "%s", s);
		(void)eglGetError();
	}
}

#ifndef ISOTERRA_HAVE_GBM
void platform_probe_drm(struct probe_drm *out)
{
	memset(out, 0, sizeof(*out)); /* built without libdrm: nothing to say */
}
#endif
