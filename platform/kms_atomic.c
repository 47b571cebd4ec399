/* isoterra — atomic modesetting (kms.h): the CRTC's primary plane and the
 * property ids a frame sets, the mode as a property blob, and the commit of
 * a whole frame (with the connector and the mode when it modesets), with
 * the fences of explicit fencing when asked (OUT_FENCE_PTR, IN_FENCE_FD).
 * After kmscube's drm-atomic.c; the legacy path is kms_legacy.c. */
#include "kms.h"
#include "platform_util.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include <drm_fourcc.h>
#include <xf86drm.h>
#include <xf86drmMode.h>

static uint32_t prop_id(int fd, uint32_t obj, uint32_t type, const char *name, uint64_t *value)
{
	drmModeObjectProperties *props = drmModeObjectGetProperties(fd, obj, type);
	uint32_t id = 0;
	if (!props)
		return 0;
	for (uint32_t i = 0; i < props->count_props && !id; i++) {
		drmModePropertyRes *pr = drmModeGetProperty(fd, props->props[i]);
		if (!pr)
			continue;
		if (strcmp(pr->name, name) == 0) {
			id = pr->prop_id;
			if (value)
				*value = props->prop_values[i];
		}
		drmModeFreeProperty(pr);
	}
	drmModeFreeObjectProperties(props);
	return id;
}

/* The DRM_MODE_ROTATE_* and DRM_MODE_REFLECT_* bits a bitmask property
 * lists (each enum entry's value is its bit's index). */
static uint64_t plane_rotations(int fd, uint32_t prop)
{
	drmModePropertyRes *pr = drmModeGetProperty(fd, prop);
	uint64_t bits = 0;
	if (!pr)
		return 0;
	if (pr->flags & DRM_MODE_PROP_BITMASK)
		for (int i = 0; i < pr->count_enums; i++)
			if (pr->enums[i].value < 64)
				bits |= 1ull << pr->enums[i].value;
	drmModeFreeProperty(pr);
	return bits;
}

static uint32_t find_primary_plane(const struct kms_output *o)
{
	drmModePlaneRes *pr = drmModeGetPlaneResources(o->fd);
	uint32_t found = 0;
	if (!pr)
		return 0;
	for (uint32_t i = 0; i < pr->count_planes && !found; i++) {
		drmModePlane *pl = drmModeGetPlane(o->fd, pr->planes[i]);
		if (!pl)
			continue;
		uint64_t type = 0;
		if ((pl->possible_crtcs & (1u << o->crtc_index)) &&
		    prop_id(o->fd, pl->plane_id, DRM_MODE_OBJECT_PLANE, "type", &type) &&
		    type == DRM_PLANE_TYPE_PRIMARY)
			found = pl->plane_id;
		drmModeFreePlane(pl);
	}
	drmModeFreePlaneResources(pr);
	return found;
}

