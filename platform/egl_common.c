/* isoterra — EGL pieces shared by every backend: platform display, config,
 * GLES 3.1 context, GL_VERSION check, EGL_KHR_debug routing. */
#include "platform.h"

#include <stdio.h>
#include <string.h>

#include <GLES3/gl31.h>

#include "platform_util.h"

bool egl_common_has_ext(const char *list, const char *ext)
{
	size_t n = strlen(ext);
	if (!list || !n)
		return false;
	for (const char *s = list; (s = strstr(s, ext)) != NULL; s += n) {
		bool start = s == list || s[-1] == ' ';
		bool end = s[n] == 0 || s[n] == ' ';
		if (start && end)
			return true;
	}
	return false;
}

const char *egl_common_client_exts(void)
{
	/* NULL (EGL_BAD_DISPLAY) when EGL_EXT_client_extensions is missing. */
	const char *s = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
	if (!s) {
		(void)eglGetError();
		return "";
	}
	return s;
}

const char *egl_common_error_name(EGLint e)
{
	switch (e) {
#define E(x) case x: return #x;
	E(EGL_SUCCESS) E(EGL_NOT_INITIALIZED) E(EGL_BAD_ACCESS) E(EGL_BAD_ALLOC)
	E(EGL_BAD_ATTRIBUTE) E(EGL_BAD_CONFIG) E(EGL_BAD_CONTEXT)
	E(EGL_BAD_CURRENT_SURFACE) E(EGL_BAD_DISPLAY) E(EGL_BAD_MATCH)
	E(EGL_BAD_NATIVE_PIXMAP) E(EGL_BAD_NATIVE_WINDOW) E(EGL_BAD_PARAMETER)
	E(EGL_BAD_SURFACE) E(EGL_CONTEXT_LOST) E(EGL_BAD_DEVICE_EXT)
#undef E
	default: return "unknown EGL error";
	}
}

/* ---- EGL_KHR_debug ------------------------------------------------------- */

/* The driver's last error message: added to our one-line failure reason.
 * Drivers also report errors they recover from (Mesa: "DRI2: failed to load
 * driver" before falling back to swrast), so these only go to the debug log. */
static char last_error[160];

static void last_error_clear(void)
{
	last_error[0] = 0;
}

/* err = "<what> failed: EGL_BAD_xxx (driver message)". */
static void egl_fail(char *err, size_t errlen, const char *what)
{
	EGLint e = eglGetError();
	if (last_error[0])
		snprintf(err, errlen, "%s failed: %s (%s)", what, egl_common_error_name(e), last_error);
	else
		snprintf(err, errlen, "%s failed: %s", what, egl_common_error_name(e));
}

static void EGLAPIENTRY debug_cb(EGLenum error, const char *command, EGLint type,
                                 EGLLabelKHR thread_label, EGLLabelKHR object_label,
                                 const char *message)
{
	(void)thread_label;
	(void)object_label;
	const char *cmd = command ? command : "EGL";
	const char *msg = message ? message : "";
	switch (type) {
	case EGL_DEBUG_MSG_CRITICAL_KHR:
		plog_error("EGL: %s: %s (%s)", cmd, msg, egl_common_error_name((EGLint)error));
		break;
	case EGL_DEBUG_MSG_ERROR_KHR:
		snprintf(last_error, sizeof(last_error), "%s", msg);
		plog_debug("EGL: %s: %s (%s)", cmd, msg, egl_common_error_name((EGLint)error));
		break;
	case EGL_DEBUG_MSG_WARN_KHR:
		plog_warn("EGL: %s: %s", cmd, msg);
		break;
	default:
		plog_debug("EGL: %s: %s", cmd, msg);
		break;
	}
}

