/* isoterra — --probe's hardware sections: DRM cards and connectors (with
 * DRM master), gpiochips and the configured knob lines, V4L2 outputs, and
 * the process's groups against the device nodes met. */
#include "probe_int.h"
#include "output.h"
#include "hal_probe.h"
#include "platform_probe.h"

#include <errno.h>
#include <grp.h>
#include <pwd.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void probe_node(struct probe_report *r, const char *path, bool needed, const char *what)
{
	if (!path || !path[0])
		return;
	for (int i = 0; i < r->nnode; i++)
		if (!strcmp(r->node[i].path, path)) {
			r->node[i].needed |= needed;
			return;
		}
	if (r->nnode >= (int)(sizeof(r->node) / sizeof(r->node[0])))
		return;
	struct probe_node_use *n = &r->node[r->nnode++];
	snprintf(n->path, sizeof(n->path), "%s", path);
	snprintf(n->what, sizeof(n->what), "%s", what);
	n->needed = needed;
}

/* ---- DRM ------------------------------------------------------------------ */

/* The card the gbm platform would use: --drm-device, else the first card
 * with KMS and a connected connector with modes (kms.c's rule). */
static const struct probe_drm_card *gbm_card(const struct probe_drm *d, const char *want)
{
	for (int i = 0; i < d->ncards; i++) {
		const struct probe_drm_card *c = &d->card[i];
		if (want[0]) {
			if (!strcmp(c->path, want))
				return c;
			continue;
		}
		for (int k = 0; k < c->nconn; k++)
			if (c->conn[k].connected && c->conn[k].nmodes > 0)
				return c;
	}
	return NULL;
}

void probe_drm(struct probe_report *r, const struct params *p)
{
	struct probe_drm *d = calloc(1, sizeof(*d));
	if (!d)
		return;
	platform_probe_drm(d);
	bool gbm = !strcmp(p->platform, "gbm");
	pt(r, "DRM (KMS displays)");
	pj_obj(r, "drm");
	pj_bool(r, "built", d->built);
	if (!d->built) {
		pt(r, "  built without libdrm/gbm: no KMS display");
		if (gbm)
			probe_block(r, "--platform gbm: this build has no gbm platform");
	} else if (d->ncards == 0) {
		pt(r, "  no DRM card in /dev/dri");
	}
	pj_arr(r, "cards");
	for (int i = 0; i < d->ncards; i++) {
		const struct probe_drm_card *c = &d->card[i];
		probe_node(r, c->path, false, "DRM card");
		pt(r, "  %s%s%s%s: %s, DRM master %s%s%s", c->path, c->driver[0] ? " (" : "", c->driver,
		   c->driver[0] ? ")" : "", c->kms ? "KMS" : c->err, c->master ? "can be taken" : "cannot be taken",
		   c->master ? "" : ": ", c->master_err);
		pj_obj(r, NULL);
		pj_str(r, "path", c->path);
		pj_str(r, "driver", c->driver);
		pj_bool(r, "kms", c->kms);
		if (c->err[0])
			pj_str(r, "error", c->err);
		pj_bool(r, "master", c->master);
		if (!c->master)
			pj_str(r, "master_error", c->master_err);
		pj_arr(r, "connectors");
		for (int k = 0; k < c->nconn; k++) {
			const struct probe_drm_connector *o = &c->conn[k];
			char modes[400] = "";
			for (int m = 0; m < o->nmodes && m < PROBE_MAX_MODES; m++) {
				size_t n = strlen(modes);
				snprintf(modes + n, sizeof(modes) - n, "%s%s", m ? ", " : "", o->modes[m]);
			}
			pt(r, "    %s: %s%s%s%s", o->name, o->connected ? "connected" : "disconnected",
			   o->nmodes ? ", modes " : "", modes, o->nmodes > PROBE_MAX_MODES ? ", ..." : "");
			pj_obj(r, NULL);
			pj_str(r, "name", o->name);
			pj_int(r, "id", o->id);
			pj_bool(r, "connected", o->connected);
			pj_int(r, "mode_count", o->nmodes);
			pj_arr(r, "modes");
			for (int m = 0; m < o->nmodes && m < PROBE_MAX_MODES; m++)
				pj_str(r, NULL, o->modes[m]);
			pj_end(r);
			pj_end(r);
		}
		pj_end(r);
		pj_end(r);
	}
	pj_end(r);
	const struct probe_drm_card *use = d->built ? gbm_card(d, p->drm_device) : NULL;
	pj_str(r, "gbm_card", use ? use->path : "");
	if (use) {
		probe_node(r, use->path, gbm, "gbm: the display's DRM card");
		pt(r, "  the gbm platform would use %s", use->path);
	}
	if (gbm && d->built) {
		if (!use && p->drm_device[0])
			probe_block(r, "--drm-device %s: no such DRM card", p->drm_device);
		else if (!use)
			probe_block(r, "--platform gbm: no DRM card with a connected display");
		else if (!use->kms)
			probe_block(r, "--platform gbm: %s: %s", use->path, use->err);
		else if (!use->master)
			probe_block(r, "--platform gbm: DRM master on %s cannot be taken: %s", use->path, use->master_err);
	}
	pj_end(r);
	free(d);
}

