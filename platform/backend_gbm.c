/* isoterra — GBM/KMS display backend (kiosks, no window system).
 *
 * Takes the output kms.c picks (a DRM card, its connector, mode and CRTC),
 * renders through a gbm_surface with EGL's GBM platform and scans the
 * buffers out: atomic modesetting (kms_atomic.c: TEST_ONLY first, then a
 * real commit) with a legacy drmModeSetCrtc/drmModePageFlip fallback
 * (kms_legacy.c).  close() puts back the CRTC that was there before (the
 * console, usually).  Structure after kmscube (drm-common, drm-atomic,
 * drm-legacy).
 *
 * Flips, three ways (said once, at info level, at the first modeset):
 *   - atomic with the CRTC's OUT_FENCE_PTR: pipelined.  present() commits
 *     the flip with DRM_MODE_ATOMIC_NONBLOCK and returns; the kernel's
 *     out-fence for it is waited for (poll) only when it must be: at the
 *     next present, before the next commit (the kernel refuses a
 *     nonblocking commit while one is pending, EBUSY), and before anything
 *     that reuses or releases a buffer the display may still scan out (a
 *     new mode, the display gone, close).  So the frame loop renders the
 *     next frame while the flip waits for vsync.  A bo goes back to the
 *     gbm surface only once the flip that replaced it signalled; up to
 *     three are locked (on screen, flipping, just rendered) of the
 *     surface's four.  With EGL_ANDROID_native_fence_sync (and the plane's
 *     IN_FENCE_FD) the GPU's render fence rides along as the plane's
 *     IN_FENCE_FD, so the kernel, not the CPU, waits for the rendering;
 *     without (llvmpipe / kms_swrast) the dma-buf's implicit fences do.
 *   - atomic without OUT_FENCE_PTR, or a kernel that refuses the fences:
 *     each flip waits for its DRM_MODE_PAGE_FLIP_EVENT in present().
 *   - legacy: drmModePageFlip, the same wait.
 * p->shown counts the flips the display confirmed (the out-fence or the
 * event), the modesets too; pipelined, the last flip is confirmed one
 * present later (or at close, which says so).
 *
 * A display that goes away (a cable pulled) does not stop the program:
 * once a second present() asks the kernel whether the connector is still
 * connected (drmModeGetConnectorCurrent: no probe, one ioctl; a probe
 * when the kernel sent a hotplug event or the connector is back: kms.c,
 * hotplug.c).  Unplugged,
 * it says so once and frames go on being rendered and counted, not shown
 * (paced at the mode's refresh rate); a flip that fails or never completes
 * asks at once.  Plugged back, it modesets again, at the mode the connector
 * offers now (the preferred one, or --mode); a new size re-creates the
 * surface and the renderer follows (the display sink's resize). */
#include "kms.h"
#include "platform.h"
#include "platform_util.h"

#include <errno.h>
#include <poll.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <gbm.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

#define FLIP_TIMEOUT_MS 5000
#define CONNECTOR_POLL_MS 1000
#define EBUSY_RETRIES 100 /* of 1 ms, should the kernel still be busy with the flip before */

struct gbm_state {
	struct kms_output kms;     /* card, connector, mode, CRTC */
	struct gbm_device *gbm;
	struct gbm_surface *surf;
	struct gbm_bo *front;      /* on screen */
	struct kms_atomic at;      /* atomic modesetting's plane, properties, mode blob */
	drmModeCrtc *saved;        /* the CRTC as we found it, put back on close */
	bool atomic, modeset_done, flip_pending, restore_done;
	/* pipelined flips (atomic with out-fences): the bo committed last and
	 * the out-fence of its flip (-1: none in flight); with in-fences, the
	 * EGL entry points for the GPU's render fence */
	bool pipelined, in_fences, flips_said, fence_proven;
	const char *no_in_fence;   /* why there are none, for the info line */
	struct gbm_bo *pending;
	int pending_fence;
	PFNEGLCREATESYNCKHRPROC create_sync;
	PFNEGLDESTROYSYNCKHRPROC destroy_sync;
	PFNEGLDUPNATIVEFENCEFDANDROIDPROC dup_fence;
	struct platform *p;
	char want_mode[32];        /* --mode ("" = the preferred one), chosen again on return */
	bool connected;            /* the connector, as last asked */
	double next_poll;          /* platform_clock_ms() of the next question */
};

