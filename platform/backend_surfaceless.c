/* isoterra — headless backend on EGL_MESA_platform_surfaceless: no device
 * selection, Mesa picks a render node or falls back to software. */
#include "platform.h"

#include <stdio.h>

static bool surfaceless_probe(void)
{
	return egl_common_has_ext(egl_common_client_exts(), "EGL_MESA_platform_surfaceless");
}

static void surfaceless_close(struct platform *p)
{
	egl_common_release(p);
}

static int surfaceless_open(struct platform *p, const struct platform_options *opt,
                            char *err, size_t errlen)
{
	if (!surfaceless_probe()) {
		snprintf(err, errlen, "EGL_MESA_platform_surfaceless not supported by this EGL");
		return -1;
	}
	if (egl_common_open_display(p, EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, err, errlen) < 0 ||
	    egl_common_make_context(p, opt, 0, err, errlen) < 0) {
		surfaceless_close(p);
		return -1;
	}
	return 0;
}

static int surfaceless_present(struct platform *p)
{
	(void)p;
	return 0;
}

const struct platform_backend platform_backend_surfaceless = {
	.name = "surfaceless",
	.probe = surfaceless_probe,
	.open = surfaceless_open,
	.close = surfaceless_close,
	.present = surfaceless_present,
};
