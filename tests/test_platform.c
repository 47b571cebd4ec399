/* isoterra — platform layer: headless GLES 3.1 contexts via EGL. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GLES3/gl32.h>

#include "platform.h"
#include "tcheck.h"

#ifdef ISOTERRA_HAVE_GBM
#include <unistd.h>

#include "kms.h"

/* The wait on a KMS out-fence (kms_atomic.c) is a poll for POLLIN on its
 * fd: a pipe stands in for the sync_file. */
static void check_fence_wait(void)
{
	int fds[2];
	CHECK(pipe(fds) == 0, "pipe");
	CHECK(kms_fence_wait(fds[0], 0) == 0, "fence wait: not signalled, looked only");
	CHECK(kms_fence_wait(fds[0], 20) == 0, "fence wait: not signalled within 20 ms");
	CHECK(write(fds[1], "x", 1) == 1, "write");
	CHECK(kms_fence_wait(fds[0], 1000) == 1, "fence wait: signalled");
	close(fds[0]);
	close(fds[1]);
}
#endif

static void check_context(const struct platform *p, const char *what)
{
	CHECK(eglGetCurrentContext() == p->ctx, "%s: context not current", what);
	CHECK(p->headless, "%s: not headless", what);
	CHECK(p->device_desc[0] != 0, "%s: empty device_desc", what);
	const char *ver = (const char *)glGetString(GL_VERSION);
	int major = 0, minor = 0;
	CHECK(ver && sscanf(ver, "OpenGL ES %d.%d", &major, &minor) == 2, "%s: GL_VERSION '%s'", what,
	      ver ? ver : "(null)");
	CHECK(major > 3 || (major == 3 && minor >= 1), "%s: GL_VERSION '%s' < 3.1", what, ver ? ver : "");
	GLint wg[3] = { 0, 0, 0 };
	for (GLuint i = 0; i < 3; i++)
		glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, i, &wg[i]);
	/* ES 3.1 guarantees at least 65535 per axis. */
	CHECK(wg[0] >= 65535 && wg[1] >= 65535 && wg[2] >= 65535, "%s: max work group count %d %d %d",
	      what, wg[0], wg[1], wg[2]);
	CHECK(glGetError() == GL_NO_ERROR, "%s: GL error after queries", what);
	printf("%s: %s, %s\n", what, ver ? ver : "?", p->device_desc);
}

static void open_ok(const char *name, bool debug)
{
	const char *label = name ? name : "(default)";
	char err[512] = "";
	struct platform_options opt = { .name = name, .width = 64, .height = 64, .debug = debug };
	struct platform *p = platform_open(&opt, err, sizeof(err));
	CHECK(p != NULL, "open '%s': %s", label, err);
	if (!p)
		return;
	check_context(p, label);
	if (debug) {
		GLint flags = 0;
		glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
		if (glGetError() == GL_NO_ERROR) /* GL_CONTEXT_FLAGS is ES 3.2 */
			CHECK(flags & GL_CONTEXT_FLAG_DEBUG_BIT, "%s: debug context requested, flags 0x%x", label, flags);
	}
	CHECK(platform_present(p) == 0, "present on headless '%s'", label);
	platform_close(p);
	CHECK(eglGetCurrentContext() == EGL_NO_CONTEXT, "'%s': context still current after close", label);
}

/* The log seam (platform_log.h): the platform's messages reach the
 * callback, one line each, with their levels. */
struct seen {
	int n, debug_open;
	char last[256];
};

static void catch_log(void *user, enum platform_log_level level, const char *msg)
{
	struct seen *s = user;
	s->n++;
	snprintf(s->last, sizeof(s->last), "%s", msg);
	if (level == PLATFORM_LOG_DEBUG && strncmp(msg, "platform 'surfaceless': ", 24) == 0 && !strchr(msg, '\n'))
		s->debug_open++;
}