bool kms_atomic_init(struct kms_atomic *a, const struct kms_output *o)
{
	if (drmSetClientCap(o->fd, DRM_CLIENT_CAP_UNIVERSAL_PLANES, 1) != 0 ||
	    drmSetClientCap(o->fd, DRM_CLIENT_CAP_ATOMIC, 1) != 0) {
		plog_debug("gbm: no atomic modesetting on %s (%s); legacy", o->path, strerror(errno));
		return false;
	}
	a->plane_id = find_primary_plane(o);
	if (!a->plane_id) {
		plog_debug("gbm: no primary plane for CRTC %u; legacy", o->crtc_id);
		return false;
	}
	struct kms_atomic *pp = a;
	struct {
		uint32_t *id;
		uint32_t obj, type;
		const char *name;
	} want[] = {
		{ &pp->conn_crtc_id, o->conn_id, DRM_MODE_OBJECT_CONNECTOR, "CRTC_ID" },
		{ &pp->crtc_mode_id, o->crtc_id, DRM_MODE_OBJECT_CRTC, "MODE_ID" },
		{ &pp->crtc_active, o->crtc_id, DRM_MODE_OBJECT_CRTC, "ACTIVE" },
		{ &pp->fb_id, a->plane_id, DRM_MODE_OBJECT_PLANE, "FB_ID" },
		{ &pp->crtc_id, a->plane_id, DRM_MODE_OBJECT_PLANE, "CRTC_ID" },
		{ &pp->src_x, a->plane_id, DRM_MODE_OBJECT_PLANE, "SRC_X" },
		{ &pp->src_y, a->plane_id, DRM_MODE_OBJECT_PLANE, "SRC_Y" },
		{ &pp->src_w, a->plane_id, DRM_MODE_OBJECT_PLANE, "SRC_W" },
		{ &pp->src_h, a->plane_id, DRM_MODE_OBJECT_PLANE, "SRC_H" },
		{ &pp->crtc_x, a->plane_id, DRM_MODE_OBJECT_PLANE, "CRTC_X" },
		{ &pp->crtc_y, a->plane_id, DRM_MODE_OBJECT_PLANE, "CRTC_Y" },
		{ &pp->crtc_w, a->plane_id, DRM_MODE_OBJECT_PLANE, "CRTC_W" },
		{ &pp->crtc_h, a->plane_id, DRM_MODE_OBJECT_PLANE, "CRTC_H" },
	};
	for (size_t i = 0; i < ARRAY_SIZE(want); i++) {
		*want[i].id = prop_id(o->fd, want[i].obj, want[i].type, want[i].name, NULL);
		if (!*want[i].id) {
			plog_debug("gbm: property %s missing on object %u; legacy", want[i].name, want[i].obj);
			return false;
		}
	}
	/* explicit fencing: optional (the flips wait for their events without) */
	a->crtc_out_fence_ptr = prop_id(o->fd, o->crtc_id, DRM_MODE_OBJECT_CRTC, "OUT_FENCE_PTR", NULL);
	a->plane_in_fence_fd = prop_id(o->fd, a->plane_id, DRM_MODE_OBJECT_PLANE, "IN_FENCE_FD", NULL);
	/* rotation: optional; set on every frame where it exists, so a turn
	 * left by the display's last master does not stay */
	a->plane_rotation = prop_id(o->fd, a->plane_id, DRM_MODE_OBJECT_PLANE, "rotation", NULL);
	a->rotations = a->plane_rotation ? plane_rotations(o->fd, a->plane_rotation) : 0;
	a->rotation = DRM_MODE_ROTATE_0;
	if (drmModeCreatePropertyBlob(o->fd, &o->mode, sizeof(o->mode), &a->mode_blob) != 0) {
		plog_debug("gbm: drmModeCreatePropertyBlob: %s; legacy", strerror(errno));
		return false;
	}
	return true;
}

/* One head's properties: its frame (the plane showing its rectangle of
 * fb; with modeset the connector, mode and activation too), or its CRTC
 * off.  false when the request could not grow. */
