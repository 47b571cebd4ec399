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
 * Flips: gbm_flip.c (pipelined with fences where the kernel offers them).
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
#include "gbm_int.h"
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

#define CONNECTOR_POLL_MS 1000

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

static void hide_cursor(struct gbm_state *g)
{
	if (drmModeSetCursor(g->kms.fd, g->kms.crtc_id, 0, 0, 0) != 0)
		plog_debug("gbm: hiding the cursor: %s", strerror(errno));
}

static int modeset(struct gbm_state *g, uint32_t fb)
{
	(void)gbm_finish_flip(g); /* (none in flight: watch_connector waited for it) */
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
	gbm_say_flips(g);
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
	(void)gbm_finish_flip(g); /* (none in flight: watch_connector waited for it) */
	gbm_show(g, NULL);
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
int gbm_watch_connector(struct gbm_state *g, bool at_once)
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
		(void)gbm_finish_flip(g);
		if (g->connected)
			plog_warn("gbm: %s on %s disconnected%s: frames go on, not shown, until it is back",
			         g->kms.conn_name, g->kms.path, g->want_mode[0] ? " (or no longer offers --mode)" : "");
		g->connected = false;
		return 0;
	}
	if (g->connected && !changed)
		return 0;
	(void)gbm_finish_flip(g); /* before the modeset, and before a new size's surface */
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

static int gbm_present(struct platform *p)
{
	struct gbm_state *g = p->priv;
	/* in-fences: the GPU's render fence of this frame, for its flip */
	EGLSyncKHR sync = g->in_fences && g->connected && g->modeset_done ? gbm_render_sync(g) : EGL_NO_SYNC_KHR;
	if (!eglSwapBuffers(p->dpy, p->surface)) {
		plog_error("gbm: eglSwapBuffers failed: %s", egl_common_error_name(eglGetError()));
		if (sync != EGL_NO_SYNC_KHR && !g->destroy_sync(p->dpy, sync))
			plog_debug("gbm: eglDestroySyncKHR: %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	int in_fence = gbm_render_fence_fd(g, sync);
	struct gbm_bo *bo = gbm_surface_lock_front_buffer(g->surf);
	if (!bo) {
		plog_error("gbm: gbm_surface_lock_front_buffer failed");
		gbm_close_fd(&in_fence);
		return -1;
	}
	if (!g->connected) {
		gbm_close_fd(&in_fence);
		drop_frame(g, bo);
		return gbm_watch_connector(g, false);
	}
	uint32_t fb = bo_fb(g, bo);
	int rc = fb ? 0 : -1;
	if (rc == 0 && !g->modeset_done) {
		rc = modeset(g, fb);
		if (rc < 0 && gbm_watch_connector(g, true) == 0 && !g->connected)
			rc = 1; /* gone again before it could be shown */
		if (rc == 0)
			gbm_show(g, bo);
	} else if (rc == 0) {
		rc = gbm_flip(g, fb, bo, in_fence); /* bo shown, or in flight */
	}
	gbm_close_fd(&in_fence); /* the kernel holds its own reference */
	if (rc != 0) {
		gbm_surface_release_buffer(g->surf, bo);
		return rc < 0 ? -1 : 0;
	}
	return gbm_watch_connector(g, false);
}

/* Put back the CRTC we found (the console's framebuffer and mode), or turn
 * the CRTC off when it was off. */
static void restore_crtc(struct gbm_state *g)
{
	if (g->restore_done || !g->modeset_done)
		return;
	g->restore_done = true;
	if (g->flip_pending)
		(void)gbm_wait_flip(g);
	if (g->pipelined) {
		(void)gbm_finish_flip(g);
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
	gbm_close_fd(&g->pending_fence);
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
	gbm_choose_flips(g);
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