/* ---- GPIO ------------------------------------------------------------------ */

static void gpio_line(struct probe_report *r, const char *what, const char *chip, int line, enum hal_bias bias,
		      bool active_low)
{
	if (line < 0)
		return;
	char path[HAL_NAME_MAX], err[320];
	bool ok = false;
	pj_obj(r, NULL);
	pj_str(r, "what", what);
	pj_str(r, "chip", chip);
	pj_int(r, "line", line);
	if (!chip || !chip[0]) {
		snprintf(err, sizeof(err), "no gpiochip given (--gpio-chip)");
		path[0] = 0;
	} else {
		ok = hal_probe_gpio_line(chip, line, bias, active_low, path, sizeof(path), err, sizeof(err)) == 0;
	}
	pj_bool(r, "can_request", ok);
	if (!ok)
		pj_str(r, "error", err);
	pj_end(r);
	probe_node(r, path, true, "GPIO knobs");
	pt(r, "  %s: %s line %d: %s%s", what, chip && chip[0] ? chip : "(no chip)", line,
	   ok ? "can be requested" : "cannot be requested", "");
	if (!ok)
		probe_block(r, "%s: %s", what, err);
}

void probe_gpio(struct probe_report *r, const struct params *p)
{
	pt(r, "GPIO");
	pj_obj(r, "gpio");
	const char *lib = hal_probe_gpiod();
	pj_str(r, "libgpiod", lib ? lib : "");
	struct hal_probe_chip chips[32];
	int n = hal_probe_gpiochips(chips, 32);
	if (n < 0)
		pt(r, "  built without libgpiod: no GPIO knobs");
	else if (n == 0)
		pt(r, "  libgpiod %s; no gpiochip in /dev", lib);
	else
		pt(r, "  libgpiod %s", lib);
	pj_arr(r, "chips");
	for (int i = 0; i < n; i++) {
		const struct hal_probe_chip *c = &chips[i];
		probe_node(r, c->path, false, "gpiochip");
		if (c->err[0])
			pt(r, "  %s: %s", c->path, c->err);
		else
			pt(r, "  %s: %s, label '%s', %u lines", c->path, c->name, c->label, c->lines);
		pj_obj(r, NULL);
		pj_str(r, "path", c->path);
		pj_str(r, "name", c->name);
		pj_str(r, "label", c->label);
		pj_int(r, "lines", c->lines);
		if (c->err[0])
			pj_str(r, "error", c->err);
		pj_end(r);
	}
	pj_end(r);
	pj_arr(r, "lines");
	struct hal_gpio_config cfg;
	char err[512];
	if (hal_config_gpio(p, &cfg, err, sizeof(err)) < 0) {
		pj_end(r);
		pj_end(r);
		probe_block(r, "GPIO configuration: %s", err);
		return;
	}
	bool any = false;
	for (int e = 0; e < HAL_ENCODERS; e++) {
		const struct hal_encoder_config *ec = &cfg.enc[e];
		const char *chip = ec->chip && ec->chip[0] ? ec->chip : cfg.chip;
		const int line[3] = { ec->a, ec->b, ec->sw };
		static const char *const suffix[3] = { "a", "b", "sw" };
		for (int k = 0; k < 3; k++) {
			char what[32];
			snprintf(what, sizeof(what), "enc%d_%s", e + 1, suffix[k]);
			any |= line[k] >= 0;
			gpio_line(r, what, chip, line[k], ec->bias, ec->active_low);
		}
	}
	const char *bchip = cfg.button_chip && cfg.button_chip[0] ? cfg.button_chip : cfg.chip;
	for (int b = 0; b < HAL_BUTTONS; b++) {
		char what[32];
		snprintf(what, sizeof(what), "button%d_line", b + 1);
		any |= cfg.button[b].line >= 0;
		gpio_line(r, what, bchip, cfg.button[b].line, cfg.button_bias, cfg.button_active_low);
	}
	pj_end(r);
	if (!any)
		pt(r, "  no knob line configured");
	pj_end(r);
}