void egl_common_debug_callback(bool enable, bool verbose)
{
	if (!egl_common_has_ext(egl_common_client_exts(), "EGL_KHR_debug"))
		return;
	PFNEGLDEBUGMESSAGECONTROLKHRPROC control =
		(PFNEGLDEBUGMESSAGECONTROLKHRPROC)eglGetProcAddress("eglDebugMessageControlKHR");
	if (!control)
		return;
	const EGLAttrib attribs[] = {
		EGL_DEBUG_MSG_CRITICAL_KHR, EGL_TRUE,
		EGL_DEBUG_MSG_ERROR_KHR, EGL_TRUE,
		EGL_DEBUG_MSG_WARN_KHR, verbose ? EGL_TRUE : EGL_FALSE,
		EGL_DEBUG_MSG_INFO_KHR, verbose ? EGL_TRUE : EGL_FALSE,
		EGL_NONE,
	};
	EGLint rc = enable ? control(debug_cb, attribs) : control(NULL, NULL);
	if (rc != EGL_SUCCESS)
		plog_warn("eglDebugMessageControlKHR failed: %s", egl_common_error_name(rc));
}

/* ---- display ------------------------------------------------------------- */

int egl_common_open_display(struct platform *p, EGLenum platform, void *native,
                            char *err, size_t errlen)
{
	const char *cexts = egl_common_client_exts();
	if (!egl_common_has_ext(cexts, "EGL_EXT_platform_base")) {
		snprintf(err, errlen, "EGL_EXT_platform_base not supported by this EGL");
		return -1;
	}
	PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
		(PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
	if (!get_display) {
		snprintf(err, errlen, "eglGetPlatformDisplayEXT not found in this EGL");
		return -1;
	}
	last_error_clear();
	EGLDisplay dpy = get_display(platform, native, NULL);
	if (dpy == EGL_NO_DISPLAY) {
		egl_fail(err, errlen, "eglGetPlatformDisplayEXT");
		return -1;
	}
	EGLint major = 0, minor = 0;
	last_error_clear();
	if (!eglInitialize(dpy, &major, &minor)) {
		egl_fail(err, errlen, "eglInitialize");
		return -1;
	}
	p->dpy = dpy;
	plog_debug("EGL %d.%d, vendor '%s'", major, minor, eglQueryString(dpy, EGL_VENDOR));
	return 0;
}

/* ---- context ------------------------------------------------------------- */

static int choose_config(struct platform *p, EGLint renderable, EGLint surface_type, bool no_config_ok,
                         char *err, size_t errlen)
{
	const EGLint attribs[] = {
		EGL_RENDERABLE_TYPE, renderable,
		/* The default is EGL_WINDOW_BIT; 0 matches every config. */
		EGL_SURFACE_TYPE, surface_type,
		EGL_RED_SIZE, surface_type ? 8 : 0,
		EGL_GREEN_SIZE, surface_type ? 8 : 0,
		EGL_BLUE_SIZE, surface_type ? 8 : 0,
		EGL_NONE,
	};
	EGLint n = 0;
	last_error_clear();
	if (!eglChooseConfig(p->dpy, attribs, &p->config, 1, &n)) {
		egl_fail(err, errlen, "eglChooseConfig");
		return -1;
	}
	if (n >= 1)
		return 0;
	if (no_config_ok) {
		p->config = EGL_NO_CONFIG_KHR;
		plog_debug("no OpenGL ES 3 EGLConfig; using EGL_KHR_no_config_context");
		return 0;
	}
	snprintf(err, errlen, "no EGLConfig supports OpenGL ES 3 on this display");
	return -1;
}

static EGLContext create_context(struct platform *p, bool egl15, bool khr_cc, bool debug)
{
	EGLint a[16], n = 0;
	if (egl15) {
		a[n++] = EGL_CONTEXT_MAJOR_VERSION;
		a[n++] = 3;
		a[n++] = EGL_CONTEXT_MINOR_VERSION;
		a[n++] = 1;
		if (debug) {
			a[n++] = EGL_CONTEXT_OPENGL_DEBUG;
			a[n++] = EGL_TRUE;
		}
	} else if (khr_cc) {
		a[n++] = EGL_CONTEXT_MAJOR_VERSION_KHR;
		a[n++] = 3;
		a[n++] = EGL_CONTEXT_MINOR_VERSION_KHR;
		a[n++] = 1;
		if (debug) {
			a[n++] = EGL_CONTEXT_FLAGS_KHR;
			a[n++] = EGL_CONTEXT_OPENGL_DEBUG_BIT_KHR;
		}
	} else {
		/* Plain EGL 1.4: ask for ES 3 and check GL_VERSION afterwards. */
		a[n++] = EGL_CONTEXT_CLIENT_VERSION;
		a[n++] = 3;
	}
	a[n++] = EGL_NONE;
	return eglCreateContext(p->dpy, p->config, EGL_NO_CONTEXT, a);
}

/* The GLES 3.1 context, with debug output when asked (and without it when a
 * debug context is refused).  0, or -1 with err. */
static int make_context(struct platform *p, bool egl15, bool khr_cc, bool debug, char *err, size_t errlen)
{
	last_error_clear();
	p->ctx = create_context(p, egl15, khr_cc, debug);
	if (p->ctx == EGL_NO_CONTEXT && debug) {
		plog_warn("cannot create a debug GLES context (%s); continuing without",
		         egl_common_error_name(eglGetError()));
		last_error_clear();
		p->ctx = create_context(p, egl15, khr_cc, false);
	}
	if (p->ctx == EGL_NO_CONTEXT) {
		egl_fail(err, errlen, "cannot create an OpenGL ES 3.1 context: eglCreateContext");
		return -1;
	}
	return 0;
}

const char *platform_check_gles31(char *err, size_t errlen)
{
	const char *ver = (const char *)glGetString(GL_VERSION);
	if (!ver) {
		snprintf(err, errlen, "no current GL context: glGetString(GL_VERSION) failed (GL error 0x%04x)",
			 glGetError());
		return NULL;
	}
	int major = 0, minor = 0;
	/* "OpenGL ES 3.2 Mesa 22.3.6"; ES 1.x says "OpenGL ES-CM 1.1". */
	if (sscanf(ver, "OpenGL ES %d.%d", &major, &minor) != 2) {
		snprintf(err, errlen, "context is not OpenGL ES 3.1 (GL_VERSION is '%s')", ver);
		return NULL;
	}
	if (major < 3 || (major == 3 && minor < 1)) {
		snprintf(err, errlen, "OpenGL ES 3.1 with compute shaders is required, the context gives '%s'", ver);
		return NULL;
	}
	return ver;
}

static int check_gl_version(struct platform *p, char *err, size_t errlen)
{
	const char *ver = platform_check_gles31(err, errlen);
	const char *ren = (const char *)glGetString(GL_RENDERER);
	if (!ver)
		return -1;
	snprintf(p->device_desc, sizeof(p->device_desc), "%s", ren ? ren : "unknown renderer");
	plog_debug("GL_VERSION '%s', GL_RENDERER '%s'", ver, p->device_desc);
	return 0;
}

/* EGL 1.5, EGL_KHR_create_context: how a GLES 3 context is asked for. */
static int context_kind(struct platform *p, bool *egl15, bool *khr_cc, char *err, size_t errlen)
{
	EGLint major = 1, minor = 0;
	const char *ver = eglQueryString(p->dpy, EGL_VERSION);
	const char *exts = eglQueryString(p->dpy, EGL_EXTENSIONS);
	if (!ver || sscanf(ver, "%d.%d", &major, &minor) != 2 || !exts) {
		egl_fail(err, errlen, "eglQueryString");
		return -1;
	}
	*egl15 = major > 1 || (major == 1 && minor >= 5);
	*khr_cc = egl_common_has_ext(exts, "EGL_KHR_create_context");
	return 0;
}

int egl_common_make_context(struct platform *p, const struct platform_options *opt,
                            EGLint surface_type, char *err, size_t errlen)
{
	bool egl15, khr_cc;
	if (context_kind(p, &egl15, &khr_cc, err, errlen) < 0)
		return -1;
	const char *exts = eglQueryString(p->dpy, EGL_EXTENSIONS);
	bool surfaceless = egl_common_has_ext(exts, "EGL_KHR_surfaceless_context");
	bool no_config = egl_common_has_ext(exts, "EGL_KHR_no_config_context") ||
	                 egl_common_has_ext(exts, "EGL_MESA_configless_context");
	bool headless = surface_type == 0;
	bool need_pbuffer = headless && !surfaceless;

	last_error_clear();
	if (!eglBindAPI(EGL_OPENGL_ES_API)) {
		egl_fail(err, errlen, "eglBindAPI(EGL_OPENGL_ES_API)");
		return -1;
	}
	if (need_pbuffer)
		surface_type = EGL_PBUFFER_BIT;
	/* EGL_OPENGL_ES3_BIT is EGL 1.5 / EGL_KHR_create_context; plain 1.4
	 * only knows ES2 configs (which then also run ES 3 contexts). */
	EGLint renderable = egl15 || khr_cc ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT;
	if (choose_config(p, renderable, surface_type, headless && !need_pbuffer && no_config, err, errlen) < 0)
		return -1;

	if (make_context(p, egl15, khr_cc, opt->debug, err, errlen) < 0)
		return -1;

	if (need_pbuffer) {
		const EGLint pb[] = { EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE };
		last_error_clear();
		p->surface = eglCreatePbufferSurface(p->dpy, p->config, pb);
		if (p->surface == EGL_NO_SURFACE) {
			egl_fail(err, errlen, "no EGL_KHR_surfaceless_context and eglCreatePbufferSurface");
			return -1;
		}
		plog_debug("no EGL_KHR_surfaceless_context: using a 1x1 pbuffer");
	}
	last_error_clear();
	if (!eglMakeCurrent(p->dpy, p->surface, p->surface, p->ctx)) {
		egl_fail(err, errlen, "eglMakeCurrent");
		return -1;
	}
	p->headless = headless;
	return check_gl_version(p, err, errlen);
}

/* ---- window surfaces (display backends) --------------------------------- */

#define MAX_CONFIGS 256

static int choose_window_config(struct platform *p, EGLint renderable, EGLint visual,
                                char *err, size_t errlen)
{
	const EGLint attribs[] = {
		EGL_RENDERABLE_TYPE, renderable,
		EGL_SURFACE_TYPE, EGL_WINDOW_BIT,
		EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8,
		EGL_NONE,
	};
	EGLConfig configs[MAX_CONFIGS];
	EGLint n = 0;
	last_error_clear();
	if (!eglChooseConfig(p->dpy, attribs, configs, MAX_CONFIGS, &n)) {
		egl_fail(err, errlen, "eglChooseConfig");
		return -1;
	}
	/* With a visual: that one.  Otherwise 8-bit RGB without alpha (the
	 * first configs are the deepest, e.g. 10-bit XRGB2101010, which some
	 * compositors show wrongly), then 8-bit RGB with alpha, then any. */
	int pick = -1, pick_alpha = -1;
	for (EGLint i = 0; i < n && pick < 0; i++) {
		EGLint id = 0, r = 0, g = 0, b = 0, alpha = 0;
		if (!eglGetConfigAttrib(p->dpy, configs[i], EGL_NATIVE_VISUAL_ID, &id) ||
		    !eglGetConfigAttrib(p->dpy, configs[i], EGL_RED_SIZE, &r) ||
		    !eglGetConfigAttrib(p->dpy, configs[i], EGL_GREEN_SIZE, &g) ||
		    !eglGetConfigAttrib(p->dpy, configs[i], EGL_BLUE_SIZE, &b) ||
		    !eglGetConfigAttrib(p->dpy, configs[i], EGL_ALPHA_SIZE, &alpha)) {
			egl_fail(err, errlen, "eglGetConfigAttrib");
			return -1;
		}
		bool rgb8 = r == 8 && g == 8 && b == 8;
		if (visual ? id == visual : rgb8 && alpha == 0)
			pick = (int)i;
		else if (!visual && rgb8 && pick_alpha < 0)
			pick_alpha = (int)i;
	}
	if (pick < 0 && !visual)
		pick = pick_alpha >= 0 ? pick_alpha : n > 0 ? 0 : -1;
	if (pick < 0) {
		if (visual)
			snprintf(err, errlen, "no EGLConfig for OpenGL ES 3 windows matches native visual 0x%x "
			         "(%d window configs)", (unsigned)visual, (int)n);
		else
			snprintf(err, errlen, "no EGLConfig supports OpenGL ES 3 windows on this display");
		return -1;
	}
	p->config = configs[pick];
	EGLint id = 0, alpha = 0;
	eglGetConfigAttrib(p->dpy, p->config, EGL_NATIVE_VISUAL_ID, &id);
	eglGetConfigAttrib(p->dpy, p->config, EGL_ALPHA_SIZE, &alpha);
	plog_debug("EGL window config %d of %d: native visual 0x%x, alpha %d", pick, (int)n, (unsigned)id, (int)alpha);
	return 0;
}

/* Makes `surface` current with the context (creating the context first
 * when there is none, then checking GL_VERSION) and destroys the surface
 * it replaces.  0, or -1 with err (surface then destroyed). */
static int make_current_on(struct platform *p, const struct platform_options *opt, EGLSurface surface, bool egl15,
                           bool khr_cc, char *err, size_t errlen)
{
	bool new_ctx = p->ctx == EGL_NO_CONTEXT;
	if (new_ctx && make_context(p, egl15, khr_cc, opt->debug, err, errlen) < 0) {
		eglDestroySurface(p->dpy, surface);
		return -1;
	}
	last_error_clear();
	if (!eglMakeCurrent(p->dpy, surface, surface, p->ctx)) {
		egl_fail(err, errlen, "eglMakeCurrent");
		eglDestroySurface(p->dpy, surface);
		return -1;
	}
	if (p->surface != EGL_NO_SURFACE && !eglDestroySurface(p->dpy, p->surface))
		plog_warn("eglDestroySurface (the surface replaced) failed: %s", egl_common_error_name(eglGetError()));
	p->surface = surface;
	p->headless = false;
	return new_ctx ? check_gl_version(p, err, errlen) : 0;
}

/* A config of exactly 8-bit red, green, blue and alpha with pbuffers, or
 * NULL.  Its pixels are what a BGRA read-back asks for: the read is a copy
 * (llvmpipe: 0.1-0.2 ms at 1280x720 against 0.7-0.9 from an xRGB one). */
static EGLConfig rgba_pbuffer_config(struct platform *p, EGLint renderable)
{
	const EGLint attribs[] = {
		EGL_RENDERABLE_TYPE, renderable, EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
		EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
		EGL_NONE,
	};
	EGLConfig configs[MAX_CONFIGS];
	EGLint n = 0;
	if (!eglChooseConfig(p->dpy, attribs, configs, MAX_CONFIGS, &n)) {
		(void)eglGetError();
		return NULL;
	}
	for (EGLint i = 0; i < n; i++) {
		EGLint r = 0, g = 0, b = 0, a = 0;
		if (eglGetConfigAttrib(p->dpy, configs[i], EGL_RED_SIZE, &r) &&
		    eglGetConfigAttrib(p->dpy, configs[i], EGL_GREEN_SIZE, &g) &&
		    eglGetConfigAttrib(p->dpy, configs[i], EGL_BLUE_SIZE, &b) &&
		    eglGetConfigAttrib(p->dpy, configs[i], EGL_ALPHA_SIZE, &a) && r == 8 && g == 8 && b == 8 && a == 8)
			return configs[i];
	}
	return NULL;
}

int egl_common_make_pbuffer_context(struct platform *p, const struct platform_options *opt, int w, int h,
                                    char *err, size_t errlen)
{
	bool egl15, khr_cc;
	EGLint type = 0;
	if (context_kind(p, &egl15, &khr_cc, err, errlen) < 0)
		return -1;
	if (p->ctx == EGL_NO_CONTEXT) {
		EGLConfig rgba = rgba_pbuffer_config(p, egl15 || khr_cc ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT);
		if (rgba)
			p->config = rgba;
		plog_debug("pbuffer config: %s", rgba ? "8-bit RGBA" : "the window's (no 8-bit RGBA one has pbuffers)");
	}
	if (!eglGetConfigAttrib(p->dpy, p->config, EGL_SURFACE_TYPE, &type) || !(type & EGL_PBUFFER_BIT)) {
		snprintf(err, errlen, "no EGLConfig for pbuffers");
		return -1;
	}
	const EGLint pb[] = { EGL_WIDTH, w, EGL_HEIGHT, h, EGL_NONE };
	last_error_clear();
	EGLSurface s = eglCreatePbufferSurface(p->dpy, p->config, pb);
	if (s == EGL_NO_SURFACE) {
		egl_fail(err, errlen, "eglCreatePbufferSurface");
		return -1;
	}
	return make_current_on(p, opt, s, egl15, khr_cc, err, errlen);
}

void egl_common_drop_context(struct platform *p)
{
	if (!eglMakeCurrent(p->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT))
		plog_warn("eglMakeCurrent(none) failed: %s", egl_common_error_name(eglGetError()));
	if (p->ctx != EGL_NO_CONTEXT && !eglDestroyContext(p->dpy, p->ctx))
		plog_warn("eglDestroyContext failed: %s", egl_common_error_name(eglGetError()));
	if (p->surface != EGL_NO_SURFACE && !eglDestroySurface(p->dpy, p->surface))
		plog_warn("eglDestroySurface failed: %s", egl_common_error_name(eglGetError()));
	p->ctx = EGL_NO_CONTEXT;
	p->surface = EGL_NO_SURFACE;
}

bool platform_display_software(EGLDisplay dpy)
{
	const char *client = egl_common_client_exts();
	if (dpy == EGL_NO_DISPLAY ||
	    (!egl_common_has_ext(client, "EGL_EXT_device_query") && !egl_common_has_ext(client, "EGL_EXT_device_base")))
		return false;
	PFNEGLQUERYDISPLAYATTRIBEXTPROC query_display =
		(PFNEGLQUERYDISPLAYATTRIBEXTPROC)eglGetProcAddress("eglQueryDisplayAttribEXT");
	PFNEGLQUERYDEVICESTRINGEXTPROC query_device =
		(PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
	EGLAttrib dev = 0;
	if (!query_display || !query_device || !query_display(dpy, EGL_DEVICE_EXT, &dev) || !dev) {
		(void)eglGetError();
		return false;
	}
	const char *exts = query_device((EGLDeviceEXT)dev, EGL_EXTENSIONS);
	(void)eglGetError();
	return egl_common_has_ext(exts, "EGL_MESA_device_software");
}

int egl_common_make_window_context(struct platform *p, const struct platform_options *opt,
                                   EGLint visual, void *native_window, char *err, size_t errlen)
{
	bool egl15, khr_cc;
	if (context_kind(p, &egl15, &khr_cc, err, errlen) < 0)
		return -1;
	if (!p->config) {
		last_error_clear();
		if (!eglBindAPI(EGL_OPENGL_ES_API)) {
			egl_fail(err, errlen, "eglBindAPI(EGL_OPENGL_ES_API)");
			return -1;
		}
		EGLint renderable = egl15 || khr_cc ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_ES2_BIT;
		if (choose_window_config(p, renderable, visual, err, errlen) < 0)
			return -1;
	}
	if (!native_window)
		return 0;

	PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC create_surface =
		(PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC)eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT");
	if (!create_surface) {
		snprintf(err, errlen, "eglCreatePlatformWindowSurfaceEXT not found in this EGL");
		return -1;
	}
	last_error_clear();
	EGLSurface s = create_surface(p->dpy, p->config, native_window, NULL);
	if (s == EGL_NO_SURFACE) {
		egl_fail(err, errlen, "eglCreatePlatformWindowSurfaceEXT");
		return -1;
	}
	if (make_current_on(p, opt, s, egl15, khr_cc, err, errlen) < 0)
		return -1;
	/* vsync where the window system has it (a no-op on GBM: the backend
	 * waits for page flips itself) */
	if (!eglSwapInterval(p->dpy, 1))
		plog_debug("eglSwapInterval(1): %s", egl_common_error_name(eglGetError()));
	return 0;
}

void egl_common_release(struct platform *p)
{
	if (p->dpy == EGL_NO_DISPLAY)
		return;
	egl_common_drop_context(p);
	if (!eglTerminate(p->dpy))
		plog_warn("eglTerminate failed: %s", egl_common_error_name(eglGetError()));
	if (!eglReleaseThread())
		plog_warn("eglReleaseThread failed: %s", egl_common_error_name(eglGetError()));
	p->config = NULL;
	p->dpy = EGL_NO_DISPLAY;
}