static bool add_head(drmModeAtomicReq *req, const struct kms_atomic_head *h, uint32_t fb, int in_fence)
{
	const struct kms_atomic *pp = h->a;
	const struct kms_output *o = h->o;
	int ok = 1;
	if (h->off) {
		ok &= drmModeAtomicAddProperty(req, o->conn_id, pp->conn_crtc_id, 0) > 0;
		ok &= drmModeAtomicAddProperty(req, o->crtc_id, pp->crtc_mode_id, 0) > 0;
		ok &= drmModeAtomicAddProperty(req, o->crtc_id, pp->crtc_active, 0) > 0;
		ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->fb_id, 0) > 0;
		ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->crtc_id, 0) > 0;
		if (pp->plane_rotation)
			ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->plane_rotation, DRM_MODE_ROTATE_0) > 0;
		return ok;
	}
	uint32_t w = o->mode.hdisplay, h_ = o->mode.vdisplay;
	/* turned by 90 or 270 degrees: the framebuffer's rectangle is the
	 * mode's turned */
	bool odd = pp->rotation & (DRM_MODE_ROTATE_90 | DRM_MODE_ROTATE_270);
	uint32_t sw = odd ? h_ : w, sh = odd ? w : h_;
	if (h->modeset) {
		ok &= drmModeAtomicAddProperty(req, o->conn_id, pp->conn_crtc_id, o->crtc_id) > 0;
		ok &= drmModeAtomicAddProperty(req, o->crtc_id, pp->crtc_mode_id, pp->mode_blob) > 0;
		ok &= drmModeAtomicAddProperty(req, o->crtc_id, pp->crtc_active, 1) > 0;
	}
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->fb_id, fb) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->crtc_id, o->crtc_id) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->src_x, (uint64_t)o->x << 16) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->src_y, (uint64_t)o->y << 16) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->src_w, (uint64_t)sw << 16) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->src_h, (uint64_t)sh << 16) > 0;
	if (pp->plane_rotation)
		ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->plane_rotation, pp->rotation) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->crtc_x, 0) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->crtc_y, 0) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->crtc_w, w) > 0;
	ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->crtc_h, h_) > 0;
	if (in_fence >= 0)
		ok &= drmModeAtomicAddProperty(req, pp->plane_id, pp->plane_in_fence_fd, (uint64_t)in_fence) > 0;
	if (h->out_fence)
		ok &= drmModeAtomicAddProperty(req, o->crtc_id, pp->crtc_out_fence_ptr,
					       (uint64_t)(uintptr_t)h->out_fence) > 0;
	return ok;
}

int kms_atomic_commit_heads(const struct kms_atomic_head *h, int n, uint32_t fb, uint32_t flags, void *user,
                            int in_fence)
{
	/* the kernel writes each fence's fd (an int) where the property points */
	for (int i = 0; i < n; i++) {
		if (h[i].out_fence)
			*h[i].out_fence = -1;
		if ((h[i].out_fence && (!h[i].a->crtc_out_fence_ptr || (flags & DRM_MODE_ATOMIC_TEST_ONLY))) ||
		    (in_fence >= 0 && !h[i].off && !h[i].a->plane_in_fence_fd)) {
			errno = EINVAL;
			return -1;
		}
	}
	drmModeAtomicReq *req = drmModeAtomicAlloc();
	if (!req) {
		errno = ENOMEM;
		return -1;
	}
	bool ok = true;
	for (int i = 0; i < n; i++) {
		ok = ok && add_head(req, &h[i], fb, in_fence);
		if (h[i].modeset || h[i].off)
			flags |= DRM_MODE_ATOMIC_ALLOW_MODESET;
	}
	int rc;
	if (!ok) {
		errno = ENOMEM;
		rc = -1;
	} else {
		rc = drmModeAtomicCommit(h[0].o->fd, req, flags, user);
	}
	drmModeAtomicFree(req);
	if (rc != 0) {
		/* (the kernel installs none when the commit fails) */
		int e = errno;
		for (int i = 0; i < n; i++)
			if (h[i].out_fence && *h[i].out_fence >= 0) {
				close(*h[i].out_fence);
				*h[i].out_fence = -1;
			}
		errno = e;
	}
	return rc;
}

int kms_atomic_commit(const struct kms_atomic *a, const struct kms_output *o, uint32_t fb, bool modeset,
		      uint32_t flags, void *user, int in_fence, int *out_fence)
{
	struct kms_atomic_head h = { .a = a, .o = o, .modeset = modeset, .out_fence = out_fence };
	return kms_atomic_commit_heads(&h, 1, fb, flags, user, in_fence);
}

