/* isoterra — platform layer: EGL display, GLES 3.1 context and (for windowed
 * backends) a surface, behind one small interface.
 *
 * Backends are plain structs of function pointers (kmscube style).  The
 * renderer never sees which one is active: headless backends render into the
 * application's FBO; windowed ones (GBM/KMS, Wayland, X11) also give a
 * window surface and a present() that swaps/flips.
 *
 * A library below the program: its only include folder is platform/ (it
 * includes nothing of app/); its messages go through the seam of
 * platform_log.h, which the program fills at start. */
#ifndef ISOTERRA_PLATFORM_H
#define ISOTERRA_PLATFORM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "platform_log.h" /* its messages: platform_set_log */

struct platform;

struct platform_options {
	const char *name;   /* "auto", "gbm", "wayland", "x11", "device", "surfaceless" */
	int width, height;  /* requested surface size (windowed backends) */
	bool debug;         /* create a debug context, route KHR_debug to the log */
	/* display backends (gbm, wayland, x11) */
	bool fullscreen;         /* wayland/x11: fullscreen window (gbm: always) */
	bool hide_cursor;        /* x11: no pointer over the window (gbm: always hidden) */
	/* x11: how a frame reaches the window (PLATFORM_X11_PRESENT_*): auto
	 * puts it through MIT-SHM where the renderer is software (whose
	 * eglSwapBuffers sends every pixel over the X connection) and the X
	 * server can share memory with us, else swaps */
	int x11_present;
	const char *drm_device;  /* gbm: "/dev/dri/cardN"; NULL or "" = first card with a connected output */
	const char *mode;        /* gbm: "WxH" or "WxH@Hz"; NULL or "" = the connector's preferred mode */
	bool kms_legacy;         /* gbm: legacy SetCrtc/PageFlip even where atomic works */
	/* gbm: the connectors to drive, "all" (every connected one, up to
	 * PLATFORM_MAX_OUTPUTS) or a comma-separated list of names
	 * ("HDMI-A-1,HDMI-A-2"); NULL or "" = the first connected one.  Every
	 * output runs the same mode size (one every connector offers: --mode,
	 * else the first's preferred mode when all offer it, else the first of
	 * its modes that all offer) and scans out its own rectangle of one
	 * surface: side by side along a row, outputs_gap + outputs_gap_per_w *
	 * (the mode's width) pixels apart (a wall's bezel, rounded per output:
	 * output k at k * w + round(k * gap)), or, outputs_mirror, all the
	 * same picture.  Another backend refuses a non-empty list. */
	const char *outputs;
	bool outputs_mirror;
	/* gbm, one output: the quarter turns clockwise (0..3, --rotate) the
	 * picture takes onto the output; the plane turns it where the driver
	 * offers the turn (p->rotated then says so), else the program does */
	int rotate;
	double outputs_gap, outputs_gap_per_w;
	/* device: which EGL device, "N" (an index in eglQueryDevicesEXT's
	 * order, as --list-devices shows them) or a DRM node path
	 * ("/dev/dri/renderD128", matched by EGL_EXT_device_drm's device file
	 * or EGL_EXT_device_drm_render_node's render node, symbolic links
	 * followed); NULL or "" = $ISOTERRA_DEVICE when set, else the first
	 * device that opens, real GPUs first.  With "auto" a device set here
	 * selects the device backend. */
	const char *device;
};

enum { PLATFORM_X11_PRESENT_AUTO, PLATFORM_X11_PRESENT_SHM, PLATFORM_X11_PRESENT_SWAP };

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
	/* Handle pending window-system events without blocking (configure /
	 * resize -> p->width/height, close); NULL for backends without a
	 * window system (headless ones, gbm).
	 * Returns 1 when the window was closed, 0 to go on, -1 on error. */
	int (*dispatch)(struct platform *p);
};

#define PLATFORM_MAX_OUTPUTS 4

/* One display output's rectangle of the surface (gbm). */
struct platform_output {
	char name[32];       /* the connector, "HDMI-A-1" */
	int x, y, w, h;      /* its picture in the surface (p->width x p->height) */
	bool on;             /* connected and scanning out (false while unplugged) */
};

