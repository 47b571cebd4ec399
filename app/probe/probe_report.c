/* isoterra — the probe's report: plain text to a stream, the same facts as
 * a JSON document in memory (written at the end, probe.c). */
#include "probe_int.h"
#include "core.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

int probe_report_open(struct probe_report *r, bool json)
{
	memset(r, 0, sizeof(*r));
	r->txt = stdout;
	if (json && !(r->json = open_memstream(&r->json_buf, &r->json_len)))
		return -1;
	r->first[0] = true;
	return 0;
}

void probe_report_close(struct probe_report *r)
{
	if (r->json)
		fclose(r->json);
	free(r->json_buf);
	r->json = NULL;
	r->json_buf = NULL;
}

static void jstring(FILE *f, const char *s)
{
	fputc('"', f);
	for (const unsigned char *c = (const unsigned char *)s; *c; c++) {
		if (*c == '"' || *c == '\\')
			fprintf(f, "\\%c", *c);
		else if (*c == '\n')
			fputs("\\n", f);
		else if (*c < 0x20 || *c == 0x7f)
			fprintf(f, "\\u%04x", *c);
		else
			fputc(*c, f);
	}
	fputc('"', f);
}

/* The comma, the indent and the key before a member. */
static void member(struct probe_report *r, const char *key)
{
	if (!r->first[r->depth])
		fputc(',', r->json);
	r->first[r->depth] = false;
	if (r->depth > 0)
		fprintf(r->json, "\n%*s", 2 * r->depth, "");
	if (key) {
		jstring(r->json, key);
		fputs(": ", r->json);
	}
}

static void open_nested(struct probe_report *r, const char *key, char c)
{
	if (!r->json)
		return;
	member(r, key);
	fputc(c, r->json);
	if (r->depth + 1 < PROBE_DEPTH)
		r->depth++;
	r->first[r->depth] = true;
	r->closer[r->depth] = c == '{' ? '}' : ']';
}

void pj_obj(struct probe_report *r, const char *key)
{
	open_nested(r, key, '{');
}

void pj_arr(struct probe_report *r, const char *key)
{
	open_nested(r, key, '[');
}

void pj_end(struct probe_report *r)
{
	if (!r->json || r->depth == 0)
		return;
	char close = r->closer[r->depth];
	bool empty = r->first[r->depth];
	r->depth--;
	if (!empty)
		fprintf(r->json, "\n%*s", 2 * r->depth, "");
	fputc(close, r->json);
}

void pj_str(struct probe_report *r, const char *key, const char *v)
{
	if (!r->json)
		return;
	member(r, key);
	jstring(r->json, v ? v : "");
}

void pj_int(struct probe_report *r, const char *key, int64_t v)
{
	if (!r->json)
		return;
	member(r, key);
	fprintf(r->json, "%" PRId64, v);
}

void pj_bool(struct probe_report *r, const char *key, bool v)
{
	if (!r->json)
		return;
	member(r, key);
	fputs(v ? "true" : "false", r->json);
}

void pj_null(struct probe_report *r, const char *key)
{
	if (!r->json)
		return;
	member(r, key);
	fputs("null", r->json);
}

void pt(struct probe_report *r, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vfprintf(r->txt, fmt, ap);
	va_end(ap);
	fputc('\n', r->txt);
}

/* One finding, in the text under its label and kept (the first n) for the
 * summary and the JSON. */
static void note(FILE *txt, const char *label, char (*kept)[512], int *n, int cap, const char *fmt, va_list ap)
{
	char msg[512];
	vsnprintf(msg, sizeof(msg), fmt, ap);
	fprintf(txt, "  %s: %s\n", label, msg);
	if (*n < cap)
		snprintf(kept[(*n)++], sizeof(kept[0]), "%s", msg);
}

void probe_block(struct probe_report *r, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	note(r->txt, "BLOCKS", r->blocking, &r->nblocking, (int)ARRAY_SIZE(r->blocking), fmt, ap);
	va_end(ap);
	r->nblocking_all++;
}

void probe_warn(struct probe_report *r, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	note(r->txt, "warning", r->warning, &r->nwarning, (int)ARRAY_SIZE(r->warning), fmt, ap);
	va_end(ap);
}
