/* isoterra — display hotplug events for the KMS output: the kernel's
 * uevents (libudev, the "kernel" netlink group, so no udev daemon is
 * needed) for the DRM card in use.  When one arrives, kms.c asks the kernel
 * to probe the connector again (drmModeGetConnector): that is how a new
 * monitor's modes, or a new preferred mode, become known.  Without
 * libudev, the connector is probed again only when it comes back from
 * disconnected.  See kms.h. */
#include "kms.h"
#include "platform_util.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifdef ISOTERRA_HAVE_LIBUDEV
#include <libudev.h>

struct hotplug {
	struct udev *udev;
	struct udev_monitor *mon;
	dev_t card;
};

struct hotplug *hotplug_open(int card_fd)
{
	struct stat st;
	if (fstat(card_fd, &st) != 0) {
		plog_debug("hotplug: fstat of the card failed: no hotplug events");
		return NULL;
	}
	struct hotplug *h = calloc(1, sizeof(*h));
	if (!h)
		return NULL;
	h->card = st.st_rdev;
	h->udev = udev_new();
	h->mon = h->udev ? udev_monitor_new_from_netlink(h->udev, "kernel") : NULL;
	if (!h->mon || udev_monitor_filter_add_match_subsystem_devtype(h->mon, "drm", NULL) < 0 ||
	    udev_monitor_enable_receiving(h->mon) < 0) {
		plog_warn("gbm: cannot listen for display hotplug events (netlink uevents): a new monitor's modes are "
		         "learnt only when it comes back from unplugged");
		hotplug_close(h);
		return NULL;
	}
	return h;
}

bool hotplug_pending(struct hotplug *h)
{
	if (!h)
		return false;
	bool hit = false;
	/* the monitor's socket is non-blocking: read every event queued */
	struct udev_device *d;
	while ((d = udev_monitor_receive_device(h->mon)) != NULL) {
		const char *sub = udev_device_get_subsystem(d);
		const char *hp = udev_device_get_property_value(d, "HOTPLUG");
		if (sub && !strcmp(sub, "drm") && hp && !strcmp(hp, "1") && udev_device_get_devnum(d) == h->card)
			hit = true;
		udev_device_unref(d);
	}
	return hit;
}

void hotplug_close(struct hotplug *h)
{
	if (!h)
		return;
	if (h->mon)
		udev_monitor_unref(h->mon);
	if (h->udev)
		udev_unref(h->udev);
	free(h);
}

#else

struct hotplug *hotplug_open(int card_fd)
{
	(void)card_fd;
	plog_debug("gbm: built without libudev: a new monitor's modes are learnt when it comes back from unplugged");
	return NULL;
}

bool hotplug_pending(struct hotplug *h)
{
	(void)h;
	return false;
}

void hotplug_close(struct hotplug *h)
{
	(void)h;
}

#endif
