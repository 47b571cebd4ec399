/* isoterra — legacy modesetting (kms.h): drmModeSetCrtc and
 * drmModePageFlip, for cards or drivers without atomic modesetting (or
 * --kms-legacy); and putting back the CRTC found at start, which both paths
 * do this way.  After kmscube's drm-legacy.c. */
#include "kms.h"

#include <xf86drm.h>
#include <xf86drmMode.h>

int kms_legacy_modeset(const struct kms_output *o, uint32_t fb)
{
	uint32_t conn = o->conn_id;
	drmModeModeInfo mode = o->mode;
	return drmModeSetCrtc(o->fd, o->crtc_id, fb, (uint32_t)o->x, (uint32_t)o->y, &conn, 1, &mode);
}

int kms_legacy_off(const struct kms_output *o)
{
	return drmModeSetCrtc(o->fd, o->crtc_id, 0, 0, 0, NULL, 0, NULL);
}

int kms_legacy_flip(const struct kms_output *o, uint32_t fb, void *user)
{
	return drmModePageFlip(o->fd, o->crtc_id, fb, DRM_MODE_PAGE_FLIP_EVENT, user);
}

int kms_legacy_restore(const struct kms_output *o, const drmModeCrtc *saved)
{
	uint32_t conn = o->conn_id;
	if (saved && saved->mode_valid && saved->buffer_id) {
		drmModeModeInfo mode = saved->mode;
		return drmModeSetCrtc(o->fd, saved->crtc_id, saved->buffer_id, saved->x, saved->y, &conn, 1, &mode);
	}
	return drmModeSetCrtc(o->fd, o->crtc_id, 0, 0, 0, NULL, 0, NULL);
}
