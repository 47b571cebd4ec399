/* isoterra — the GBM/KMS backend's page flips (backend_gbm.c presents,
 * this file flips).
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
 * present later (or at close, which says so). */
#include "gbm_int.h"
#include "platform_util.h"

#include <errno.h>
#include <poll.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <xf86drm.h>

/* One CRTC's page-flip event (the flip's, or a modeset's): the frame is
 * shown once every CRTC of the flip has said so. */
static void flip_handler(int fd, unsigned frame, unsigned sec, unsigned usec, unsigned crtc_id, void *data)
{
	(void)fd;
	(void)frame;
	(void)sec;
	(void)usec;
	struct gbm_state *g = data;
	for (int i = 0; i < g->n; i++)
		if (g->h[i].kms.crtc_id == crtc_id)
			g->h[i].flips++;
	if (g->events > 0)
		g->events--;
	if (g->events > 0)
		return;
	g->flip_pending = false;
	g->p->shown++;
}

bool gbm_any_connected(const struct gbm_state *g)
{
	for (int i = 0; i < g->n; i++)
		if (g->h[i].connected)
			return true;
	return false;
}

/* The outputs a flip shows: connected and modeset. */
static int live_heads(struct gbm_state *g, struct kms_atomic_head *ah, int *idx)
{
	int n = 0;
	for (int i = 0; i < g->n; i++) {
		struct gbm_head *h = &g->h[i];
		if (!h->connected || !h->modeset_done)
			continue;
		if (ah)
			ah[n] = (struct kms_atomic_head){ .a = &h->at, .o = &h->kms };
		if (idx)
			idx[n] = i;
		n++;
	}
	return n;
}

int gbm_wait_flip(struct gbm_state *g)
{
	drmEventContext ev = {
		.version = 3,
		.page_flip_handler2 = flip_handler,
	};
	const struct kms_output *k = &g->h[0].kms;
	while (g->flip_pending) {
		struct pollfd pfd = { .fd = k->fd, .events = POLLIN };
		int n = poll(&pfd, 1, FLIP_TIMEOUT_MS);
		if (n < 0) {
			if (errno == EINTR)
				continue; /* a signal: the flip still completes */
			plog_error("gbm: poll on %s: %s", k->path, strerror(errno));
			return -1;
		}
		if (n == 0) {
			plog_error("gbm: no page-flip event from %s within %d ms", k->path, FLIP_TIMEOUT_MS);
			return -1;
		}
		if (drmHandleEvent(k->fd, &ev) != 0) {
			plog_error("gbm: drmHandleEvent: %s", strerror(errno));
			return -1;
		}
	}
	return 0;
}

/* The bo shown now: the one before goes back to the surface. */
void gbm_show(struct gbm_state *g, struct gbm_bo *bo)
{
	if (g->front)
		gbm_surface_release_buffer(g->surf, g->front);
	g->front = bo;
}

void gbm_close_fd(int *fd)
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
	for (int i = 0; i < g->n; i++)
		gbm_close_fd(&g->h[i].fence);
	gbm_show(g, g->pending);
	g->pending = NULL;
	if (confirmed)
		g->p->shown++;
}

/* Pipelined: waits (up to FLIP_TIMEOUT_MS) for the flip in flight, if any.
 * 0, or -1 when its out-fence did not signal or cannot be waited for
 * (logged; the flip is then taken as done, unconfirmed). */
int gbm_finish_flip(struct gbm_state *g)
{
	if (!g->pending)
		return 0;
	int failed = 0;
	for (int i = 0; i < g->n; i++) {
		struct gbm_head *h = &g->h[i];
		if (h->fence < 0)
			continue;
		/* several outputs: which one */
		char where[96];
		snprintf(where, sizeof(where), "%s%s%s", h->kms.path, g->n > 1 ? " " : "", g->n > 1 ? h->kms.conn_name : "");
		int rc = kms_fence_wait(h->fence, FLIP_TIMEOUT_MS);
		if (rc > 0) {
			h->flips++;
			continue;
		}
		failed = 1;
		if (rc == 0)
			plog_error("gbm: no page flip on %s within %d ms (its out-fence did not signal)", where,
			           FLIP_TIMEOUT_MS);
		else
			plog_error("gbm: waiting for the page flip's out-fence on %s: %s", where, strerror(errno));
	}
	if (!failed)
		g->fence_proven = true;
	flip_done(g, !failed);
	return failed ? -1 : 0;
}

/* The flip path, once (see the top of this file). */
void gbm_say_flips(struct gbm_state *g)
{
	if (g->flips_said)
		return;
	g->flips_said = true;
	if (!g->atomic)
		plog_info("kms: legacy, each flip waits for its page-flip event");
	else if (!g->pipelined)
		plog_info("kms: atomic, each flip waits for its page-flip event (no OUT_FENCE_PTR on CRTC %u)",
		          g->h[0].kms.crtc_id);
	else if (g->in_fences)
		plog_info("kms: atomic, flips pipelined with out-fences and in-fences (EGL_ANDROID_native_fence_sync)");
	else
		plog_info("kms: atomic, flips pipelined with out-fences (no in-fence: %s)", g->no_in_fence);
}

/* Atomic: pipelined when the CRTC has OUT_FENCE_PTR; in-fences too when
 * the plane has IN_FENCE_FD and the EGL EGL_ANDROID_native_fence_sync. */
