/* isoterra — --probe's GL sections: the EGL client extensions and devices,
 * the platform the configured --platform opens (for auto: platform_open's
 * own choice), every GL limit against the need and the pass behind it
 * (the configured job's programs are built first: their needs are the
 * driver's counts, recorded when they link), and the program cache. */
#include "probe_int.h"
#include "gpu.h"
#include "core.h"
#include "platform.h"
#include "platform_probe.h"
#include "render.h"
#include "scene.h"

#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void probe_egl(struct probe_report *r)
{
	struct probe_egl *e = calloc(1, sizeof(*e));
	if (!e)
		return;
	platform_probe_egl(e);
	pt(r, "EGL");
	pt(r, "  platforms built: %s", platform_backend_names());
	pt(r, "  client extensions: %s", e->client_exts[0] ? e->client_exts : "(none)");
	pj_obj(r, "egl");
	pj_str(r, "platforms_built", platform_backend_names());
	pj_str(r, "client_extensions", e->client_exts);
	pj_arr(r, "devices");
	if (e->err[0])
		pt(r, "  devices: %s", e->err);
	else if (e->ndev == 0)
		pt(r, "  devices: none");
	for (int i = 0; i < e->ndev; i++) {
		const struct probe_egl_device *d = &e->dev[i];
		pt(r, "  device %d: %s%s%s%s%s%s", i, d->kind, d->card[0] ? ", " : "", d->card, d->render[0] ? ", " : "",
		   d->render, d->card[0] || d->render[0] ? "" : ", no DRM node");
		pj_obj(r, NULL);
		pj_int(r, "index", i);
		pj_str(r, "kind", d->kind);
		if (d->card[0])
			pj_str(r, "drm_card", d->card);
		else
			pj_null(r, "drm_card");
		if (d->render[0])
			pj_str(r, "drm_render_node", d->render);
		else
			pj_null(r, "drm_render_node");
		pj_str(r, "extensions", d->exts);
		pj_end(r);
		probe_node(r, d->render[0] ? d->render : d->card, false, "EGL device's DRM node");
	}
	pj_end(r);
	if (e->err[0])
		pj_str(r, "devices_error", e->err);
	pj_end(r);
	free(e);
}

/* The configured job's programs: the renderer's and the scene's (its
 * pipeline, field and passes), built as the run builds them. */
static int build_job(const struct params *p, int w, int h, char *err, size_t errlen)
{
	struct renderer *rd = renderer_create(w, h, p->antialias, err, errlen);
	if (!rd)
		return -1;
	if (renderer_prepare(rd, p) < 0) {
		snprintf(err, errlen, "the terrain's shading program does not build (the error is logged above)");
		renderer_destroy(rd);
		return -1;
	}
	struct scene *sc = scene_create(p, err, errlen);
	scene_destroy(sc);
	renderer_destroy(rd);
	return sc ? 0 : -1;
}

static void limits(struct probe_report *r, bool have_ok, const int64_t *have)
{
	size_t n;
	const struct gl_limit *list = gl_limits_list(&n);
	pt(r, "  limit                                          have   need  needed by");
	pj_arr(r, "limits");
	for (size_t i = 0; i < n; i++) {
		const char *who = NULL;
		int64_t need = gl_limits_need(i, &who);
		bool ok = !have_ok || have[i] >= need;
		char name[96];
		if (list[i].index >= 0)
			snprintf(name, sizeof(name), "%s[%d]", list[i].name, list[i].index);
		else
			snprintf(name, sizeof(name), "%s", list[i].name);
		char hv[24];
		if (have_ok)
			snprintf(hv, sizeof(hv), "%" PRId64, have[i]);
		else
			snprintf(hv, sizeof(hv), "?");
		pt(r, "  %-44s %8s %6" PRId64 "  %s%s", name, hv, need, who && who[0] ? who : "-",
		   ok ? "" : "   TOO LOW");
		pj_obj(r, NULL);
		pj_str(r, "name", name);
		if (have_ok)
			pj_int(r, "have", have[i]);
		else
			pj_null(r, "have");
		pj_int(r, "need", need);
		pj_str(r, "needed_by", who ? who : "");
		pj_int(r, "es31_minimum", list[i].es31_min);
		pj_bool(r, "ok", ok);
		pj_end(r);
	}
	pj_end(r);
}

