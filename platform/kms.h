/* isoterra — KMS output selection for the GBM backend: which DRM card,
 * which connected connector, which mode and which CRTC drives it. */
#ifndef ISOTERRA_KMS_H
#define ISOTERRA_KMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <xf86drmMode.h>

struct kms_output {
	int fd;                /* the card, read-write; -1 when not open */
	char path[64];         /* e.g. "/dev/dri/card0" */
	uint32_t conn_id, crtc_id;
	int crtc_index;        /* of crtc_id in the card's CRTC list */
	char conn_name[32];    /* e.g. "HDMI-A-1" */
	drmModeModeInfo mode;
	bool connected;        /* at the last kms_output_poll */
	struct hotplug *hotplug; /* the card's hotplug events, or NULL (outputs after the first: NULL) */
	int x, y;              /* its picture's top left in the framebuffer (0, 0 for one output) */
};

/* True when a DRM card with KMS has a connected output. */
bool kms_probe(void);
/* Opens the card (`device`, or the first card with a connected output) and
 * picks its first connected connector, the mode (`mode`: "WxH" or
 * "WxH@Hz"; NULL or "": the connector's preferred mode) and a CRTC that can
 * drive the connector.  0, or -1 with err; o->fd stays open either way when
 * the card could be opened (the caller closes it). */
int kms_output_open(struct kms_output *o, const char *device, const char *mode, char *err, size_t errlen);

/* Several outputs of one card (--outputs): the card as kms_output_open
 * opens it; the connectors `names` ("all": every connected one, at most
 * max; else a comma-separated list of connector names, each connected),
 * one mode size every one of them offers (`mode`; else the first's
 * preferred mode when all offer it, else the first of the first's modes
 * that all offer; each connector its own mode of that size, the first's
 * refresh rate when it has it) and a CRTC each, all different.  *n
 * outputs in o[0..*n); o[0] owns the card's fd and its hotplug events,
 * the others share the fd (only kms_output_close(&o[0])).  0, or -1 with
 * err naming the connector, or listing each one's modes when none is
 * common. */
int kms_outputs_open(struct kms_output *o, int max, int *n, const char *device, const char *names, const char *mode,
                     char *err, size_t errlen);

/* The connector's state now: as the kernel last probed it (no new probe:
 * cheap enough to ask once a second), or probed again (the kernel reads the
 * monitor's EDID) when a hotplug event came for the card (`event`: the
 * caller read them, hotplug_pending) or the connector has just come back.  1 connected with modes, 0 not (or the mode asked for
 * is no longer offered), -1 the card cannot say.  When connected, o->mode
 * is chosen again as kms_output_open does (`mode`, or the preferred one)
 * and *changed says whether it differs from before. */
int kms_output_poll(struct kms_output *o, const char *mode, bool event, bool *changed);
/* Closes the card and stops listening for its hotplug events. */
void kms_output_close(struct kms_output *o);

/* ---- kms_atomic.c: atomic modesetting -------------------------------------- */
struct kms_atomic {
	uint32_t plane_id;  /* the CRTC's primary plane */
	uint32_t mode_blob; /* the mode as a property blob */
	uint32_t conn_crtc_id, crtc_mode_id, crtc_active; /* property ids */
	uint32_t fb_id, crtc_id, src_x, src_y, src_w, src_h, crtc_x, crtc_y, crtc_w, crtc_h;
	/* explicit fencing, 0 where the driver lacks the property: the CRTC's
	 * OUT_FENCE_PTR (a fence that signals when the commit is on screen)
	 * and the plane's IN_FENCE_FD (a fence the flip waits for) */
	uint32_t crtc_out_fence_ptr, plane_in_fence_fd;
	/* the plane's "rotation" property (0: none), the DRM_MODE_ROTATE_*
	 * bits it lists, and the one every frame sets (DRM_MODE_ROTATE_0
	 * unless kms_atomic_try_rotation chose another): with 90 or 270 the
	 * framebuffer is the mode's size turned (portrait on a landscape
	 * mode) */
	uint32_t plane_rotation;
	uint64_t rotations, rotation;
};
/* The atomic client cap, o's CRTC's primary plane, every property id a
 * frame sets and the mode blob; the fence properties when there are.
 * false (why: logged): use legacy. */
