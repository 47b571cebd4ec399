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
	struct hotplug *hotplug; /* the card's hotplug events, or NULL */
};

/* True when a DRM card with KMS has a connected output. */
bool kms_probe(void);
/* Opens the card (`device`, or the first card with a connected output) and
 * picks its first connected connector, the mode (`mode`: "WxH" or
 * "WxH@Hz"; NULL or "": the connector's preferred mode) and a CRTC that can
 * drive the connector.  0, or -1 with err; o->fd stays open either way when
 * the card could be opened (the caller closes it). */
int kms_output_open(struct kms_output *o, const char *device, const char *mode, char *err, size_t errlen);

/* The connector's state now: as the kernel last probed it (no new probe:
 * cheap enough to ask once a second), or probed again (the kernel reads the
 * monitor's EDID) when a hotplug event came for the card or the connector
 * has just come back.  1 connected with modes, 0 not (or the mode asked for
 * is no longer offered), -1 the card cannot say.  When connected, o->mode
 * is chosen again as kms_output_open does (`mode`, or the preferred one)
 * and *changed says whether it differs from before. */
int kms_output_poll(struct kms_output *o, const char *mode, bool *changed);
/* Closes the card and stops listening for its hotplug events. */
void kms_output_close(struct kms_output *o);

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
