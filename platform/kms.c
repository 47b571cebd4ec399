/* isoterra — KMS output selection: the DRM card (given, or the first with a
 * connected output), its first connected connector, the mode (asked for,
 * or the preferred one) and a CRTC that can drive the connector: the one
 * its encoder uses, else the first its encoders can use; later, whether
 * that connector is still connected and which mode it wants now.  See
 * kms.h. */
#include "kms.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <xf86drm.h>

#define MAX_CARDS 16

static const char *conn_type_name(uint32_t type)
{
	switch (type) {
	case DRM_MODE_CONNECTOR_VGA: return "VGA";
	case DRM_MODE_CONNECTOR_DVII: return "DVI-I";
	case DRM_MODE_CONNECTOR_DVID: return "DVI-D";
	case DRM_MODE_CONNECTOR_DVIA: return "DVI-A";
	case DRM_MODE_CONNECTOR_Composite: return "Composite";
	case DRM_MODE_CONNECTOR_LVDS: return "LVDS";
	case DRM_MODE_CONNECTOR_Component: return "Component";
	case DRM_MODE_CONNECTOR_DisplayPort: return "DP";
	case DRM_MODE_CONNECTOR_HDMIA: return "HDMI-A";
	case DRM_MODE_CONNECTOR_HDMIB: return "HDMI-B";
	case DRM_MODE_CONNECTOR_TV: return "TV";
	case DRM_MODE_CONNECTOR_eDP: return "eDP";
	case DRM_MODE_CONNECTOR_VIRTUAL: return "Virtual";
	case DRM_MODE_CONNECTOR_DSI: return "DSI";
	case DRM_MODE_CONNECTOR_DPI: return "DPI";
	default: return "Unknown";
	}
}

/* The first connected connector with modes, or NULL. */
static drmModeConnector *find_connector(int fd, drmModeRes *res)
{
	for (int i = 0; i < res->count_connectors; i++) {
		drmModeConnector *c = drmModeGetConnector(fd, res->connectors[i]);
		if (!c)
			continue;
		if (c->connection == DRM_MODE_CONNECTED && c->count_modes > 0)
			return c;
		drmModeFreeConnector(c);
	}
	return NULL;
}

/* 1: the card has KMS and a connected output, 0: no connected output,
 * -1: not a KMS device (or cannot be opened). */
static int card_state(const char *path, int *fd_out)
{
	int fd = open(path, O_RDWR | O_CLOEXEC);
	if (fd < 0)
		return -1;
	drmModeRes *res = drmModeGetResources(fd);
	if (!res) {
		close(fd);
		return -1;
	}
	drmModeConnector *c = find_connector(fd, res);
	int rc = c ? 1 : 0;
	drmModeFreeConnector(c);
	drmModeFreeResources(res);
	if (fd_out && rc == 1)
		*fd_out = fd;
	else
		close(fd);
	return rc;
}

bool kms_probe(void)
{
	char path[64];
	for (int i = 0; i < MAX_CARDS; i++) {
		snprintf(path, sizeof(path), "%s/card%d", DRM_DIR_NAME, i);
		if (card_state(path, NULL) == 1)
			return true;
	}
	return false;
}

static int open_card(struct kms_output *o, const char *want, char *err, size_t errlen)
{
	if (want && want[0]) {
		snprintf(o->path, sizeof(o->path), "%s", want);
		int fd = open(want, O_RDWR | O_CLOEXEC);
		if (fd < 0) {
			snprintf(err, errlen, "cannot open %s: %s", want, strerror(errno));
			return -1;
		}
		close(fd);
		int st = card_state(want, &o->fd);
		if (st < 0) {
			snprintf(err, errlen, "%s is not a KMS display device (drmModeGetResources failed)", want);
			return -1;
		}
		if (st == 0) {
			snprintf(err, errlen, "no connected display on %s", want);
			return -1;
		}
		return 0;
	}
	char first_kms[64] = "";
	for (int i = 0; i < MAX_CARDS; i++) {
		char path[64];
		snprintf(path, sizeof(path), "%s/card%d", DRM_DIR_NAME, i);
		int st = card_state(path, &o->fd);
		if (st == 1) {
			snprintf(o->path, sizeof(o->path), "%s", path);
			return 0;
		}
		if (st == 0 && !first_kms[0])
			snprintf(first_kms, sizeof(first_kms), "%s", path);
	}
	if (first_kms[0])
		snprintf(err, errlen, "no connected display on %s", first_kms);
	else
		snprintf(err, errlen, "no DRM card with KMS in %s (give one with --drm-device)", DRM_DIR_NAME);
	return -1;
}

/* "WxH" or "WxH@Hz" -> w, h, hz (0 = any).  0 or -1. */
static int parse_mode(const char *s, int *w, int *h, int *hz)
{
	char tail = 0;
	*hz = 0;
	if (sscanf(s, "%dx%d%c", w, h, &tail) == 2)
		return *w > 0 && *h > 0 ? 0 : -1;
	if (sscanf(s, "%dx%d@%d%c", w, h, hz, &tail) == 3)
		return *w > 0 && *h > 0 && *hz > 0 ? 0 : -1;
	return -1;
}