void gbm_choose_flips(struct gbm_state *g)
{
	g->pipelined = g->atomic;
	bool in_fence_fd = true;
	for (int i = 0; i < g->n; i++) {
		g->pipelined = g->pipelined && g->h[i].at.crtc_out_fence_ptr;
		in_fence_fd = in_fence_fd && g->h[i].at.plane_in_fence_fd;
	}
	if (!g->pipelined)
		return;
	const char *dexts = eglQueryString(g->p->dpy, EGL_EXTENSIONS);
	if (!in_fence_fd) {
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
EGLSyncKHR gbm_render_sync(struct gbm_state *g)
{
	static const EGLint attribs[] = { EGL_SYNC_NATIVE_FENCE_FD_ANDROID, EGL_NO_NATIVE_FENCE_FD_ANDROID, EGL_NONE };
	EGLSyncKHR s = g->create_sync(g->p->dpy, EGL_SYNC_NATIVE_FENCE_ANDROID, attribs);
	if (s == EGL_NO_SYNC_KHR)
		no_more_in_fences(g, "eglCreateSyncKHR(EGL_SYNC_NATIVE_FENCE_ANDROID)", egl_common_error_name(eglGetError()));
	return s;
}

/* Its fd after the swap (-1 when none), the EGL sync destroyed. */
int gbm_render_fence_fd(struct gbm_state *g, EGLSyncKHR s)
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


/* Pipelined: the flip of bo (fb) committed with DRM_MODE_ATOMIC_NONBLOCK
 * and an out-fence (and in_fence, the GPU's render fence, when >= 0); the
 * flip before waited for first.  0 committed (bo is in flight), 1 refused
 * because the display is gone, -1 error, 2 the kernel refused the fences
 * on the first flip (the caller goes on with events). */
static int flip_pipelined(struct gbm_state *g, uint32_t fb, struct gbm_bo *bo, int in_fence)
{
	if (gbm_finish_flip(g) < 0) {
		/* given up on (taken as done): the display gone, or an error */
		if (gbm_watch_connector(g, true) == 0 && (!gbm_any_connected(g) || g->lost))
			return 1;
		return -1;
	}
	struct kms_atomic_head ah[PLATFORM_MAX_OUTPUTS];
	int idx[PLATFORM_MAX_OUTPUTS];
	int n = live_heads(g, ah, idx), rc;
	for (int i = 0; i < n; i++)
		ah[i].out_fence = &g->h[idx[i]].fence;
	for (int tries = 0;; tries++) {
		rc = kms_atomic_commit_heads(ah, n, fb, DRM_MODE_ATOMIC_NONBLOCK, g, in_fence);
		if (rc == 0 || errno != EBUSY || tries >= EBUSY_RETRIES)
			break;
		struct timespec ms = { 0, 1000000L };
		nanosleep(&ms, NULL);
	}
	bool unfenced = false;
	for (int i = 0; i < n && rc == 0; i++)
		unfenced = unfenced || g->h[idx[i]].fence < 0;
	if (rc == 0 && unfenced) {
		/* committed, but no fence to wait for: the flip is done once
		 * the kernel takes the next commit; from now on events */
		plog_warn("kms: the atomic commit on %s gave no out-fence; flips wait for their events from now on",
		          g->h[0].kms.path);
		for (int i = 0; i < g->n; i++)
			gbm_close_fd(&g->h[i].fence);
		g->pipelined = false;
		g->in_fences = false;
		gbm_show(g, bo);
		return 0;
	}
	if (rc != 0) {
		int e = errno;
		if (gbm_watch_connector(g, true) == 0 && (!gbm_any_connected(g) || g->lost))
			return 1;
		if (!g->fence_proven && g->h[0].modeset_done && (e == EINVAL || e == EOPNOTSUPP)) {
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
		plog_error("gbm: atomic page flip on %s: %s", g->h[0].kms.path, strerror(e));
		return -1;
	}
	g->pending = bo;
	return 0;
}

/* A page flip of bo (fb): 0 committed (bo is the front now, or in flight
 * when pipelined), 1 refused because the display is gone (the connector
 * unplugged), -1 error.  A flip whose event never comes counts as
 * committed when the connector is gone. */
int gbm_flip(struct gbm_state *g, uint32_t fb, struct gbm_bo *bo, int in_fence)
{
	if (g->pipelined) {
		int rc = flip_pipelined(g, fb, bo, g->in_fences ? in_fence : -1);
		if (rc != 2)
			return rc;
	}
	struct kms_atomic_head ah[PLATFORM_MAX_OUTPUTS];
	int idx[PLATFORM_MAX_OUTPUTS];
	int n = live_heads(g, ah, idx);
	g->flip_pending = true;
	int rc = 0;
	if (g->atomic) {
		rc = kms_atomic_commit_heads(ah, n, fb, DRM_MODE_PAGE_FLIP_EVENT | DRM_MODE_ATOMIC_NONBLOCK, g, -1);
		g->events = rc == 0 ? n : 0;
	} else {
		/* one flip per CRTC, each with its event */
		g->events = 0;
		for (int i = 0; i < n && rc == 0; i++) {
			rc = kms_legacy_flip(&g->h[idx[i]].kms, fb, g);
			if (rc == 0)
				g->events++;
		}
	}
	if (rc != 0) {
		int e = errno;
		if (g->events > 0)
			(void)gbm_wait_flip(g); /* the CRTCs that did take it */
		g->flip_pending = false;
		g->events = 0;
		if (gbm_watch_connector(g, true) == 0 && (!gbm_any_connected(g) || g->lost))
			return 1;
		plog_error("gbm: %s on %s: %s", g->atomic ? "atomic page flip" : "drmModePageFlip", g->h[0].kms.path,
		          strerror(e));
		return -1;
	}
	if (gbm_wait_flip(g) == 0) {
		gbm_show(g, bo);
		return 0;
	}
	if (gbm_watch_connector(g, true) == 0 && (!gbm_any_connected(g) || g->lost)) {
		g->flip_pending = false; /* its event may still come */
		g->events = 0;
		gbm_show(g, bo);
		return 0;
	}
	return -1;
}
