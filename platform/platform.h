/* isoterra — platform layer: EGL display, GLES 3.1 context and (for windowed
 * backends, later) a surface, behind one small interface.
 *
 * Backends are plain structs of function pointers (kmscube style).  The
 * renderer never sees which one is active: headless backends render into the
 * application's FBO; windowed ones (GBM/KMS, Wayland, X11 — later) also give a
 * window surface and a present() that swaps/flips. */
#ifndef ISOTERRA_PLATFORM_H
#define ISOTERRA_PLATFORM_H

#include <stdbool.h>
#include <stddef.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

struct platform;

struct platform_options {
	const char *name;   /* "auto", "device", "surfaceless" (later gbm, wayland, x11) */
	int width, height;  /* requested surface size (windowed backends) */
	bool debug;         /* create a debug context, route KHR_debug to the log */
};

struct platform_backend {
	const char *name;
	/* Cheap check: can this backend work here?  Used by "auto".  For
	 * "device" it means: an EGL device that is a real GPU exists. */
	bool (*probe)(void);
	/* Open the display, create the GLES 3.1 context, make it current. */
	int (*open)(struct platform *p, const struct platform_options *opt, char *err, size_t errlen);
	void (*close)(struct platform *p);
	/* Show the frame drawn into the default framebuffer; no-op headless. */
	int (*present)(struct platform *p);
};

struct platform {
	const struct platform_backend *backend;
	EGLDisplay dpy;
	EGLConfig config;
	EGLContext ctx;
	EGLSurface surface;   /* EGL_NO_SURFACE when headless (or a 1x1 pbuffer
	                         when the EGL lacks EGL_KHR_surfaceless_context) */
	bool headless;        /* true: render into an FBO, no window */
	int width, height;    /* surface size when not headless */
	char device_desc[128];/* e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" / DRM node */
	void *priv;           /* backend state */
};

/* Open the named backend ("auto" tries device with a hardware GPU, then
 * surfaceless, then a software EGL device).  On failure returns NULL and a
 * one-line reason in err (missing EGL, missing extension, no GLES 3.1 ...). */
struct platform *platform_open(const struct platform_options *opt, char *err, size_t errlen);
void platform_close(struct platform *p);
int platform_present(struct platform *p);
/* Names of the backends compiled in, space-separated. */
const char *platform_backend_names(void);

/* ---- for the backends only (files under platform/) -------------------------------- */

extern const struct platform_backend platform_backend_device;
extern const struct platform_backend platform_backend_surfaceless;

/* egl_common.c */
/* True when the space-separated extension list contains ext (whole token). */
bool egl_common_has_ext(const char *list, const char *ext);
/* Client extension string (EGL_NO_DISPLAY); "" when EGL has none. */
const char *egl_common_client_exts(void);
/* "EGL_BAD_ALLOC" ... for eglGetError() values. */
const char *egl_common_error_name(EGLint e);
/* eglGetPlatformDisplayEXT through eglGetProcAddress (needs
 * EGL_EXT_platform_base); then eglInitialize.  Sets p->dpy. */
int egl_common_open_display(struct platform *p, EGLenum platform, void *native,
                            char *err, size_t errlen);
/* On p->dpy: bind GLES, choose a config (surface_type: 0 for headless), create
 * a GLES 3.1 context (debug when asked), make it current (surfaceless, or a
 * 1x1 pbuffer when the EGL lacks EGL_KHR_surfaceless_context), check
 * GL_VERSION >= OpenGL ES 3.1 and fill p->device_desc. */
int egl_common_make_context(struct platform *p, const struct platform_options *opt,
                            EGLint surface_type, char *err, size_t errlen);
/* Releases whatever egl_common_* created (safe on partial state). */
void egl_common_release(struct platform *p);
/* enable: route EGL_KHR_debug messages to log_* (verbose: also warnings and
 * info); !enable: remove the callback.  No-op without EGL_KHR_debug. */
void egl_common_debug_callback(bool enable, bool verbose);

#endif