static void check_log_seam(void)
{
	struct seen s = { 0 };
	platform_set_log(&(struct platform_log){ .fn = catch_log, .user = &s });
	char err[512] = "";
	struct platform_options opt = { .name = "surfaceless" };
	struct platform *p = platform_open(&opt, err, sizeof(err));
	CHECK(p != NULL, "surfaceless: %s", err);
	platform_close(p);
	platform_set_log(NULL);
	CHECK(s.debug_open == 1, "log seam: %d messages, %d 'platform 'surfaceless': ...' at debug level (last '%s')",
	      s.n, s.debug_open, s.last);
	printf("log seam: %d messages through the callback\n", s.n);
}

/* Number of EGL devices as the test sees it, -1 when the EGL cannot list them. */
static int egl_device_count(void)
{
	const char *ce = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
	if (!ce || !egl_common_has_ext(ce, "EGL_EXT_platform_device"))
		return -1;
	PFNEGLQUERYDEVICESEXTPROC q = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
	EGLint n = 0;
	if (!q || !q(0, NULL, &n))
		return -1;
	return n;
}

/* The GL_VERSION of a plain OpenGL ES 3 context (EGL_CONTEXT_CLIENT_VERSION
 * 3, no minor version asked: what the driver gives) on the surfaceless
 * display, made here without the platform layer; into ver ("" when no such
 * context could be made current). */
static void plain_es3_version(char *ver, size_t len)
{
	ver[0] = 0;
	PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
		(PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
	EGLDisplay dpy = get_display ? get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL)
				     : EGL_NO_DISPLAY;
	if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, NULL, NULL)) {
		(void)eglGetError();
		return;
	}
	EGLConfig cfg = (EGLConfig)0; /* EGL_NO_CONFIG_KHR */
	const char *exts = eglQueryString(dpy, EGL_EXTENSIONS);
	if (!egl_common_has_ext(exts, "EGL_KHR_no_config_context")) {
		const EGLint want[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE };
		EGLint n = 0;
		if (!eglChooseConfig(dpy, want, &cfg, 1, &n) || n < 1)
			cfg = (EGLConfig)0;
	}
	const EGLint attr[] = { EGL_CONTEXT_CLIENT_VERSION, 3, EGL_NONE };
	EGLContext ctx = eglBindAPI(EGL_OPENGL_ES_API) ? eglCreateContext(dpy, cfg, EGL_NO_CONTEXT, attr)
						       : EGL_NO_CONTEXT;
	if (ctx != EGL_NO_CONTEXT && eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx)) {
		const char *v = (const char *)glGetString(GL_VERSION);
		snprintf(ver, len, "%s", v ? v : "");
		eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
	}
	if (ctx != EGL_NO_CONTEXT)
		eglDestroyContext(dpy, ctx);
	(void)eglGetError();
	eglTerminate(dpy);
}

/* Run with MESA_GLES_VERSION_OVERRIDE=3.0: opening must fail, naming 3.1.
 * A capability decides whether the test can be made at all: a driver
 * without that override (not Mesa) gives a plain context its own version;
 * when that is ES 3.1 or later no context here is limited to 3.0, and the
 * refusal cannot be provoked: skipped (77), saying so.  Otherwise (the
 * plain context is 3.0, or none could be made) the refusal must hold. */
static int expect_no_es31(void)
{
	char err[512] = "", plain[256];
	plain_es3_version(plain, sizeof(plain));
	int major = 0, minor = 0;
	if (sscanf(plain, "OpenGL ES %d.%d", &major, &minor) == 2 && (major > 3 || (major == 3 && minor >= 1))) {
		printf("test_platform (no ES 3.1): skipped: a plain ES 3 context is '%s' with "
		       "MESA_GLES_VERSION_OVERRIDE=%s: this driver does not take the override, no ES 3.0-only "
		       "context to refuse\n",
		       plain, getenv("MESA_GLES_VERSION_OVERRIDE") ? getenv("MESA_GLES_VERSION_OVERRIDE") : "(unset)");
		return 77;
	}
	printf("plain ES 3 context: %s\n", plain[0] ? plain : "(none could be made)");
	struct platform_options opt = { .name = "surfaceless" };
	struct platform *p = platform_open(&opt, err, sizeof(err));
	CHECK(p == NULL, "opened although GLES is limited to 3.0");
	CHECK(strstr(err, "OpenGL ES 3.1") != NULL, "err '%s'", err);
	printf("es3.0 only: %s\n", err);
	platform_close(p);
	return tc_done("test_platform (no ES 3.1)");
}

