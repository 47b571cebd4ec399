/* isoterra — what the platform layer can tell about this machine without
 * opening a platform (isoterra --probe): the EGL client extensions and
 * devices, and the DRM cards with their connectors and whether DRM master
 * can be taken.  Which platform `auto` chooses is platform_open's own
 * answer (the probe opens it). */
#ifndef ISOTERRA_PLATFORM_PROBE_H
#define ISOTERRA_PLATFORM_PROBE_H

#include <stdbool.h>

#define PROBE_MAX_EGL 16
#define PROBE_MAX_CARDS 8
#define PROBE_MAX_CONNECTORS 8
#define PROBE_MAX_MODES 8

struct probe_egl_device {
	const char *kind;          /* "GPU" (a DRM device), "software" (EGL_MESA_device_software), "other" */
	char card[128], render[128]; /* DRM device file and render node, "" = none */
	char exts[768];
};

struct probe_egl {
	char client_exts[2048];
	bool can_enumerate;        /* EGL_EXT_device_enumeration (or _base) */
	int ndev;
	struct probe_egl_device dev[PROBE_MAX_EGL];
	char err[256];             /* why no device list, "" = listed */
};
void platform_probe_egl(struct probe_egl *out);

struct probe_drm_connector {
	unsigned id;
	char name[32];             /* "HDMI-A-1" */
	bool connected;
	int nmodes;                /* all of them; the first PROBE_MAX_MODES are listed */
	char modes[PROBE_MAX_MODES][40]; /* "1920x1080@60", a preferred one ends in " preferred" */
};

struct probe_drm_card {
	char path[64];
	char driver[32];
	char err[160];             /* cannot open, no KMS ...; "" = fine */
	bool kms;                  /* drmModeGetResources worked */
	bool master;               /* drmSetMaster worked (dropped again) */
	char master_err[160];
	int nconn;
	struct probe_drm_connector conn[PROBE_MAX_CONNECTORS];
};

struct probe_drm {
	bool built;                /* libdrm is in (the gbm platform) */
	int ncards;
	struct probe_drm_card card[PROBE_MAX_CARDS];
};
void platform_probe_drm(struct probe_drm *out);

#endif