static int choose_mode(struct kms_output *o, drmModeConnector *c, const char *want, char *err, size_t errlen)
{
	if (want && want[0]) {
		int w, h, hz;
		if (parse_mode(want, &w, &h, &hz) < 0) {
			snprintf(err, errlen, "--mode '%s' is not WxH or WxH@Hz", want);
			return -1;
		}
		for (int i = 0; i < c->count_modes; i++) {
			const drmModeModeInfo *m = &c->modes[i];
			if (m->hdisplay == w && m->vdisplay == h && (!hz || (int)m->vrefresh == hz)) {
				o->mode = *m;
				return 0;
			}
		}
		char list[256] = "";
		size_t len = 0;
		for (int i = 0; i < c->count_modes && len + 24 < sizeof(list); i++) {
			int n = snprintf(list + len, sizeof(list) - len, "%s%dx%d@%u", i ? " " : "",
			                 c->modes[i].hdisplay, c->modes[i].vdisplay, c->modes[i].vrefresh);
			if (n > 0)
				len += (size_t)n;
		}
		snprintf(err, errlen, "mode %s not offered by %s on %s (modes: %s)", want, o->conn_name, o->path, list);
		return -1;
	}
	o->mode = c->modes[0];
	for (int i = 0; i < c->count_modes; i++)
		if (c->modes[i].type & DRM_MODE_TYPE_PREFERRED) {
			o->mode = c->modes[i];
			break;
		}
	return 0;
}

static int choose_crtc(struct kms_output *o, drmModeRes *res, drmModeConnector *c, char *err, size_t errlen)
{
	o->crtc_id = 0;
	if (c->encoder_id) {
		drmModeEncoder *e = drmModeGetEncoder(o->fd, c->encoder_id);
		if (e) {
			o->crtc_id = e->crtc_id;
			drmModeFreeEncoder(e);
		}
	}
	for (int i = 0; i < c->count_encoders && !o->crtc_id; i++) {
		drmModeEncoder *e = drmModeGetEncoder(o->fd, c->encoders[i]);
		if (!e)
			continue;
		for (int k = 0; k < res->count_crtcs; k++)
			if (e->possible_crtcs & (1u << k)) {
				o->crtc_id = res->crtcs[k];
				break;
			}
		drmModeFreeEncoder(e);
	}
	if (!o->crtc_id) {
		snprintf(err, errlen, "no CRTC can drive %s on %s", o->conn_name, o->path);
		return -1;
	}
	o->crtc_index = -1;
	for (int k = 0; k < res->count_crtcs; k++)
		if (res->crtcs[k] == o->crtc_id)
			o->crtc_index = k;
	if (o->crtc_index < 0) {
		snprintf(err, errlen, "CRTC %u is not in the card's list", o->crtc_id);
		return -1;
	}
	return 0;
}

int kms_output_poll(struct kms_output *o, const char *mode, bool *changed)
{
	*changed = false;
	/* an event (a monitor swapped, a new preferred mode): probe again */
	bool probe = hotplug_pending(o->hotplug);
	drmModeConnector *c = probe ? drmModeGetConnector(o->fd, o->conn_id) : drmModeGetConnectorCurrent(o->fd, o->conn_id);
	if (c && !probe && !o->connected && c->connection == DRM_MODE_CONNECTED) {
		/* back from unplugged: its modes may be another monitor's */
		drmModeFreeConnector(c);
		c = drmModeGetConnector(o->fd, o->conn_id);
	}
	if (!c)
		return -1;
	int rc = c->connection == DRM_MODE_CONNECTED && c->count_modes > 0;
	if (rc) {
		drmModeModeInfo before = o->mode;
		char err[256];
		if (choose_mode(o, c, mode, err, sizeof(err)) < 0) {
			o->mode = before; /* the mode asked for is gone: as good as unplugged */
			rc = 0;
		} else {
			*changed = memcmp(&before, &o->mode, sizeof(before)) != 0;
		}
	}
	drmModeFreeConnector(c);
	o->connected = rc == 1;
	return rc;
}

void kms_output_close(struct kms_output *o)
{
	hotplug_close(o->hotplug);
	o->hotplug = NULL;
	if (o->fd >= 0)
		close(o->fd);
	o->fd = -1;
}

int kms_output_open(struct kms_output *o, const char *device, const char *mode, char *err, size_t errlen)
{
	drmModeRes *res = NULL;
	drmModeConnector *conn = NULL;
	int rc = -1;
	if (open_card(o, device, err, errlen) < 0)
		goto out;
	res = drmModeGetResources(o->fd);
	conn = res ? find_connector(o->fd, res) : NULL;
	if (!res || !conn) {
		snprintf(err, errlen, "no connected display on %s", o->path);
		goto out;
	}
	o->conn_id = conn->connector_id;
	snprintf(o->conn_name, sizeof(o->conn_name), "%s-%u", conn_type_name(conn->connector_type),
	         conn->connector_type_id);
	if (choose_mode(o, conn, mode, err, errlen) < 0 || choose_crtc(o, res, conn, err, errlen) < 0)
		goto out;
	o->connected = true;
	o->hotplug = hotplug_open(o->fd);
	rc = 0;
out:
	drmModeFreeConnector(conn);
	drmModeFreeResources(res);
	return rc;
}