/* ---- V4L2 ------------------------------------------------------------------ */

static void v4l2_json(struct probe_report *r, const struct hal_probe_v4l2 *v)
{
	pj_obj(r, NULL);
	pj_str(r, "path", v->path);
	pj_str(r, "driver", v->driver);
	pj_str(r, "card", v->card);
	pj_bool(r, "output", v->output);
	if (v->err[0])
		pj_str(r, "error", v->err);
	pj_arr(r, "formats");
	for (int f = 0; f < v->nfmt; f++) {
		pj_obj(r, NULL);
		pj_str(r, "fourcc", v->fmt[f]);
		pj_bool(r, "supported", v->fmt_ok[f]);
		pj_end(r);
	}
	pj_end(r);
	pj_end(r);
}

static void v4l2_text(struct probe_report *r, const struct hal_probe_v4l2 *v)
{
	if (v->err[0]) {
		pt(r, "  %s: %s", v->path, v->err);
		return;
	}
	char fmts[400] = "";
	for (int f = 0; f < v->nfmt; f++) {
		size_t n = strlen(fmts);
		snprintf(fmts + n, sizeof(fmts) - n, "%s%s%s", f ? " " : "", v->fmt[f], v->fmt_ok[f] ? "" : "(-)");
	}
	pt(r, "  %s: %s (%s): %s%s%s", v->path, v->card, v->driver,
	   v->output ? "video output" : v->output_mplane ? "multi-planar output (not supported)" : "not an output",
	   v->output ? ", formats " : "", v->output ? (fmts[0] ? fmts : "none") : "");
}

void probe_v4l2(struct probe_report *r, const struct params *p)
{
	pt(r, "V4L2 (video outputs; (-) = a format the conversion does not write)");
	pj_obj(r, "v4l2");
	struct hal_probe_v4l2 *list = calloc(33, sizeof(*list));
	if (!list) {
		pj_end(r);
		return;
	}
	int n = hal_probe_v4l2_list(list, 32);
	int outputs = 0;
	pj_arr(r, "devices");
	for (int i = 0; i < n; i++) {
		probe_node(r, list[i].path, false, "V4L2 device");
		if (!list[i].output)
			continue; /* capture devices and the like: not ours */
		outputs++;
		v4l2_text(r, &list[i]);
		v4l2_json(r, &list[i]);
	}
	pj_end(r);
	if (outputs == 0)
		pt(r, "  no V4L2 video output among %d /dev/video* device%s", n, n == 1 ? "" : "s");
	pj_str(r, "configured", p->v4l2);
	if (p->v4l2[0]) {
		struct hal_probe_v4l2 *v = &list[32];
		hal_probe_v4l2_one(p->v4l2, v);
		probe_node(r, p->v4l2, true, "--v4l2 output");
		struct hal_v4l2_config cfg;
		hal_config_v4l2(p, 16, 16, &cfg);
		if (v->err[0]) {
			probe_block(r, "--v4l2 %s: %s", p->v4l2, v->err);
		} else if (!v->output) {
			v4l2_text(r, v);
			probe_block(r, "--v4l2 %s (%s) is not a video output device", p->v4l2, v->card);
		} else {
			int usable = -1;
			for (int f = 0; f < v->nfmt && usable < 0; f++) {
				bool want = cfg.format < 0 ? v->fmt_ok[f]
							  : conv_fmt_from_fourcc((uint32_t)v->fmt[f][0] |
										 (uint32_t)v->fmt[f][1] << 8 |
										 (uint32_t)v->fmt[f][2] << 16 |
										 (uint32_t)v->fmt[f][3] << 24) == cfg.format;
				if (want)
					usable = f;
			}
			if (usable >= 0)
				pt(r, "  --v4l2 %s: writes %s", p->v4l2, v->fmt[usable]);
			else if (cfg.format < 0)
				probe_block(r, "--v4l2 %s offers no format the conversion writes (YUYV UYVY NV12 NV21 YU12 "
					    "RGB3 BGR3)", p->v4l2);
			else
				probe_block(r, "--v4l2 %s does not offer --v4l2-format %s", p->v4l2,
					    conv_fmt_name((enum conv_fmt)cfg.format));
		}
	}
	pj_end(r);
	free(list);
}