struct platform {
	const struct platform_backend *backend;
	EGLDisplay dpy;
	EGLConfig config;
	EGLContext ctx;
	EGLSurface surface;   /* EGL_NO_SURFACE when headless (or a 1x1 pbuffer
	                         when the EGL lacks EGL_KHR_surfaceless_context) */
	bool headless;        /* true: render into an FBO, no window */
	int width, height;    /* surface size when not headless (updated on resize) */
	double refresh_hz;    /* the display's refresh rate when known (gbm), else 0 */
	unsigned long presented;  /* frames handed to the display (present calls that succeeded) */
	unsigned long shown;      /* frames the display confirmed: page-flip events (gbm),
	                             frame callbacks (wayland); = presented on x11 */
	/* gbm: the outputs, n_outputs >= 1 (one output: the whole surface,
	 * following its mode); 0 on the other backends (one picture, the
	 * whole surface) */
	int n_outputs;
	struct platform_output outputs[PLATFORM_MAX_OUTPUTS];
	/* quarter turns clockwise the display applies itself (gbm: the
	 * plane's rotation property, for opt->rotate): the surface is then
	 * the upright picture (its size turned back), drawn unturned */
	int rotated;
	char device_desc[128];/* e.g. "llvmpipe (LLVM 15.0.6, 256 bits)" / DRM node */
	const char *present_how; /* x11: "MIT-SHM" or "eglSwapBuffers"; NULL elsewhere */
	void *priv;           /* backend state */
};

/* Open the named backend ("auto" tries device with a hardware GPU, then
 * surfaceless, then a software EGL device).  On failure returns NULL and a
 * one-line reason in err (missing EGL, missing extension, no GLES 3.1 ...). */
struct platform *platform_open(const struct platform_options *opt, char *err, size_t errlen);
void platform_close(struct platform *p);
int platform_present(struct platform *p);
/* Window-system events (see platform_backend.dispatch): 1 closed, 0 go on,
 * -1 error.  Always 0 for headless backends. */
int platform_dispatch(struct platform *p);
/* Names of the backends compiled in, space-separated. */
const char *platform_backend_names(void);
/* --list-devices: every EGL device in eglQueryDevicesEXT's order, its
 * index, kind, DRM node(s), the GL renderer a context on it reports (or
 * why none opens) and its extensions, to f.  0 (also with no device), or
 * -1 with err when EGL cannot enumerate devices.  No platform may be open. */
int platform_list_devices(FILE *f, char *err, size_t errlen);
/* The current context's GL_VERSION when it is OpenGL ES 3.1 or later, else
 * NULL with err (one check for the platform's contexts and gpu_init). */
const char *platform_check_gles31(char *err, size_t errlen);
/* A capability, not a name: whether display dpy's EGL device renders on
 * the CPU (EGL_MESA_device_software: llvmpipe, softpipe, lavapipe under
 * zink).  A display whose device cannot be queried counts as hardware. */
bool platform_display_software(EGLDisplay dpy);
/* A device option's form: "" (none), a decimal index or an absolute path.
 * 0, or -1 with err (which device it names is only known at open). */
int platform_device_check(const char *spec, char *err, size_t errlen);

/* ---- for the backends only (files under platform/) -------------------------------- */

extern const struct platform_backend platform_backend_device;
extern const struct platform_backend platform_backend_surfaceless;
#ifdef ISOTERRA_HAVE_GBM
extern const struct platform_backend platform_backend_gbm;
#endif
#ifdef ISOTERRA_HAVE_WAYLAND
extern const struct platform_backend platform_backend_wayland;
#endif
#ifdef ISOTERRA_HAVE_X11
extern const struct platform_backend platform_backend_x11;
#endif

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
/* Display backends: on p->dpy choose a window config (native visual id
 * `visual` when non-zero, else preferring one without alpha), create the
 * GLES 3.1 context, the window surface for `native_window` (as
 * eglCreatePlatformWindowSurfaceEXT wants it) and make both current; swap
 * interval 1.  A NULL native_window stops after the config is chosen (the
 * caller reads p->config to create its window, then calls again). */
int egl_common_make_window_context(struct platform *p, const struct platform_options *opt,
                                   EGLint visual, void *native_window, char *err, size_t errlen);
/* Display backends that present by reading the frame back (x11 through
 * MIT-SHM): the GLES 3.1 context current on a w x h pbuffer.  With no
 * context yet, p->config becomes an 8-bit RGBA config with pbuffers where
 * there is one (its frame reads back as BGRA by a copy), and the context
 * is made on it.  Called again, a new pbuffer (the window's new size)
 * replaces the surface, as a window surface then can. */
int egl_common_make_pbuffer_context(struct platform *p, const struct platform_options *opt, int w, int h,
                                    char *err, size_t errlen);
/* The context and surface gone (the display and config kept): a backend
 * that tried one kind of surface and goes on with another config. */
void egl_common_drop_context(struct platform *p);
/* Releases whatever egl_common_* created (safe on partial state). */
void egl_common_release(struct platform *p);
/* enable: route EGL_KHR_debug messages to the platform's log (verbose: also warnings and
 * info); !enable: remove the callback.  No-op without EGL_KHR_debug. */
void egl_common_debug_callback(bool enable, bool verbose);

#endif