bool kms_atomic_init(struct kms_atomic *a, const struct kms_output *o);
/* The plane turns the picture `quarter` quarter turns clockwise onto the
 * output (1..3), when its rotation property lists that turn and a
 * TEST_ONLY modeset with a framebuffer of the turned size passes (drivers
 * list turns that need tiled buffers): then a->rotation is set and true;
 * else false with why (the final pass turns the picture then). */
bool kms_atomic_try_rotation(struct kms_atomic *a, const struct kms_output *o, int quarter, char *why, size_t whylen);
/* The frame with fb on the primary plane at the mode's size; modeset: the
 * connector, the mode and the CRTC's activation too
 * (DRM_MODE_ATOMIC_ALLOW_MODESET).  flags: DRM_MODE_ATOMIC_* and
 * DRM_MODE_PAGE_FLIP_EVENT, whose event carries user.  in_fence: -1, or a
 * sync_file fd the plane waits for before it shows fb (IN_FENCE_FD; needs
 * a->plane_in_fence_fd; the caller still owns and closes it).  out_fence:
 * NULL, or where the kernel puts the fd of a fence that signals when the
 * commit is on screen (OUT_FENCE_PTR; needs a->crtc_out_fence_ptr; not with
 * DRM_MODE_ATOMIC_TEST_ONLY), -1 when the commit failed; the caller closes
 * it.  0, or -1 (errno). */
int kms_atomic_commit(const struct kms_atomic *a, const struct kms_output *o, uint32_t fb, bool modeset,
		      uint32_t flags, void *user, int in_fence, int *out_fence);
/* Several outputs in one commit, each showing its rectangle of fb
 * (o->x, o->y at its mode's size): as kms_atomic_commit for each head h[i]
 * (its own modeset and out-fence), or its CRTC turned off (off: the plane,
 * the connector and the CRTC let go; DRM_MODE_ATOMIC_ALLOW_MODESET).
 * in_fence rides on every plane shown.  0, or -1 (errno). */
struct kms_atomic_head {
	const struct kms_atomic *a;
	const struct kms_output *o;
	bool modeset, off;
	int *out_fence;
};
int kms_atomic_commit_heads(const struct kms_atomic_head *h, int n, uint32_t fb, uint32_t flags, void *user,
                            int in_fence);
/* Waits up to timeout_ms (0: only looks) for a sync_file fence fd to
 * signal.  1 signalled, 0 not yet, -1 error (errno). */
int kms_fence_wait(int fd, int timeout_ms);
/* o->mode changed: its blob made again.  0, or -1 (logged). */
int kms_atomic_set_mode(struct kms_atomic *a, const struct kms_output *o);
void kms_atomic_release(struct kms_atomic *a, int fd);

/* ---- kms_legacy.c: legacy modesetting ---------------------------------------- */
/* drmModeSetCrtc of fb at o's mode; a page flip to fb with its event
 * (carrying user); the CRTC put back as saved (or off when it was off).
 * 0, or the ioctl's non-zero return (errno). */
int kms_legacy_modeset(const struct kms_output *o, uint32_t fb);
/* drmModeSetCrtc with no framebuffer: the CRTC off (an output gone). */
int kms_legacy_off(const struct kms_output *o);
int kms_legacy_flip(const struct kms_output *o, uint32_t fb, void *user);
int kms_legacy_restore(const struct kms_output *o, const drmModeCrtc *saved);

/* ---- hotplug.c: the card's hotplug events ------------------------------- */
struct hotplug;
/* Listens for the kernel's hotplug events of the card open as card_fd;
 * NULL when it cannot (said once) or the build has no libudev. */
struct hotplug *hotplug_open(int card_fd);
/* True when a hotplug event for the card came since the last call (reads
 * them all; never blocks). */
bool hotplug_pending(struct hotplug *h);
void hotplug_close(struct hotplug *h);

#endif