struct gbm_fb {
	int fd;
	uint32_t fb_id;
};

static bool gbm_probe(void)
{
	return kms_probe();
}

/* ---- framebuffers -------------------------------------------------------- */

static void fb_destroy(struct gbm_bo *bo, void *data)
{
	(void)bo;
	struct gbm_fb *fb = data;
	if (fb->fb_id && drmModeRmFB(fb->fd, fb->fb_id) != 0)
		plog_warn("gbm: drmModeRmFB(%u): %s", fb->fb_id, strerror(errno));
	free(fb);
}

/* The KMS framebuffer of a bo, created once and cached on the bo. */
static uint32_t bo_fb(struct gbm_state *g, struct gbm_bo *bo)
{
	struct gbm_fb *fb = gbm_bo_get_user_data(bo);
	if (fb)
		return fb->fb_id;
	fb = calloc(1, sizeof(*fb));
	if (!fb) {
		plog_error("gbm: out of memory");
		return 0;
	}
	fb->fd = g->kms.fd;
	uint32_t w = gbm_bo_get_width(bo), h = gbm_bo_get_height(bo), format = gbm_bo_get_format(bo);
	uint32_t handles[4] = { 0 }, strides[4] = { 0 }, offsets[4] = { 0 };
	int planes = gbm_bo_get_plane_count(bo);
	for (int i = 0; i < planes && i < 4; i++) {
		handles[i] = gbm_bo_get_handle_for_plane(bo, i).u32;
		strides[i] = gbm_bo_get_stride_for_plane(bo, i);
		offsets[i] = gbm_bo_get_offset(bo, i);
	}
	if (drmModeAddFB2(g->kms.fd, w, h, format, handles, strides, offsets, &fb->fb_id, 0) != 0) {
		int e = errno;
		if (drmModeAddFB(g->kms.fd, w, h, 24, 32, strides[0], handles[0], &fb->fb_id) != 0) {
			plog_error("gbm: cannot create a %ux%u framebuffer: drmModeAddFB2: %s, drmModeAddFB: %s",
			          w, h, strerror(e), strerror(errno));
			free(fb);
			return 0;
		}
	}
	gbm_bo_set_user_data(bo, fb, fb_destroy);
	return fb->fb_id;
}

/* ---- page flips ---------------------------------------------------------- */

static void flip_handler(int fd, unsigned frame, unsigned sec, unsigned usec, void *data)
{
	(void)fd;
	(void)frame;
	(void)sec;
	(void)usec;
	struct gbm_state *g = data;
	g->flip_pending = false;
	g->p->shown++;
}

static int wait_flip(struct gbm_state *g)
{
	drmEventContext ev = {
		.version = 2,
		.page_flip_handler = flip_handler,
	};
	while (g->flip_pending) {
		struct pollfd pfd = { .fd = g->kms.fd, .events = POLLIN };
		int n = poll(&pfd, 1, FLIP_TIMEOUT_MS);
		if (n < 0) {
			if (errno == EINTR)
				continue; /* a signal: the flip still completes */
			plog_error("gbm: poll on %s: %s", g->kms.path, strerror(errno));
			return -1;
		}
		if (n == 0) {
			plog_error("gbm: no page-flip event from %s within %d ms", g->kms.path, FLIP_TIMEOUT_MS);
			return -1;
		}
		if (drmHandleEvent(g->kms.fd, &ev) != 0) {
			plog_error("gbm: drmHandleEvent: %s", strerror(errno));
			return -1;
		}
	}
	return 0;
}