int main(int argc, char **argv)
{
	char err[512];
	const char *ce = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
	if (!ce || !egl_common_has_ext(ce, "EGL_MESA_platform_surfaceless")) {
		printf("test_platform: skipped: EGL_MESA_platform_surfaceless not available\n");
		return 77;
	}
	if (argc > 1 && strcmp(argv[1], "--expect-no-es31") == 0)
		return expect_no_es31();

	/* names: the backends meson built (ISOTERRA_BACKENDS, from the build
	 * configuration), in any order; the headless ones always */
	const char *names = platform_backend_names();
	const char *want = getenv("ISOTERRA_BACKENDS");
	if (!want || !want[0])
		want = "device surfaceless";
	int nwant = 0, nhave = 0;
	char tok[64];
	for (const char *q = want; sscanf(q, "%63s", tok) == 1; nwant++) {
		CHECK(egl_common_has_ext(names, tok), "backend '%s' built but not in '%s'", tok, names);
		q = strstr(q, tok) + strlen(tok);
	}
	for (const char *q = names; sscanf(q, "%63s", tok) == 1; nhave++)
		q = strstr(q, tok) + strlen(tok);
	CHECK(nhave == nwant, "names '%s', built '%s'", names, want);
	CHECK(egl_common_has_ext(names, "device") && egl_common_has_ext(names, "surfaceless"), "names '%s'", names);
	struct platform_options bad = { .name = "nonsense" };
	err[0] = 0;
	CHECK(platform_open(&bad, err, sizeof(err)) == NULL, "nonsense opened");
	char want_err[256];
	snprintf(want_err, sizeof(want_err), "unknown platform 'nonsense' (compiled in: %s)", names);
	CHECK(strcmp(err, want_err) == 0, "err '%s'", err);

	/* extension token matching */
	CHECK(egl_common_has_ext("EGL_KHR_debug EGL_EXT_device_drm_render_node", "EGL_EXT_device_drm_render_node"), "ext last");
	CHECK(!egl_common_has_ext("EGL_EXT_device_drm_render_node", "EGL_EXT_device_drm"), "ext prefix");
	CHECK(egl_common_has_ext("EGL_EXT_device_drm_render_node EGL_EXT_device_drm", "EGL_EXT_device_drm"), "ext second");
	CHECK(!egl_common_has_ext("", "EGL_KHR_debug") && !egl_common_has_ext(NULL, "EGL_KHR_debug"), "ext empty");

	/* one platform at a time */
	struct platform_options sl = { .name = "surfaceless" };
	struct platform *first = platform_open(&sl, err, sizeof(err));
	CHECK(first != NULL, "surfaceless: %s", err);
	err[0] = 0;
	CHECK(platform_open(&sl, err, sizeof(err)) == NULL &&
	      !strcmp(err, "a platform is already open (one at a time per process)"), "second open: '%s'", err);
	platform_close(first);

	check_log_seam();
#ifdef ISOTERRA_HAVE_GBM
	check_fence_wait();
#endif
	open_ok("surfaceless", false);
	open_ok("surfaceless", true);  /* again: terminate + reinitialise works */
	open_ok("auto", false);
	open_ok(NULL, false);          /* NULL name = auto */

	/* device: Mesa exposes a software device; whether it opens must match
	 * what the device list says. */
	int ndev = egl_device_count();
	struct platform_options dopt = { .name = "device" };
	err[0] = 0;
	struct platform *p = platform_open(&dopt, err, sizeof(err));
	if (ndev > 0) {
		CHECK(p != NULL, "%d EGL device(s) but 'device' failed: %s", ndev, err);
		if (p) {
			check_context(p, "device");
			platform_close(p);
		}
	} else {
		CHECK(p == NULL, "'device' opened with no EGL devices listed");
		CHECK(err[0] != 0, "no message");
		if (ndev == 0)
			CHECK(strcmp(err, "no EGL device found") == 0, "err '%s'", err);
		printf("device: %s\n", err);
		platform_close(p);
	}
	return tc_done("test_platform");
}
