/* isoterra — --probe: the DRM cards in /dev/dri, their connectors (connected
 * or not, the modes) and whether DRM master can be taken (drmSetMaster, then
 * dropped at once), as platform_probe.h describes. */
#include "platform_probe.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <xf86drm.h>
#include <xf86drmMode.h>

static void card_connectors(int fd, drmModeRes *res, struct probe_drm_card *c)
{
	for (int i = 0; i < res->count_connectors && c->nconn < PROBE_MAX_CONNECTORS; i++) {
		drmModeConnector *k = drmModeGetConnector(fd, res->connectors[i]);
		if (!k)
			continue;
		struct probe_drm_connector *o = &c->conn[c->nconn++];
		o->id = k->connector_id;
		const char *type = drmModeGetConnectorTypeName(k->connector_type);
		snprintf(o->name, sizeof(o->name), "%s-%u", type ? type : "Unknown", k->connector_type_id);
		o->connected = k->connection == DRM_MODE_CONNECTED;
		o->nmodes = k->count_modes;
		for (int m = 0; m < k->count_modes && m < PROBE_MAX_MODES; m++) {
			const drmModeModeInfo *mi = &k->modes[m];
			snprintf(o->modes[m], sizeof(o->modes[m]), "%ux%u@%u%s", mi->hdisplay, mi->vdisplay,
				 mi->vrefresh, (mi->type & DRM_MODE_TYPE_PREFERRED) ? " preferred" : "");
		}
		drmModeFreeConnector(k);
	}
}

static void probe_card(const char *path, struct probe_drm_card *c)
{
	snprintf(c->path, sizeof(c->path), "%s", path);
	int fd = open(path, O_RDWR | O_CLOEXEC);
	if (fd < 0) {
		snprintf(c->err, sizeof(c->err), "cannot open: %s", strerror(errno));
		return;
	}
	drmVersionPtr v = drmGetVersion(fd);
	if (v) {
		snprintf(c->driver, sizeof(c->driver), "%s", v->name ? v->name : "");
		drmFreeVersion(v);
	}
	drmModeRes *res = drmModeGetResources(fd);
	if (res) {
		c->kms = true;
		card_connectors(fd, res, c);
		drmModeFreeResources(res);
	} else {
		snprintf(c->err, sizeof(c->err), "no KMS (drmModeGetResources failed: %s)", strerror(errno));
	}
	if (drmSetMaster(fd) == 0) {
		c->master = true;
		drmDropMaster(fd);
	} else {
		int e = errno;
		snprintf(c->master_err, sizeof(c->master_err), "drmSetMaster: %s%s", strerror(e),
			 e == EBUSY || e == EINVAL || e == EACCES || e == EPERM
				 ? " (another program, a compositor or a console, holds the display)" : "");
	}
	close(fd);
}

void platform_probe_drm(struct probe_drm *out)
{
	memset(out, 0, sizeof(*out));
	out->built = true;
	for (int i = 0; i < 64 && out->ncards < PROBE_MAX_CARDS; i++) {
		char path[64];
		snprintf(path, sizeof(path), "%s/card%d", DRM_DIR_NAME, i);
		if (access(path, F_OK) != 0)
			continue;
		probe_card(path, &out->card[out->ncards++]);
	}
}