bool kms_atomic_try_rotation(struct kms_atomic *a, const struct kms_output *o, int quarter, char *why, size_t whylen)
{
	/* DRM turns counter-clockwise: a quarter turn clockwise is its 270 */
	static const uint64_t bit[4] = { DRM_MODE_ROTATE_0, DRM_MODE_ROTATE_270, DRM_MODE_ROTATE_180, DRM_MODE_ROTATE_90 };
	static const char *const name[4] = { "rotate-0", "rotate-270", "rotate-180", "rotate-90" };
	quarter &= 3;
	if (!a->plane_rotation) {
		snprintf(why, whylen, "plane %u has no rotation property", a->plane_id);
		return false;
	}
	if (!(a->rotations & bit[quarter])) {
		snprintf(why, whylen, "plane %u's rotation property lacks %s", a->plane_id, name[quarter]);
		return false;
	}
	/* a linear framebuffer of the turned size, for a TEST_ONLY modeset */
	bool odd = quarter & 1;
	uint32_t w = odd ? o->mode.vdisplay : o->mode.hdisplay, h = odd ? o->mode.hdisplay : o->mode.vdisplay;
	struct drm_mode_create_dumb cd = { .width = w, .height = h, .bpp = 32 };
	if (drmIoctl(o->fd, DRM_IOCTL_MODE_CREATE_DUMB, &cd) != 0) {
		snprintf(why, whylen, "a %ux%u test buffer: %s", w, h, strerror(errno));
		return false;
	}
	uint32_t handles[4] = { cd.handle }, pitches[4] = { cd.pitch }, offsets[4] = { 0 }, fb = 0;
	bool ok = false;
	if (drmModeAddFB2(o->fd, w, h, DRM_FORMAT_XRGB8888, handles, pitches, offsets, &fb, 0) != 0) {
		snprintf(why, whylen, "a %ux%u test framebuffer: %s", w, h, strerror(errno));
	} else {
		uint64_t was = a->rotation;
		a->rotation = bit[quarter];
		struct kms_atomic_head hd = { .a = a, .o = o, .modeset = true };
		ok = kms_atomic_commit_heads(&hd, 1, fb, DRM_MODE_ATOMIC_TEST_ONLY, NULL, -1) == 0;
		if (!ok) {
			snprintf(why, whylen, "plane %u refused %s for a %ux%u linear buffer (%s)", a->plane_id,
			         name[quarter], w, h, strerror(errno));
			a->rotation = was;
		}
		if (drmModeRmFB(o->fd, fb) != 0)
			plog_debug("gbm: drmModeRmFB of the test buffer: %s", strerror(errno));
	}
	struct drm_mode_destroy_dumb dd = { .handle = cd.handle };
	if (drmIoctl(o->fd, DRM_IOCTL_MODE_DESTROY_DUMB, &dd) != 0)
		plog_debug("gbm: destroying the test buffer: %s", strerror(errno));
	return ok;
}

int kms_fence_wait(int fd, int timeout_ms)
{
	double end = platform_clock_ms() + timeout_ms;
	for (;;) {
		struct pollfd pfd = { .fd = fd, .events = POLLIN };
		int n = poll(&pfd, 1, timeout_ms);
		if (n > 0) {
			if (pfd.revents & (POLLERR | POLLNVAL)) {
				errno = EINVAL;
				return -1;
			}
			return 1;
		}
		if (n == 0)
			return 0;
		if (errno != EINTR)
			return -1;
		/* a signal: on with the time left */
		double left = end - platform_clock_ms();
		timeout_ms = left > 0 ? (int)left : 0;
	}
}

int kms_atomic_set_mode(struct kms_atomic *a, const struct kms_output *o)
{
	if (a->mode_blob && drmModeDestroyPropertyBlob(o->fd, a->mode_blob) != 0)
		plog_debug("gbm: drmModeDestroyPropertyBlob: %s", strerror(errno));
	a->mode_blob = 0;
	if (drmModeCreatePropertyBlob(o->fd, &o->mode, sizeof(o->mode), &a->mode_blob) != 0) {
		plog_error("gbm: drmModeCreatePropertyBlob: %s", strerror(errno));
		return -1;
	}
	return 0;
}

void kms_atomic_release(struct kms_atomic *a, int fd)
{
	if (a->mode_blob && drmModeDestroyPropertyBlob(fd, a->mode_blob) != 0)
		plog_debug("gbm: drmModeDestroyPropertyBlob: %s", strerror(errno));
	a->mode_blob = 0;
}
