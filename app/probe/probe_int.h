/* isoterra — the probe's parts (private to app/probe/): the report, which
 * goes to a text stream and a JSON document at once, and its sections. */
#ifndef ISOTERRA_PROBE_INT_H
#define ISOTERRA_PROBE_INT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "params.h"

#define PROBE_DEPTH 16

struct probe_report {
	FILE *txt;          /* the plain-text report (stdout) */
	FILE *json;         /* the JSON document (a memory stream), NULL = none */
	char *json_buf;
	size_t json_len;
	int depth;
	bool first[PROBE_DEPTH]; /* no member written yet at this depth */
	char closer[PROBE_DEPTH]; /* '}' or ']' */
	char blocking[8][512]; /* the blocking reasons, the first first */
	int nblocking, nblocking_all;
	char warning[16][512];
	int nwarning;
	struct probe_node_use {
		char path[256], what[96];
		bool needed;
	} node[64];                 /* the device nodes the sections met */
	int nnode;
};

int probe_report_open(struct probe_report *r, bool json);
void probe_report_close(struct probe_report *r);
/* JSON structure: key NULL inside arrays (and for the root). */
void pj_obj(struct probe_report *r, const char *key);
void pj_arr(struct probe_report *r, const char *key);
void pj_end(struct probe_report *r);
void pj_str(struct probe_report *r, const char *key, const char *v);
void pj_int(struct probe_report *r, const char *key, int64_t v);
void pj_bool(struct probe_report *r, const char *key, bool v);
void pj_null(struct probe_report *r, const char *key);
/* Text lines. */
void pt(struct probe_report *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A reason the job would not run: kept when it is the first, printed as
 * "  BLOCKS: ..." now; its text goes to the JSON's "blocking" list. */
void probe_block(struct probe_report *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Something that runs but not as well (no cache, a knob chip busy ...). */
void probe_warn(struct probe_report *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The sections, in the report's order (probe_hw.c, probe_gl.c).  The
 * device nodes met are checked against the process's groups in
 * probe_access (each section calls it for the nodes it uses). */
/* Notes a device node a section met (needed: the job opens it). */
void probe_node(struct probe_report *r, const char *path, bool needed, const char *what);
/* The process's user and groups against every node noted. */
void probe_access(struct probe_report *r);
void probe_drm(struct probe_report *r, const struct params *p);
void probe_gpio(struct probe_report *r, const struct params *p);
void probe_v4l2(struct probe_report *r, const struct params *p);
void probe_egl(struct probe_report *r);
/* Opens the configured platform (the choice --platform auto makes), GL, the
 * job's programs: the limits against the needs with the passes. */
void probe_gl(struct probe_report *r, const struct params *p);
void probe_cache(struct probe_report *r, const struct params *p);

#endif