/* ---- the process's groups against the nodes -------------------------------- */

static const char *group_name(gid_t g, char *buf, size_t n)
{
	struct group *gr = getgrgid(g);
	if (gr)
		snprintf(buf, n, "%s", gr->gr_name);
	else
		snprintf(buf, n, "%u", (unsigned)g);
	return buf;
}

static bool in_groups(gid_t g, const gid_t *groups, int n)
{
	if (g == getegid())
		return true;
	for (int i = 0; i < n; i++)
		if (groups[i] == g)
			return true;
	return false;
}

void probe_access(struct probe_report *r)
{
	gid_t groups[256];
	int ng = getgroups(256, groups);
	if (ng < 0)
		ng = 0;
	struct passwd *pw = getpwuid(geteuid());
	char gname[64], all[1024] = "";
	for (int i = -1; i < ng; i++) {
		size_t n = strlen(all);
		gid_t g = i < 0 ? getegid() : groups[i];
		if (i >= 0 && g == getegid())
			continue;
		snprintf(all + n, sizeof(all) - n, "%s%s", n ? " " : "", group_name(g, gname, sizeof(gname)));
	}
	pt(r, "Access (user %s, uid %u; groups %s)", pw ? pw->pw_name : "?", (unsigned)geteuid(), all);
	pj_obj(r, "access");
	pj_str(r, "user", pw ? pw->pw_name : "");
	pj_int(r, "uid", geteuid());
	pj_arr(r, "groups");
	pj_str(r, NULL, group_name(getegid(), gname, sizeof(gname)));
	for (int i = 0; i < ng; i++)
		if (groups[i] != getegid())
			pj_str(r, NULL, group_name(groups[i], gname, sizeof(gname)));
	pj_end(r);
	pj_arr(r, "nodes");
	for (int i = 0; i < r->nnode; i++) {
		const struct probe_node_use *u = &r->node[i];
		struct stat st;
		pj_obj(r, NULL);
		pj_str(r, "path", u->path);
		pj_str(r, "what", u->what);
		pj_bool(r, "needed", u->needed);
		if (stat(u->path, &st) < 0) {
			pj_str(r, "error", strerror(errno));
			pj_end(r);
			pt(r, "  %s (%s): %s", u->path, u->what, strerror(errno));
			continue; /* the section that needs it said so */
		}
		bool rw = access(u->path, R_OK | W_OK) == 0;
		struct passwd *own = getpwuid(st.st_uid);
		group_name(st.st_gid, gname, sizeof(gname));
		const char *via = geteuid() == 0 ? "root"
				  : st.st_uid == geteuid() && (st.st_mode & 0600) == 0600 ? "owner"
				  : in_groups(st.st_gid, groups, ng) && (st.st_mode & 0060) == 0060 ? "group"
				  : (st.st_mode & 0006) == 0006 ? "others"
				  : "";
		char owner[64];
		snprintf(owner, sizeof(owner), "%s", own ? own->pw_name : "?");
		pj_str(r, "owner", owner);
		pj_str(r, "group", gname);
		char mode[8];
		snprintf(mode, sizeof(mode), "%04o", (unsigned)(st.st_mode & 07777));
		pj_str(r, "mode", mode);
		pj_bool(r, "member", in_groups(st.st_gid, groups, ng));
		pj_bool(r, "read_write", rw);
		pj_end(r);
		pt(r, "  %s (%s%s): %s:%s %s, read/write %s%s%s%s", u->path, u->what, u->needed ? ", needed" : "", owner,
		   gname, mode, rw ? "yes" : "NO", rw && via[0] ? " (as " : "", rw ? via : "", rw && via[0] ? ")" : "");
		if (!rw && u->needed)
			probe_block(r, "%s (%s): no read/write access for %s (owner %s, group %s, mode %s%s%s)", u->path,
				    u->what, pw ? pw->pw_name : "this user", owner, gname, mode,
				    in_groups(st.st_gid, groups, ng) ? "" : "; add the user to group ",
				    in_groups(st.st_gid, groups, ng) ? "" : gname);
	}
	pj_end(r);
	pj_end(r);
}