void probe_gl(struct probe_report *r, const struct params *p)
{
	int w = 0, h = 0;
	char err[1024];
	pt(r, "Platform and GL (--platform %s)", p->platform);
	pj_obj(r, "gl");
	pj_str(r, "platform_asked", p->platform);
	if (cli_parse_size(p->size, &w, &h) < 0) {
		probe_block(r, "--size '%s' is not WxH", p->size);
		pj_end(r);
		return;
	}
	shader_set_dir(p->shader_dir);
	gpu_program_cache_config(p->program_cache, NULL);
	struct platform_options po = { .name = p->platform, .width = w, .height = h, .debug = p->verbose,
		.fullscreen = p->fullscreen, .hide_cursor = p->hide_cursor, .x11_present = p->x11_present, .drm_device = p->drm_device,
		.mode = p->mode, .kms_legacy = p->kms_legacy, .device = p->device };
	struct platform *plat = platform_open(&po, err, sizeof(err));
	if (!plat) {
		pj_null(r, "platform");
		pj_str(r, "error", err);
		probe_block(r, "platform %s: %s", p->platform, err);
		pj_end(r);
		return;
	}
	if (!plat->headless) {
		w = plat->width;
		h = plat->height;
	}
	pt(r, "  %s %s: %s, %s %dx%d", strcmp(p->platform, "auto") ? "platform" : "--platform auto chooses",
	   plat->backend->name, plat->device_desc, plat->headless ? "headless" : "display", w, h);
	pj_str(r, "platform", plat->backend->name);
	pj_str(r, "device", plat->device_desc);
	pj_bool(r, "headless", plat->headless);
	pj_int(r, "width", w);
	pj_int(r, "height", h);
	if (plat->headless && p->count == 0)
		probe_block(r, "--count 0 (until closed) needs a display platform (gbm, wayland, x11), not '%s'",
			    plat->backend->name);
	const char *s;
	s = (const char *)glGetString(GL_VERSION);
	pt(r, "  GL: %s", s ? s : "?");
	pj_str(r, "version", s ? s : "");
	s = (const char *)glGetString(GL_RENDERER);
	pj_str(r, "renderer", s ? s : "");
	struct gpu_caps caps;
	bool usable = gpu_init(&caps, false, err, sizeof(err)) == 0;
	if (!usable) {
		pj_str(r, "error", err);
		probe_block(r, "GL: %s", err);
	}
	/* the limits as read (the fixed needs' check again, its message kept
	 * from gpu_init's) */
	size_t n;
	gl_limits_list(&n);
	int64_t *have = calloc(n, sizeof(*have));
	char e2[512];
	bool have_ok = have && (gl_limits_check(have, e2, sizeof(e2)) == 0 || have[0] != 0);
	if (usable) {
		if (build_job(p, w, h, err, sizeof(err)) == 0) {
			pt(r, "  the job's programs: built");
			pj_bool(r, "programs_built", true);
		} else {
			pt(r, "  the job's programs: %s", err);
			pj_bool(r, "programs_built", false);
			pj_str(r, "programs_error", err);
			probe_block(r, "%s", err);
		}
	}
	limits(r, have_ok, have);
	free(have);
	struct gpu_program_cache_stats cs = gpu_program_cache_stats();
	pj_obj(r, "program_cache_use");
	pj_int(r, "hits", cs.hits);
	pj_int(r, "misses", cs.misses);
	pj_int(r, "rejected", cs.rejected);
	pj_int(r, "writes", cs.writes);
	pj_int(r, "write_errors", cs.write_errors);
	pj_end(r);
	pt(r, "  program cache while building: %u loaded, %u compiled, %u written, %u write errors", cs.hits, cs.misses,
	   cs.writes, cs.write_errors);
	pj_end(r);
	platform_close(plat);
}

/* The directory the program cache uses (gpu_program_cache_default_dir),
 * writable? */
void probe_cache(struct probe_report *r, const struct params *p)
{
	pt(r, "Program cache");
	pj_obj(r, "program_cache");
	pj_bool(r, "enabled", p->program_cache);
	if (!p->program_cache) {
		pt(r, "  off (--no-program-cache): every program is compiled at start");
		pj_end(r);
		return;
	}
	char dir[600] = "";
	if (!gpu_program_cache_default_dir(dir, sizeof(dir)))
		dir[0] = 0;
	pj_str(r, "dir", dir);
	if (!dir[0]) {
		pj_bool(r, "writable", false);
		probe_warn(r, "program cache: neither XDG_CACHE_HOME nor HOME is an absolute path: every start compiles");
		pj_end(r);
		return;
	}
	/* the directory, or the nearest parent that exists (it is created) */
	char at[600];
	snprintf(at, sizeof(at), "%s", dir);
	struct stat st;
	while (stat(at, &st) < 0 && strrchr(at, '/') && strrchr(at, '/') != at)
		*strrchr(at, '/') = 0;
	bool exists = !strcmp(at, dir);
	bool writable = access(at, W_OK | X_OK) == 0;
	pj_bool(r, "exists", exists);
	pj_bool(r, "writable", writable);
	pt(r, "  %s: %s, %s", dir, exists ? "exists" : "created at start", writable ? "writable" : "NOT writable");
	if (!writable)
		probe_warn(r, "program cache %s: %s is not writable: every start compiles", dir, at);
	pj_end(r);
}