/* The bo shown now: the one before goes back to the surface. */
static void show(struct gbm_state *g, struct gbm_bo *bo)
{
	if (g->front)
		gbm_surface_release_buffer(g->surf, g->front);
	g->front = bo;
}

static void close_fd(int *fd)
{
	if (*fd >= 0 && close(*fd) != 0)
		plog_debug("gbm: close(fence %d): %s", *fd, strerror(errno));
	*fd = -1;
}

/* Pipelined: the flip in flight is on screen (its out-fence signalled):
 * its bo is the front, the one it replaced goes back.  confirmed: false
 * when it is only taken as done (the display gone, the fence never came). */
static void flip_done(struct gbm_state *g, bool confirmed)
{
	close_fd(&g->pending_fence);
	show(g, g->pending);
	g->pending = NULL;
	if (confirmed)
		g->p->shown++;
}

/* Pipelined: waits (up to FLIP_TIMEOUT_MS) for the flip in flight, if any.
 * 0, or -1 when its out-fence did not signal or cannot be waited for
 * (logged; the flip is then taken as done, unconfirmed). */
static int finish_flip(struct gbm_state *g)
{
	if (!g->pending)
		return 0;
	int rc = kms_fence_wait(g->pending_fence, FLIP_TIMEOUT_MS);
	if (rc > 0) {
		g->fence_proven = true;
		flip_done(g, true);
		return 0;
	}
	if (rc == 0)
		plog_error("gbm: no page flip on %s within %d ms (its out-fence did not signal)", g->kms.path,
		           FLIP_TIMEOUT_MS);
	else
		plog_error("gbm: waiting for the page flip's out-fence on %s: %s", g->kms.path, strerror(errno));
	flip_done(g, false);
	return -1;
}

/* The flip path, once (see the top of this file). */
static void say_flips(struct gbm_state *g)
{
	if (g->flips_said)
		return;
	g->flips_said = true;
	if (!g->atomic)
		plog_info("kms: legacy, each flip waits for its page-flip event");
	else if (!g->pipelined)
		plog_info("kms: atomic, each flip waits for its page-flip event (no OUT_FENCE_PTR on CRTC %u)",
		          g->kms.crtc_id);
	else if (g->in_fences)
		plog_info("kms: atomic, flips pipelined with out-fences and in-fences (EGL_ANDROID_native_fence_sync)");
	else
		plog_info("kms: atomic, flips pipelined with out-fences (no in-fence: %s)", g->no_in_fence);
}

/* Atomic: pipelined when the CRTC has OUT_FENCE_PTR; in-fences too when
 * the plane has IN_FENCE_FD and the EGL EGL_ANDROID_native_fence_sync. */
static void choose_flips(struct gbm_state *g)
{
	g->pipelined = g->atomic && g->at.crtc_out_fence_ptr;
	if (!g->pipelined)
		return;
	const char *dexts = eglQueryString(g->p->dpy, EGL_EXTENSIONS);
	if (!g->at.plane_in_fence_fd) {
		g->no_in_fence = "the plane has no IN_FENCE_FD";
		return;
	}
	if (!egl_common_has_ext(dexts, "EGL_ANDROID_native_fence_sync")) {
		g->no_in_fence = "EGL_ANDROID_native_fence_sync missing";
		return;
	}
	g->create_sync = (PFNEGLCREATESYNCKHRPROC)eglGetProcAddress("eglCreateSyncKHR");
	g->destroy_sync = (PFNEGLDESTROYSYNCKHRPROC)eglGetProcAddress("eglDestroySyncKHR");
	g->dup_fence = (PFNEGLDUPNATIVEFENCEFDANDROIDPROC)eglGetProcAddress("eglDupNativeFenceFDANDROID");
	if (!g->create_sync || !g->destroy_sync || !g->dup_fence) {
		g->no_in_fence = "no eglCreateSyncKHR / eglDupNativeFenceFDANDROID";
		return;
	}
	g->in_fences = true;
}

