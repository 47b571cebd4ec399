/* isoterra — KMS output selection: the DRM card (given, or the first with a
 * connected output), its first connected connector, the mode (asked for,
 * or the preferred one) and a CRTC that can drive the connector: the one
 * its encoder uses, else the first its encoders can use; later, whether
 * that connector is still connected and which mode it wants now.  See
 * kms.h. */
#include "kms.h"
#include "platform_util.h"

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

/* "WxH@Hz WxH@Hz ..." of the connector's modes, as many as fit. */
static void modes_list(const drmModeConnector *c, char *list, size_t size)
{
	size_t len = 0;
	list[0] = 0;
	for (int i = 0; i < c->count_modes && len + 24 < size; i++) {
		int n = snprintf(list + len, size - len, "%s%dx%d@%u", i ? " " : "", c->modes[i].hdisplay,
		                 c->modes[i].vdisplay, c->modes[i].vrefresh);
		if (n > 0)
			len += (size_t)n;
	}
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
		char list[256];
		modes_list(c, list, sizeof(list));
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

/* The index of a CRTC in the card's list, or -1. */
static int crtc_index(const drmModeRes *res, uint32_t id)
{
	for (int k = 0; k < res->count_crtcs; k++)
		if (res->crtcs[k] == id)
			return k;
	return -1;
}

/* A CRTC for the connector, not one of `used` (a mask of CRTC indices:
 * the other outputs'). */
static int choose_crtc(struct kms_output *o, drmModeRes *res, drmModeConnector *c, uint32_t used, char *err,
                       size_t errlen)
{
	o->crtc_id = 0;
	if (c->encoder_id) {
		drmModeEncoder *e = drmModeGetEncoder(o->fd, c->encoder_id);
		if (e) {
			int k = crtc_index(res, e->crtc_id);
			if (k >= 0 && k < 32 && !(used & (1u << k)))
				o->crtc_id = e->crtc_id;
			drmModeFreeEncoder(e);
		}
	}
	for (int i = 0; i < c->count_encoders && !o->crtc_id; i++) {
		drmModeEncoder *e = drmModeGetEncoder(o->fd, c->encoders[i]);
		if (!e)
			continue;
		for (int k = 0; k < res->count_crtcs && k < 32; k++)
			if ((e->possible_crtcs & (1u << k)) && !(used & (1u << k))) {
				o->crtc_id = res->crtcs[k];
				break;
			}
		drmModeFreeEncoder(e);
	}
	if (!o->crtc_id) {
		snprintf(err, errlen, "no CRTC can drive %s on %s%s", o->conn_name, o->path,
		         used ? " besides the other outputs' CRTCs" : "");
		return -1;
	}
	o->crtc_index = crtc_index(res, o->crtc_id);
	if (o->crtc_index < 0) {
		snprintf(err, errlen, "CRTC %u is not in the card's list", o->crtc_id);
		return -1;
	}
	return 0;
}

int kms_output_poll(struct kms_output *o, const char *mode, bool event, bool *changed)
{
	*changed = false;
	/* an event (a monitor swapped, a new preferred mode): probe again */
	bool probe = event;
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
	if (choose_mode(o, conn, mode, err, errlen) < 0 || choose_crtc(o, res, conn, 0, err, errlen) < 0)
		goto out;
	o->connected = true;
	o->hotplug = hotplug_open(o->fd);
	rc = 0;
out:
	drmModeFreeConnector(conn);
	drmModeFreeResources(res);
	return rc;
}

/* ---- several outputs ------------------------------------------------------ */

static void conn_name(const drmModeConnector *c, char *name, size_t size)
{
	snprintf(name, size, "%s-%u", conn_type_name(c->connector_type), c->connector_type_id);
}

/* The connector's mode of w x h: the refresh rate hz when it has it, else
 * its preferred one of that size, else the first; NULL when none. */
static const drmModeModeInfo *mode_of_size(const drmModeConnector *c, int w, int h, unsigned hz)
{
	const drmModeModeInfo *found = NULL;
	for (int i = 0; i < c->count_modes; i++) {
		const drmModeModeInfo *m = &c->modes[i];
		if (m->hdisplay != w || m->vdisplay != h)
			continue;
		if (m->vrefresh == hz)
			return m;
		if (!found || (m->type & DRM_MODE_TYPE_PREFERRED))
			found = m;
	}
	return found;
}

/* One mode size for every connector c[0..n): `want`, or the first's
 * preferred, or the first of its modes that all offer. */
static int common_mode(struct kms_output *o, drmModeConnector **c, int n, const char *want, char *err, size_t errlen)
{
	if (want && want[0]) {
		for (int i = 0; i < n; i++)
			if (choose_mode(&o[i], c[i], want, err, errlen) < 0)
				return -1;
		return 0;
	}
	if (choose_mode(&o[0], c[0], NULL, err, errlen) < 0)
		return -1;
	const drmModeModeInfo first = o[0].mode;
	for (int k = -1; k < c[0]->count_modes; k++) {
		const drmModeModeInfo *m = k < 0 ? &first : &c[0]->modes[k];
		bool all = true;
		for (int i = 1; i < n && all; i++) {
			const drmModeModeInfo *mi = mode_of_size(c[i], m->hdisplay, m->vdisplay, m->vrefresh);
			if (mi)
				o[i].mode = *mi;
			else
				all = false;
		}
		if (all) {
			o[0].mode = *m;
			return 0;
		}
	}
	size_t len = (size_t)snprintf(err, errlen, "--outputs: no mode size common to");
	for (int i = 0; i < n && len < errlen; i++) {
		char list[160];
		modes_list(c[i], list, sizeof(list));
		int k = snprintf(err + len, errlen - len, "%s %s (modes: %s)", i ? (i == n - 1 ? " and" : ",") : "",
		                 o[i].conn_name, list);
		if (k < 0)
			break;
		len += (size_t)k;
	}
	return -1;
}

/* Every connector's name, connected or not, for an error. */
static void conn_names(int fd, const drmModeRes *res, char *list, size_t size)
{
	size_t len = 0;
	list[0] = 0;
	for (int i = 0; i < res->count_connectors && len + 48 < size; i++) {
		drmModeConnector *c = drmModeGetConnectorCurrent(fd, res->connectors[i]);
		if (!c)
			continue;
		char name[32];
		conn_name(c, name, sizeof(name));
		int k = snprintf(list + len, size - len, "%s%s %s", i ? ", " : "", name,
		                 c->connection == DRM_MODE_CONNECTED ? "connected" : "not connected");
		if (k > 0)
			len += (size_t)k;
		drmModeFreeConnector(c);
	}
}

int kms_outputs_open(struct kms_output *o, int max, int *n, const char *device, const char *names, const char *mode,
                     char *err, size_t errlen)
{
	drmModeRes *res = NULL;
	drmModeConnector *conn[32] = { 0 };
	int count = 0, rc = -1;
	*n = 0;
	if (max > (int)(sizeof(conn) / sizeof(conn[0])))
		max = (int)(sizeof(conn) / sizeof(conn[0]));
	if (open_card(&o[0], device, err, errlen) < 0)
		return -1;
	res = drmModeGetResources(o[0].fd);
	if (!res) {
		snprintf(err, errlen, "no connected display on %s", o[0].path);
		return -1;
	}
	bool all = !strcmp(names, "all");
	if (all) {
		for (int i = 0; i < res->count_connectors; i++) {
			drmModeConnector *c = drmModeGetConnector(o[0].fd, res->connectors[i]);
			if (!c)
				continue;
			if (c->connection != DRM_MODE_CONNECTED || c->count_modes == 0) {
				drmModeFreeConnector(c);
				continue;
			}
			if (count == max) {
				char name[32];
				conn_name(c, name, sizeof(name));
				plog_warn("gbm: --outputs all: %s on %s left dark (at most %d outputs)", name, o[0].path, max);
				drmModeFreeConnector(c);
				continue;
			}
			conn[count++] = c;
		}
		if (!count) {
			snprintf(err, errlen, "no connected display on %s", o[0].path);
			goto out;
		}
	} else {
		const char *s = names;
		while (*s) {
			const char *comma = strchr(s, ',');
			size_t len = comma ? (size_t)(comma - s) : strlen(s);
			char want[32];
			if (len == 0 || len >= sizeof(want)) {
				snprintf(err, errlen, "--outputs '%.64s' is not all or a comma-separated list of connector names",
				         names);
				goto out;
			}
			memcpy(want, s, len);
			want[len] = 0;
			s += len + (comma ? 1 : 0);
			if (comma && !*s) {
				snprintf(err, errlen, "--outputs '%.64s': a name is missing after the last comma", names);
				goto out;
			}
			if (count == max) {
				snprintf(err, errlen, "--outputs '%.64s': more than %d outputs", names, max);
				goto out;
			}
			drmModeConnector *found = NULL;
			for (int i = 0; i < res->count_connectors && !found; i++) {
				drmModeConnector *c = drmModeGetConnector(o[0].fd, res->connectors[i]);
				if (!c)
					continue;
				char name[32];
				conn_name(c, name, sizeof(name));
				if (!strcmp(name, want))
					found = c;
				else
					drmModeFreeConnector(c);
			}
			char list[256];
			if (!found) {
				conn_names(o[0].fd, res, list, sizeof(list));
				snprintf(err, errlen, "--outputs: no connector %s on %s (its connectors: %s)", want, o[0].path, list);
				goto out;
			}
			for (int i = 0; i < count; i++)
				if (conn[i]->connector_id == found->connector_id) {
					drmModeFreeConnector(found);
					snprintf(err, errlen, "--outputs: %s is named twice", want);
					goto out;
				}
			conn[count++] = found;
			if (found->connection != DRM_MODE_CONNECTED || found->count_modes == 0) {
				conn_names(o[0].fd, res, list, sizeof(list));
				snprintf(err, errlen, "--outputs: %s on %s is not connected (its connectors: %s)", want, o[0].path,
				         list);
				goto out;
			}
		}
		if (!count) {
			snprintf(err, errlen, "--outputs '%.64s' names no connector", names);
			goto out;
		}
	}
	uint32_t used = 0;
	for (int i = 0; i < count; i++) {
		if (i > 0) {
			o[i] = o[0];
			o[i].hotplug = NULL;
		}
		o[i].conn_id = conn[i]->connector_id;
		conn_name(conn[i], o[i].conn_name, sizeof(o[i].conn_name));
		o[i].x = o[i].y = 0;
	}
	if (common_mode(o, conn, count, mode, err, errlen) < 0)
		goto out;
	for (int i = 0; i < count; i++) {
		if (choose_crtc(&o[i], res, conn[i], used, err, errlen) < 0)
			goto out;
		used |= 1u << o[i].crtc_index;
		o[i].connected = true;
	}
	o[0].hotplug = hotplug_open(o[0].fd);
	*n = count;
	rc = 0;
out:
	for (int i = 0; i < count; i++)
		drmModeFreeConnector(conn[i]);
	drmModeFreeResources(res);
	return rc;
}
