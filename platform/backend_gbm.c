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
 * surface and the renderer follows (the display sink's resize).
 *
 * Several outputs (--outputs, platform.h): one surface as large as their
 * pictures together, rendered once a frame; each CRTC scans out its own
 * rectangle of the same buffer (the plane's SRC_X/SRC_Y; legacy: the
 * CRTC's x, y), side by side along a row or all the same (mirror), at one
 * mode size.  Every flip goes to all of them in one atomic commit (one
 * out-fence or page-flip event per CRTC; legacy: a flip per CRTC).  One
 * output unplugged: said once, its CRTC is turned off and the others go
 * on; back, it is modeset again (at the same size: a connector that no
 * longer offers it stays dark).  All of them unplugged: as for one. */
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
	fb->fd = g->h[0].kms.fd;
	uint32_t w = gbm_bo_get_width(bo), h = gbm_bo_get_height(bo), format = gbm_bo_get_format(bo);
	uint32_t handles[4] = { 0 }, strides[4] = { 0 }, offsets[4] = { 0 };
	int planes = gbm_bo_get_plane_count(bo);
	for (int i = 0; i < planes && i < 4; i++) {
		handles[i] = gbm_bo_get_handle_for_plane(bo, i).u32;
		strides[i] = gbm_bo_get_stride_for_plane(bo, i);
		offsets[i] = gbm_bo_get_offset(bo, i);
	}
	if (drmModeAddFB2(fb->fd, w, h, format, handles, strides, offsets, &fb->fb_id, 0) != 0) {
		int e = errno;
		if (drmModeAddFB(fb->fd, w, h, 24, 32, strides[0], handles[0], &fb->fb_id) != 0) {
			plog_error("gbm: cannot create a %ux%u framebuffer: drmModeAddFB2: %s, drmModeAddFB: %s",
			          w, h, strerror(e), strerror(errno));
			free(fb);
			return 0;
		}
	}
	gbm_bo_set_user_data(bo, fb, fb_destroy);
	return fb->fb_id;
}

static void hide_cursor(struct gbm_head *h)
{
	if (drmModeSetCursor(h->kms.fd, h->kms.crtc_id, 0, 0, 0) != 0)
		plog_debug("gbm: hiding the cursor: %s", strerror(errno));
}

/* An output's picture in the surface: its mode's size, turned back when
 * the plane turns it a quarter (the surface holds the upright picture). */
static void picture_size(const struct gbm_state *g, const drmModeModeInfo *m, int *w, int *h)
{
	bool odd = g->turned & 1;
	*w = odd ? m->vdisplay : m->hdisplay;
	*h = odd ? m->hdisplay : m->vdisplay;
}

/* The outputs' rectangles for the program (platform.h). */
static void publish_outputs(struct gbm_state *g)
{
	struct platform *p = g->p;
	p->n_outputs = g->n;
	for (int i = 0; i < g->n; i++) {
		const struct gbm_head *h = &g->h[i];
		struct platform_output *po = &p->outputs[i];
		snprintf(po->name, sizeof(po->name), "%s", h->kms.conn_name);
		po->x = h->kms.x;
		po->y = h->kms.y;
		picture_size(g, &h->kms.mode, &po->w, &po->h);
		po->on = h->connected && h->modeset_done;
	}
}

/* The connected outputs not scanning out yet are modeset, the others
 * shown fb in the same commit.  Atomic: TEST_ONLY first. */
static int modeset(struct gbm_state *g, uint32_t fb)
{
	(void)gbm_finish_flip(g); /* (none in flight: watch_connector waited for it) */
	struct kms_output *k0 = &g->h[0].kms;
	struct kms_atomic_head ah[PLATFORM_MAX_OUTPUTS];
	int n = 0;
	for (int i = 0; i < g->n; i++)
		if (g->h[i].connected)
			ah[n++] = (struct kms_atomic_head){ .a = &g->h[i].at, .o = &g->h[i].kms,
			                                    .modeset = !g->h[i].modeset_done };
	if (g->atomic) {
		if (kms_atomic_commit_heads(ah, n, fb, DRM_MODE_ATOMIC_TEST_ONLY, g, -1) != 0) {
			plog_debug("gbm: atomic TEST_ONLY commit refused (%s); legacy modesetting", strerror(errno));
			g->atomic = false;
			g->pipelined = false;
			g->in_fences = false;
		} else if (kms_atomic_commit_heads(ah, n, fb, 0, g, -1) != 0) {
			plog_error("gbm: atomic modeset %ux%u on %s: %s", k0->mode.hdisplay, k0->mode.vdisplay, k0->path,
			          strerror(errno));
			return -1;
		}
	}
	for (int i = 0; i < n && !g->atomic; i++)
		if (kms_legacy_modeset(ah[i].o, fb) != 0) {
			plog_error("gbm: drmModeSetCrtc %ux%u on %s%s%s: %s", ah[i].o->mode.hdisplay, ah[i].o->mode.vdisplay,
			          ah[i].o->path, g->n > 1 ? " " : "", g->n > 1 ? ah[i].o->conn_name : "", strerror(errno));
			return -1;
		}
	for (int i = 0; i < g->n; i++) {
		struct gbm_head *h = &g->h[i];
		if (!h->connected)
			continue;
		h->flips++;
		if (h->modeset_done)
			continue;
		hide_cursor(h);
		if (g->n == 1)
			plog_info("gbm: %s %s %ux%u@%u (%s modesetting)", h->kms.path, h->kms.conn_name, h->kms.mode.hdisplay,
			         h->kms.mode.vdisplay, h->kms.mode.vrefresh, g->atomic ? "atomic" : "legacy");
		else
			plog_info("gbm: %s %s %ux%u@%u (%s modesetting), output %d of %d at %d,%d of the %dx%d surface",
			         h->kms.path, h->kms.conn_name, h->kms.mode.hdisplay, h->kms.mode.vdisplay, h->kms.mode.vrefresh,
			         g->atomic ? "atomic" : "legacy", i + 1, g->n, h->kms.x, h->kms.y, g->p->width, g->p->height);
		h->modeset_done = true;
		h->off = false;
	}
	gbm_say_flips(g);
	g->p->shown++;
	publish_outputs(g);
	return 0;
}

/* Several outputs, one gone while others go on: its CRTC off (so that
 * the flips of the others do not carry it), once.  0, or -1 (logged). */
static int output_off(struct gbm_state *g, struct gbm_head *h)
{
	if (h->off || !h->modeset_done)
		return 0;
	int rc;
	if (g->atomic) {
		struct kms_atomic_head ah = { .a = &h->at, .o = &h->kms, .off = true };
		rc = kms_atomic_commit_heads(&ah, 1, 0, 0, g, -1);
	} else {
		rc = kms_legacy_off(&h->kms);
	}
	h->modeset_done = false;
	if (rc != 0) {
		plog_warn("gbm: turning off CRTC %u of %s on %s: %s", h->kms.crtc_id, h->kms.conn_name, h->kms.path,
		         strerror(errno));
		return -1;
	}
	h->off = true;
	return 0;
}

/* A new size: the gbm surface and its EGL window surface made again (the
 * old buffers go with them; the modeset that follows shows a new one).
 * One output only (several keep their size). */
static int remake_surface(struct gbm_state *g)
{
	struct platform *p = g->p;
	struct kms_output *k = &g->h[0].kms;
	int w, h;
	picture_size(g, &k->mode, &w, &h);
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
		plog_error("gbm: gbm_surface_create %dx%d on %s failed", w, h, k->path);
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
	publish_outputs(g);
	return 0;
}

/* The connector's mode changed while it was away: the atomic mode blob and,
 * for a new size (one output), the surface follow. */
static int follow_mode(struct gbm_state *g, struct gbm_head *h)
{
	if (g->atomic && kms_atomic_set_mode(&h->at, &h->kms) < 0)
		return -1;
	int w, ht;
	picture_size(g, &h->kms.mode, &w, &ht);
	if (g->n == 1 && (w != g->p->width || ht != g->p->height))
		return remake_surface(g);
	return 0;
}

/* One output asked (see gbm_watch_connector).  0 or -1. */
static int watch_head(struct gbm_state *g, struct gbm_head *h, bool event)
{
	bool changed = false;
	int st = kms_output_poll(&h->kms, h->want_mode, event, &changed);
	if (st < 0) {
		plog_debug("gbm: connector %u on %s: %s", h->kms.conn_id, h->kms.path, strerror(errno));
		return 0; /* cannot tell: as before */
	}
	if (st == 0) {
		/* the flip in flight, if any, is over (or given up) before the
		 * frames go on unshown */
		(void)gbm_finish_flip(g);
		bool was = h->connected;
		h->connected = false;
		if (!was)
			return 0;
		g->lost = true;
		if (g->n == 1) {
			plog_warn("gbm: %s on %s disconnected%s: frames go on, not shown, until it is back",
			         h->kms.conn_name, h->kms.path, h->want_mode[0] ? " (or no longer offers --mode)" : "");
		} else if (gbm_any_connected(g)) {
			plog_warn("gbm: %s on %s disconnected (or no longer offers the outputs' mode size): its CRTC off, the "
			         "other outputs go on, until it is back", h->kms.conn_name, h->kms.path);
			(void)output_off(g, h);
		} else {
			plog_warn("gbm: %s on %s disconnected (or no longer offers the outputs' mode size), the last output: "
			         "frames go on, not shown, until one is back", h->kms.conn_name, h->kms.path);
		}
		publish_outputs(g);
		return 0;
	}
	if (h->connected && !changed)
		return 0;
	(void)gbm_finish_flip(g); /* before the modeset, and before a new size's surface */
	plog_info("gbm: %s on %s %s: modesetting %ux%u@%u", h->kms.conn_name, h->kms.path,
	         h->connected ? "changed its mode" : "connected again", h->kms.mode.hdisplay, h->kms.mode.vdisplay,
	         h->kms.mode.vrefresh);
	h->connected = true;
	h->modeset_done = false;
	return changed ? follow_mode(g, h) : 0;
}

/* Are the connectors still there (asked once a second, or at once)?  Gone:
 * said once, frames go on unshown (or on the other outputs).  Back, or at
 * another mode: the next present modesets.  0, or -1 when the surface
 * cannot follow a new size. */
int gbm_watch_connector(struct gbm_state *g, bool at_once)
{
	double t = platform_clock_ms();
	g->lost = false;
	if (!at_once && t < g->next_poll)
		return 0;
	g->next_poll = t + CONNECTOR_POLL_MS;
	/* an event (a monitor swapped, a new preferred mode): each probed again */
	bool event = hotplug_pending(g->h[0].kms.hotplug);
	int rc = 0;
	for (int i = 0; i < g->n; i++)
		if (watch_head(g, &g->h[i], event) < 0)
			rc = -1;
	return rc;
}

/* Is an output waiting for its modeset? */
static bool modeset_wanted(const struct gbm_state *g)
{
	for (int i = 0; i < g->n; i++)
		if (g->h[i].connected && !g->h[i].modeset_done)
			return true;
	return false;
}

/* Unplugged: the frame is dropped, at the pace the display had. */
static void drop_frame(struct gbm_state *g, struct gbm_bo *bo)
{
	gbm_surface_release_buffer(g->surf, bo);
	unsigned hz = g->h[0].kms.mode.vrefresh ? g->h[0].kms.mode.vrefresh : 60;
	struct timespec ts = { 0, (long)(1000000000L / hz) };
	while (nanosleep(&ts, &ts) != 0 && errno == EINTR)
		;
}

static int gbm_present(struct platform *p)
{
	struct gbm_state *g = p->priv;
	/* in-fences: the GPU's render fence of this frame, for its flip */
	EGLSyncKHR sync = g->in_fences && gbm_any_connected(g) && !modeset_wanted(g) ? gbm_render_sync(g) : EGL_NO_SYNC_KHR;
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
	if (!gbm_any_connected(g)) {
		gbm_close_fd(&in_fence);
		drop_frame(g, bo);
		return gbm_watch_connector(g, false);
	}
	uint32_t fb = bo_fb(g, bo);
	int rc = fb ? 0 : -1;
	if (rc == 0 && modeset_wanted(g)) {
		rc = modeset(g, fb);
		if (rc < 0 && gbm_watch_connector(g, true) == 0 && (!gbm_any_connected(g) || g->lost))
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

/* Put back the CRTCs we found (the console's framebuffer and mode), or
 * turn a CRTC off when it was off. */
static void restore_crtc(struct gbm_state *g)
{
	bool any = false;
	for (int i = 0; i < g->n; i++)
		any = any || g->h[i].modeset_done || g->h[i].off;
	if (g->restore_done || !any)
		return;
	g->restore_done = true;
	if (g->flip_pending)
		(void)gbm_wait_flip(g);
	if (g->pipelined) {
		(void)gbm_finish_flip(g);
		plog_info("kms: no flip in flight when the CRTC%s restored: %lu of %lu frames shown",
		          g->n > 1 ? "s were" : " was", g->p->shown, g->p->presented);
	}
	if (g->n > 1) {
		char line[256];
		size_t len = 0;
		for (int i = 0; i < g->n && len < sizeof(line); i++) {
			int k = snprintf(line + len, sizeof(line) - len, "%s%s %lu", i ? ", " : "", g->h[i].kms.conn_name,
			                 g->h[i].flips);
			if (k < 0)
				break;
			len += (size_t)k;
		}
		plog_info("gbm: frames each output's CRTC confirmed: %s", line);
	}
	for (int i = 0; i < g->n; i++) {
		struct gbm_head *h = &g->h[i];
		drmModeCrtc *s = h->saved;
		/* a turned plane keeps its turn through a legacy modeset: first
		 * the CRTC off with the plane's rotation at 0 */
		if (g->atomic && h->at.rotation != DRM_MODE_ROTATE_0) {
			struct kms_atomic_head ah = { .a = &h->at, .o = &h->kms, .off = true };
			if (kms_atomic_commit_heads(&ah, 1, 0, 0, g, -1) != 0)
				plog_warn("gbm: turning the plane back on %s: %s", h->kms.path, strerror(errno));
			h->at.rotation = DRM_MODE_ROTATE_0;
		}
		if (kms_legacy_restore(&h->kms, s) != 0)
			plog_warn("gbm: restoring CRTC %u on %s: %s", h->kms.crtc_id, h->kms.path, strerror(errno));
		else
			plog_debug("gbm: CRTC %u restored (fb %u)", h->kms.crtc_id, s ? s->buffer_id : 0);
	}
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
	for (int i = 0; i < PLATFORM_MAX_OUTPUTS; i++)
		gbm_close_fd(&g->h[i].fence);
	if (g->front)
		gbm_surface_release_buffer(g->surf, g->front);
	if (g->surf)
		gbm_surface_destroy(g->surf); /* frees the bos: fb_destroy removes the FBs */
	if (g->gbm)
		gbm_device_destroy(g->gbm);
	for (int i = 0; i < g->n; i++) {
		kms_atomic_release(&g->h[i].at, g->h[0].kms.fd);
		if (g->h[i].saved)
			drmModeFreeCrtc(g->h[i].saved);
	}
	kms_output_close(&g->h[0].kms);
	free(g);
	p->priv = NULL;
}

/* Several outputs: the layout (a row with the gaps between, or one
 * picture each), the surface's size.  One output: the whole surface. */
static void lay_out(struct gbm_state *g, const struct platform_options *opt)
{
	int w, h; /* (turned only with one output: then x is 0) */
	picture_size(g, &g->h[0].kms.mode, &w, &h);
	float gap = (float)opt->outputs_gap + (float)opt->outputs_gap_per_w * (float)w;
	for (int i = 0; i < g->n; i++) {
		/* rounded as the wall's frame width is (wall.h: lroundf, gap >= 0) */
		g->h[i].kms.x = g->mirror ? 0 : i * w + (int)((float)i * gap + 0.5f);
		g->h[i].kms.y = 0;
	}
	g->p->width = g->h[g->n - 1].kms.x + w;
	g->p->height = h;
}

/* --rotate on one output: the plane's rotation property where the driver
 * offers the turn, else the program's final pass (said once either way). */
static void choose_turn(struct gbm_state *g, const struct platform_options *opt)
{
	int q = opt->rotate & 3;
	if (!q)
		return;
	char why[160] = "";
	if (g->n > 1)
		snprintf(why, sizeof(why), "several outputs");
	else if (!g->atomic)
		snprintf(why, sizeof(why), "legacy modesetting");
	else if (kms_atomic_try_rotation(&g->h[0].at, &g->h[0].kms, q, why, sizeof(why)))
		g->turned = q;
	g->p->rotated = g->turned;
	if (g->turned)
		plog_info("kms: the plane turns the picture %d degrees (its rotation property)", 90 * q);
	else
		plog_info("kms: --rotate %d: the program's final pass turns the picture (%s)", 90 * q, why);
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
	for (int i = 0; i < PLATFORM_MAX_OUTPUTS; i++) {
		g->h[i].kms.fd = -1;
		g->h[i].fence = -1;
	}
	g->p = p;
	p->priv = g;
	g->next_poll = platform_clock_ms() + CONNECTOR_POLL_MS;
	if (opt->mode && strlen(opt->mode) >= sizeof(g->h[0].want_mode)) {
		snprintf(err, errlen, "--mode '%.40s...' is not WxH or WxH@Hz", opt->mode);
		goto fail;
	}
	bool several = opt->outputs && opt->outputs[0];
	if (!several) {
		if (kms_output_open(&g->h[0].kms, opt->drm_device, opt->mode, err, errlen) < 0)
			goto fail;
		g->n = 1;
		snprintf(g->h[0].want_mode, sizeof(g->h[0].want_mode), "%s", opt->mode ? opt->mode : "");
	} else {
		struct kms_output ko[PLATFORM_MAX_OUTPUTS];
		memset(ko, 0, sizeof(ko));
		ko[0].fd = -1;
		int rc = kms_outputs_open(ko, PLATFORM_MAX_OUTPUTS, &g->n, opt->drm_device, opt->outputs, opt->mode, err,
		                          errlen);
		g->h[0].kms = ko[0]; /* (the card's fd, closed with it) */
		for (int i = 1; i < g->n; i++)
			g->h[i].kms = ko[i];
		if (rc < 0)
			goto fail;
		g->mirror = opt->outputs_mirror;
		/* each output comes back only at the size they share */
		for (int i = 0; i < g->n; i++) {
			if (opt->mode && opt->mode[0])
				snprintf(g->h[i].want_mode, sizeof(g->h[i].want_mode), "%s", opt->mode);
			else
				snprintf(g->h[i].want_mode, sizeof(g->h[i].want_mode), "%ux%u", g->h[i].kms.mode.hdisplay,
				         g->h[i].kms.mode.vdisplay);
		}
	}
	for (int i = 0; i < g->n; i++)
		g->h[i].connected = true;
	struct kms_output *k0 = &g->h[0].kms;
	if (!egl_common_has_ext(cexts, "EGL_KHR_platform_gbm") && !egl_common_has_ext(cexts, "EGL_MESA_platform_gbm")) {
		snprintf(err, errlen, "EGL_KHR_platform_gbm not supported by this EGL");
		goto fail;
	}
	if (!drmIsMaster(k0->fd) && drmSetMaster(k0->fd) != 0) {
		snprintf(err, errlen, "%s: cannot become DRM master (%s): another program (a compositor, "
		         "an X server) drives the display", k0->path, strerror(errno));
		goto fail;
	}
	g->atomic = !opt->kms_legacy;
	for (int i = 0; i < g->n; i++) {
		struct gbm_head *h = &g->h[i];
		h->saved = drmModeGetCrtc(h->kms.fd, h->kms.crtc_id);
		if (!h->saved)
			plog_warn("gbm: cannot read CRTC %u (%s); it will be turned off on exit", h->kms.crtc_id,
			         strerror(errno));
		g->atomic = g->atomic && kms_atomic_init(&h->at, &h->kms);
		for (int k = 0; k < i && g->atomic; k++)
			if (g->h[k].at.plane_id == h->at.plane_id) {
				plog_debug("gbm: %s and %s share primary plane %u; legacy", g->h[k].kms.conn_name,
				          h->kms.conn_name, h->at.plane_id);
				g->atomic = false;
			}
	}

	g->gbm = gbm_create_device(k0->fd);
	if (!g->gbm) {
		snprintf(err, errlen, "gbm_create_device(%s) failed", k0->path);
		goto fail;
	}
	choose_turn(g, opt);
	lay_out(g, opt);
	g->surf = gbm_surface_create(g->gbm, (uint32_t)p->width, (uint32_t)p->height, GBM_FORMAT_XRGB8888,
	                             GBM_BO_USE_SCANOUT | GBM_BO_USE_RENDERING);
	if (!g->surf) {
		snprintf(err, errlen, "gbm_surface_create %dx%d XRGB8888 on %s failed", p->width, p->height,
		         k0->path);
		goto fail;
	}
	if (egl_common_open_display(p, EGL_PLATFORM_GBM_KHR, g->gbm, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, GBM_FORMAT_XRGB8888, NULL, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, GBM_FORMAT_XRGB8888, g->surf, err, errlen) < 0)
		goto fail;
	size_t len = strlen(p->device_desc);
	if (len + strlen(k0->path) + 4 < sizeof(p->device_desc))
		snprintf(p->device_desc + len, sizeof(p->device_desc) - len, " (%s)", k0->path);
	for (int i = 0; i < g->n; i++)
		plog_debug("gbm: %s connector %s, mode %ux%u@%u, CRTC %u, %s", g->h[i].kms.path, g->h[i].kms.conn_name,
		          g->h[i].kms.mode.hdisplay, g->h[i].kms.mode.vdisplay, g->h[i].kms.mode.vrefresh,
		          g->h[i].kms.crtc_id, g->atomic ? "atomic" : "legacy");
	if (g->n > 1)
		plog_info("gbm: %d outputs on %s, %s, %dx%d each: one %dx%d surface", g->n, k0->path,
		         g->mirror ? "mirrored" : "side by side", k0->mode.hdisplay, k0->mode.vdisplay, p->width, p->height);
	p->refresh_hz = k0->mode.vrefresh;
	publish_outputs(g);
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