/* In-fences fail at run time: said once, the flips go on without (the
 * dma-buf's implicit fences still order rendering and scanout). */
static void no_more_in_fences(struct gbm_state *g, const char *what, const char *why)
{
	plog_warn("kms: %s: %s; flips go on without in-fences", what, why);
	g->in_fences = false;
	g->no_in_fence = "they failed";
}

/* The GPU's render fence, made before eglSwapBuffers (which flushes it). */
static EGLSyncKHR render_sync(struct gbm_state *g)
{
	static const EGLint attribs[] = { EGL_SYNC_NATIVE_FENCE_FD_ANDROID, EGL_NO_NATIVE_FENCE_FD_ANDROID, EGL_NONE };
	EGLSyncKHR s = g->create_sync(g->p->dpy, EGL_SYNC_NATIVE_FENCE_ANDROID, attribs);
	if (s == EGL_NO_SYNC_KHR)
		no_more_in_fences(g, "eglCreateSyncKHR(EGL_SYNC_NATIVE_FENCE_ANDROID)", egl_common_error_name(eglGetError()));
	return s;
}

/* Its fd after the swap (-1 when none), the EGL sync destroyed. */
static int render_fence_fd(struct gbm_state *g, EGLSyncKHR s)
{
	if (s == EGL_NO_SYNC_KHR)
		return -1;
	int fd = g->dup_fence(g->p->dpy, s);
	if (fd < 0)
		no_more_in_fences(g, "eglDupNativeFenceFDANDROID", egl_common_error_name(eglGetError()));
	if (!g->destroy_sync(g->p->dpy, s))
		plog_debug("gbm: eglDestroySyncKHR: %s", egl_common_error_name(eglGetError()));
	return fd < 0 ? -1 : fd;
}

static void hide_cursor(struct gbm_state *g)
{
	if (drmModeSetCursor(g->kms.fd, g->kms.crtc_id, 0, 0, 0) != 0)
		plog_debug("gbm: hiding the cursor: %s", strerror(errno));
}

static int modeset(struct gbm_state *g, uint32_t fb)
{
	(void)finish_flip(g); /* (none in flight: watch_connector waited for it) */
	if (g->atomic) {
		if (kms_atomic_commit(&g->at, &g->kms, fb, true, DRM_MODE_ATOMIC_TEST_ONLY, g, -1, NULL) != 0) {
			plog_debug("gbm: atomic TEST_ONLY commit refused (%s); legacy modesetting", strerror(errno));
			g->atomic = false;
			g->pipelined = false;
			g->in_fences = false;
		} else if (kms_atomic_commit(&g->at, &g->kms, fb, true, 0, g, -1, NULL) != 0) {
			plog_error("gbm: atomic modeset %ux%u on %s: %s", g->kms.mode.hdisplay, g->kms.mode.vdisplay,
			          g->kms.path, strerror(errno));
			return -1;
		}
	}
	if (!g->atomic && kms_legacy_modeset(&g->kms, fb) != 0) {
		plog_error("gbm: drmModeSetCrtc %ux%u on %s: %s", g->kms.mode.hdisplay, g->kms.mode.vdisplay,
		          g->kms.path, strerror(errno));
		return -1;
	}
	hide_cursor(g);
	plog_info("gbm: %s %s %ux%u@%u (%s modesetting)", g->kms.path, g->kms.conn_name, g->kms.mode.hdisplay,
	         g->kms.mode.vdisplay, g->kms.mode.vrefresh, g->atomic ? "atomic" : "legacy");
	say_flips(g);
	g->modeset_done = true;
	g->p->shown++;
	return 0;
}

/* A new size: the gbm surface and its EGL window surface made again (the
 * old buffers go with them; the modeset that follows shows a new one). */
