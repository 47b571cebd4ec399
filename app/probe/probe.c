/* isoterra — `isoterra --probe`: every section in turn, then the verdict.
 * The text goes to stdout; its last line is the verdict, and when the job
 * would not run, the first blocking reason.  --results FILE writes the
 * same facts as JSON (temp file + rename; "-" = stdout, the text then
 * going to stderr). */
#include "probe.h"
#include "probe_int.h"
#include "core.h"

#include <string.h>

static void config_json(struct probe_report *r, const struct params *p)
{
	pj_obj(r, "config");
	static const char *const keys[] = { "platform", "device", "drm_device", "mode", "size", "count", "scene",
					    "seed", "gpio_chip", "v4l2", "v4l2_format", "keyboard" };
	for (size_t i = 0; i < sizeof(keys) / sizeof(keys[0]); i++) {
		const struct param_info *pi = params_find(keys[i]);
		if (!pi)
			continue;
		char v[PARAM_STR_MAX];
		params_format(p, pi, v, sizeof(v));
		pj_str(r, keys[i], v);
	}
	pj_end(r);
}

static int write_json(struct probe_report *r, const char *path)
{
	fflush(r->json);
	if (!strcmp(path, "-")) {
		fwrite(r->json_buf, 1, r->json_len, stdout);
		return fflush(stdout) == 0 ? 0 : -1;
	}
	struct atomic_file af = { 0 };
	char err[512 + ATOMIC_TMP_EXTRA];
	if (atomic_open(&af, path, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return -1;
	}
	if (fwrite(r->json_buf, 1, r->json_len, af.f) != r->json_len) {
		log_error("cannot write '%s'", path);
		atomic_abort(&af);
		return -1;
	}
	if (atomic_commit(&af, path, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return -1;
	}
	return 0;
}

int probe_run(const struct params *p)
{
	struct probe_report r;
	if (probe_report_open(&r, p->results[0] != 0) < 0) {
		log_error("out of memory");
		return 2;
	}
	if (!strcmp(p->results, "-"))
		r.txt = stderr; /* stdout carries the JSON alone */
	log_set_level(p->verbose ? LOG_DEBUG : LOG_WARN);
	pj_obj(&r, NULL);
	pj_int(&r, "isoterra_probe", 1);
	config_json(&r, p);
	pt(&r, "isoterra --probe: what this machine offers against what the job needs");
	probe_egl(&r);
	probe_drm(&r, p);
	probe_gpio(&r, p);
	probe_v4l2(&r, p);
	probe_gl(&r, p);
	probe_cache(&r, p);
	probe_access(&r);
	bool runs = r.nblocking_all == 0;
	pj_obj(&r, "verdict");
	pj_bool(&r, "runs", runs);
	pj_arr(&r, "blocking");
	for (int i = 0; i < r.nblocking; i++)
		pj_str(&r, NULL, r.blocking[i]);
	pj_end(&r);
	pj_arr(&r, "warnings");
	for (int i = 0; i < r.nwarning; i++)
		pj_str(&r, NULL, r.warning[i]);
	pj_end(&r);
	pj_end(&r);
	pj_end(&r);
	if (r.json)
		fputc('\n', r.json);
	int rc = runs ? 0 : 1;
	if (r.json && write_json(&r, p->results) < 0)
		rc = 2;
	if (runs)
		pt(&r, "probe: the job would run (%d warning%s)", r.nwarning, r.nwarning == 1 ? "" : "s");
	else
		pt(&r, "probe: the job would NOT run (%d blocking reason%s); the first: %s", r.nblocking_all,
		   r.nblocking_all == 1 ? "" : "s", r.blocking[0]);
	fflush(stdout);
	probe_report_close(&r);
	return rc;
}