static int remake_surface(struct gbm_state *g)
{
	struct platform *p = g->p;
	int w = g->kms.mode.hdisplay, h = g->kms.mode.vdisplay;
	if (!eglMakeCurrent(p->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, p->ctx)) {
		plog_error("gbm: eglMakeCurrent(no surface): %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	if (!eglDestroySurface(p->dpy, p->surface))
		plog_warn("gbm: eglDestroySurface: %s", egl_common_error_name(eglGetError()));
	p->surface = EGL_NO_SURFACE;
	(void)finish_flip(g); /* (none in flight: watch_connector waited for it) */
	show(g, NULL);
	gbm_surface_destroy(g->surf);
	g->surf = gbm_surface_create(g->gbm, (uint32_t)w, (uint32_t)h, GBM_FORMAT_XRGB8888,
	                             GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
	if (!g->surf) {
		plog_error("gbm: gbm_surface_create %dx%d on %s failed", w, h, g->kms.path);
		return -1;
	}
	PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC create_surface =
		(PFNEGLCREATEPLATFORMWINDOWSURFACEEXTPROC)eglGetProcAddress("eglCreatePlatformWindowSurfaceEXT");
	p->surface = create_surface ? create_surface(p->dpy, p->config, g->surf, NULL) : EGL_NO_SURFACE;
	if (p->surface == EGL_NO_SURFACE || !eglMakeCurrent(p->dpy, p->surface, p->surface, p->ctx)) {
		plog_error("gbm: a %dx%d window surface: %s", w, h, egl_common_error_name(eglGetError()));
		return -1;
	}
	p->width = w;
	p->height = h;
	return 0;
}

/* The connector's mode changed while it was away: the atomic mode blob and,
 * for a new size, the surface follow. */
static int follow_mode(struct gbm_state *g)
{
	if (g->atomic && kms_atomic_set_mode(&g->at, &g->kms) < 0)
		return -1;
	if (g->kms.mode.hdisplay != g->p->width || g->kms.mode.vdisplay != g->p->height)
		return remake_surface(g);
	return 0;
}

/* Is the connector still there (asked once a second, or at once)?  Gone:
 * said once, frames go on unshown.  Back, or at another mode: the next
 * present modesets.  0, or -1 when the surface cannot follow a new size. */
static int watch_connector(struct gbm_state *g, bool at_once)
{
	double t = platform_clock_ms();
	if (!at_once && t < g->next_poll)
		return 0;
	g->next_poll = t + CONNECTOR_POLL_MS;
	bool changed = false;
	int st = kms_output_poll(&g->kms, g->want_mode, &changed);
	if (st < 0) {
		plog_debug("gbm: connector %u on %s: %s", g->kms.conn_id, g->kms.path, strerror(errno));
		return 0; /* cannot tell: as before */
	}
	if (st == 0) {
		/* the flip in flight, if any, is over (or given up) before the
		 * frames go on unshown */
		(void)finish_flip(g);
		if (g->connected)
			plog_warn("gbm: %s on %s disconnected%s: frames go on, not shown, until it is back",
			         g->kms.conn_name, g->kms.path, g->want_mode[0] ? " (or no longer offers --mode)" : "");
		g->connected = false;
		return 0;
	}
	if (g->connected && !changed)
		return 0;
	(void)finish_flip(g); /* before the modeset, and before a new size's surface */
	plog_info("gbm: %s on %s %s: modesetting %ux%u@%u", g->kms.conn_name, g->kms.path,
	         g->connected ? "changed its mode" : "connected again", g->kms.mode.hdisplay, g->kms.mode.vdisplay,
	         g->kms.mode.vrefresh);
	g->connected = true;
	g->modeset_done = false;
	return changed ? follow_mode(g) : 0;
}

/* Unplugged: the frame is dropped, at the pace the display had. */
static void drop_frame(struct gbm_state *g, struct gbm_bo *bo)
{
	gbm_surface_release_buffer(g->surf, bo);
	unsigned hz = g->kms.mode.vrefresh ? g->kms.mode.vrefresh : 60;
	struct timespec ts = { 0, (long)(1000000000L / hz) };
	while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
		;
}

/* Pipelined: the flip of bo (fb) committed with DRM_MODE_ATOMIC_NONBLOCK
 * and an out-fence (and in_fence, the GPU's render fence, when >= 0); the
 * flip before waited for first.  0 committed (bo is in flight), 1 refused
 * because the display is gone, -1 error, 2 the kernel refused the fences
 * on the first flip (the caller goes on with events). */
static int flip_pipelined(struct gbm_state *g, uint32_t fb, struct gbm_bo *bo, int in_fence)
{
	if (finish_flip(g) < 0) {
		/* given up on (taken as done): the display gone, or an error */
		if (watch_connector(g, true) == 0 && !g->connected)
			return 1;
		return -1;
	}
	int fence = -1, rc;
	for (int tries = 0;; tries++) {
		rc = kms_atomic_commit(&g->at, &g->kms, fb, false, DRM_MODE_ATOMIC_NONBLOCK, g, in_fence, &fence);
		if (rc == 0 || errno != EBUSY || tries >= EBUSY_RETRIES)
			break;
		struct timespec ms = { 0, 1000000L };
		nanosleep(&ms, NULL);
	}
	if (rc == 0 && fence < 0) {
		/* committed, but no fence to wait for: the flip is done once
		 * the kernel takes the next commit; from now on events */
		plog_warn("kms: the atomic commit on %s gave no out-fence; flips wait for their events from now on",
		          g->kms.path);
		g->pipelined = false;
		g->in_fences = false;
		show(g, bo);
		return 0;
	}
	if (rc != 0) {
		int e = errno;
		if (watch_connector(g, true) == 0 && !g->connected)
			return 1;
		if (!g->fence_proven && g->modeset_done && (e == EINVAL || e == EOPNOTSUPP)) {
			/* no flip with fences went through yet: the kernel may
			 * not take them after all */
			if (in_fence >= 0) {
				no_more_in_fences(g, "the kernel refused the in-fence", strerror(e));
				return flip_pipelined(g, fb, bo, -1);
			}
			plog_info("kms: atomic, each flip waits for its page-flip event (the kernel refused the out-fence: %s)",
			          strerror(e));
			g->pipelined = false;
			return 2;
		}
		plog_error("gbm: atomic page flip on %s: %s", g->kms.path, strerror(e));
		return -1;
	}
	g->pending = bo;
	g->pending_fence = fence;
	return 0;
}

/* A page flip of bo (fb): 0 committed (bo is the front now, or in flight
 * when pipelined), 1 refused because the display is gone (the connector
 * unplugged), -1 error.  A flip whose event never comes counts as
 * committed when the connector is gone. */
static int flip(struct gbm_state *g, uint32_t fb, struct gbm_bo *bo, int in_fence)
{
	if (g->pipelined) {
		int rc = flip_pipelined(g, fb, bo, g->in_fences ? in_fence : -1);
		if (rc != 2)
			return rc;
	}
	g->flip_pending = true;
	int rc;
	if (g->atomic)
		rc = kms_atomic_commit(&g->at, &g->kms, fb, false, DRM_MODE_PAGE_FLIP_EVENT | DRM_MODE_ATOMIC_NONBLOCK, g,
		                       -1, NULL);
	else
		rc = kms_legacy_flip(&g->kms, fb, g);
	if (rc != 0) {
		int e = errno;
		g->flip_pending = false;
		if (watch_connector(g, true) == 0 && !g->connected)
			return 1;
		plog_error("gbm: %s on %s: %s", g->atomic ? "atomic page flip" : "drmModePageFlip", g->kms.path,
		          strerror(e));
		return -1;
	}
	if (wait_flip(g) == 0) {
		show(g, bo);
		return 0;
	}
	if (watch_connector(g, true) == 0 && !g->connected) {
		g->flip_pending = false; /* its event may still come */
		show(g, bo);
		return 0;
	}
	return -1;
}

static int gbm_present(struct platform *p)
{
	struct gbm_state *g = p->priv;
	/* in-fences: the GPU's render fence of this frame, for its flip */
	EGLSyncKHR sync = g->in_fences && g->connected && g->modeset_done ? render_sync(g) : EGL_NO_SYNC_KHR;
	if (!eglSwapBuffers(p->dpy, p->surface)) {
		plog_error("gbm: eglSwapBuffers failed: %s", egl_common_error_name(eglGetError()));
		if (sync != EGL_NO_SYNC_KHR && !g->destroy_sync(p->dpy, sync))
			plog_debug("gbm: eglDestroySyncKHR: %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	int in_fence = render_fence_fd(g, sync);
	struct gbm_bo *bo = gbm_surface_lock_front_buffer(g->surf);
	if (!bo) {
		plog_error("gbm: gbm_surface_lock_front_buffer failed");
		close_fd(&in_fence);
		return -1;
	}
	if (!g->connected) {
		close_fd(&in_fence);
		drop_frame(g, bo);
		return watch_connector(g, false);
	}
	uint32_t fb = bo_fb(g, bo);
	int rc = fb ? 0 : -1;
	if (rc == 0 && !g->modeset_done) {
		rc = modeset(g, fb);
		if (rc < 0 && watch_connector(g, true) == 0 && !g->connected)
			rc = 1; /* gone again before it could be shown */
		if (rc == 0)
			show(g, bo);
	} else if (rc == 0) {
		rc = flip(g, fb, bo, in_fence); /* bo shown, or in flight */
	}
	close_fd(&in_fence); /* the kernel holds its own reference */
	if (rc != 0) {
		gbm_surface_release_buffer(g->surf, bo);
		return rc < 0 ? -1 : 0;
	}
	return watch_connector(g, false);
}

/* Put back the CRTC we found (the console's framebuffer and mode), or turn
 * the CRTC off when it was off. */
static void restore_crtc(struct gbm_state *g)
{
	if (g->restore_done || !g->modeset_done)
		return;
	g->restore_done = true;
	if (g->flip_pending)
		(void)wait_flip(g);
	if (g->pipelined) {
		(void)finish_flip(g);
		plog_info("kms: no flip in flight when the CRTC was restored: %lu of %lu frames shown", g->p->shown,
		          g->p->presented);
	}
	drmModeCrtc *s = g->saved;
	if (kms_legacy_restore(&g->kms, s) != 0)
		plog_warn("gbm: restoring CRTC %u on %s: %s", g->kms.crtc_id, g->kms.path, strerror(errno));
	else
		plog_debug("gbm: CRTC %u restored (fb %u)", g->kms.crtc_id, s ? s->buffer_id : 0);
}

static void gbm_close(struct platform *p)
{
	struct gbm_state *g = p->priv;
	if (g)
		restore_crtc(g);
	egl_common_release(p);
	if (!g)
		return;
	if (g->pending)
		gbm_surface_release_buffer(g->surf, g->pending);
	close_fd(&g->pending_fence);
	if (g->front)
		gbm_surface_release_buffer(g->surf, g->front);
	if (g->surf)
		gbm_surface_destroy(g->surf); /* frees the bos: fb_destroy removes the FBs */
	if (g->gbm)
		gbm_device_destroy(g->gbm);
	kms_atomic_release(&g->at, g->kms.fd);
	if (g->saved)
		drmModeFreeCrtc(g->saved);
	kms_output_close(&g->kms);
	free(g);
	p->priv = NULL;
}

/* The card first (a missing or wrong --drm-device is named whatever the
 * EGL), then whether this EGL renders to GBM at all, before anything is
 * changed on the card (DRM master, modeset). */
static int gbm_open(struct platform *p, const struct platform_options *opt, char *err, size_t errlen)
{
	const char *cexts = egl_common_client_exts();
	struct gbm_state *g = calloc(1, sizeof(*g));
	if (!g) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	g->kms.fd = -1;
	g->pending_fence = -1;
	g->p = p;
	p->priv = g;
	g->connected = true;
	g->next_poll = platform_clock_ms() + CONNECTOR_POLL_MS;
	if (opt->mode && strlen(opt->mode) >= sizeof(g->want_mode)) {
		snprintf(err, errlen, "--mode '%.40s...' is not WxH or WxH@Hz", opt->mode);
		goto fail;
	}
	snprintf(g->want_mode, sizeof(g->want_mode), "%s", opt->mode ? opt->mode : "");
	if (kms_output_open(&g->kms, opt->drm_device, opt->mode, err, errlen) < 0)
		goto fail;
	if (!egl_common_has_ext(cexts, "EGL_KHR_platform_gbm") && !egl_common_has_ext(cexts, "EGL_MESA_platform_gbm")) {
		snprintf(err, errlen, "EGL_KHR_platform_gbm not supported by this EGL");
		goto fail;
	}
	if (!drmIsMaster(g->kms.fd) && drmSetMaster(g->kms.fd) != 0) {
		snprintf(err, errlen, "%s: cannot become DRM master (%s): another program (a compositor, "
		         "an X server) drives the display", g->kms.path, strerror(errno));
		goto fail;
	}
	g->saved = drmModeGetCrtc(g->kms.fd, g->kms.crtc_id);
	if (!g->saved)
		plog_warn("gbm: cannot read CRTC %u (%s); it will be turned off on exit", g->kms.crtc_id,
		         strerror(errno));
	g->atomic = !opt->kms_legacy && kms_atomic_init(&g->at, &g->kms);

	g->gbm = gbm_create_device(g->kms.fd);
	if (!g->gbm) {
		snprintf(err, errlen, "gbm_create_device(%s) failed", g->kms.path);
		goto fail;
	}
	p->width = g->kms.mode.hdisplay;
	p->height = g->kms.mode.vdisplay;
	g->surf = gbm_surface_create(g->gbm, (uint32_t)p->width, (uint32_t)p->height, GBM_FORMAT_XRGB8888,
	                             GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
	if (!g->surf) {
		snprintf(err, errlen, "gbm_surface_create %dx%d XRGB8888 on %s failed", p->width, p->height,
		         g->kms.path);
		goto fail;
	}
	if (egl_common_open_display(p, EGL_PLATFORM_GBM_KHR, g->gbm, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, GBM_FORMAT_XRGB8888, NULL, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, GBM_FORMAT_XRGB8888, g->surf, err, errlen) < 0)
		goto fail;
	size_t len = strlen(p->device_desc);
	if (len + strlen(g->kms.path) + 4 < sizeof(p->device_desc))
		snprintf(p->device_desc + len, sizeof(p->device_desc) - len, " (%s)", g->kms.path);
	plog_debug("gbm: %s connector %s, mode %ux%u@%u, CRTC %u, %s", g->kms.path, g->kms.conn_name,
	          g->kms.mode.hdisplay, g->kms.mode.vdisplay, g->kms.mode.vrefresh, g->kms.crtc_id,
	          g->atomic ? "atomic" : "legacy");
	p->refresh_hz = g->kms.mode.vrefresh;
	choose_flips(g);
	return 0;
fail:
	gbm_close(p);
	return -1;
}

const struct platform_backend platform_backend_gbm = {
	.name = "gbm",
	.probe = gbm_probe,
	.open = gbm_open,
	.close = gbm_close,
	.present = gbm_present,
	/* no window system: no events (dispatch NULL) */
};
