/* isoterra — the results sink (sink.h): the run's figures as JSON for
 * scripts and dashboards, as glmark2 users expect (--results FILE or -),
 * and the frame rate on stderr every --fps-report seconds when no display
 * sink does it (headless runs).
 *
 * Frame time is the time between successive frames reaching the sinks
 * (the whole loop: controls, scene, overlays, the other sinks); the first
 * frame is reported apart (it includes the scene's set-up and, in the
 * world, filling the view).  The scene waits for the GPU after its update
 * and after its draw while results are collected, so the split is real
 * (and the frame a little slower than without --results). */
#include "sink.h"
#include "core.h"
#include "gpu.h"
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <unistd.h>

struct results_sink {
	struct sink base;
	char path[PARAM_STR_MAX]; /* "" = no file, "-" = stdout */
	double report_every;      /* headless --fps-report, 0 = none */
	double t_open, t_prev, t_report;
	unsigned long frames_report;
	double *ft, *up, *dr;     /* per frame, ms */
	size_t n, cap;
	char status[192];
	int battery_percent;   /* the last frame's (-1: no battery) */
	char battery_status[16];
	bool low_power;
	unsigned long low_power_frames;
	double cap_fps;
	char scene[16], size[PARAM_STR_MAX];
	int grid;
	struct atomic_file af; /* the staged file, renamed at commit */
	bool staged;
};

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static int push(struct results_sink *rs, double ft, double up, double dr)
{
	if (rs->n == rs->cap) {
		size_t nc = rs->cap ? rs->cap * 2 : 256;
		double *a = realloc(rs->ft, nc * sizeof(double));
		if (a)
			rs->ft = a;
		double *b = a ? realloc(rs->up, nc * sizeof(double)) : NULL;
		if (b)
			rs->up = b;
		double *c = b ? realloc(rs->dr, nc * sizeof(double)) : NULL;
		if (!c)
			return -1;
		rs->dr = c;
		rs->cap = nc;
	}
	rs->ft[rs->n] = ft;
	rs->up[rs->n] = up;
	rs->dr[rs->n] = dr;
	rs->n++;
	return 0;
}

static int results_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	struct results_sink *rs = (struct results_sink *)s;
	double now = clock_ms();
	if (push(rs, now - rs->t_prev, fr->update_ms, fr->draw_ms) < 0) {
		snprintf(err, errlen, "out of memory collecting frame times");
		return -1;
	}
	rs->t_prev = now;
	snprintf(rs->status, sizeof(rs->status), "%s", fr->status);
	rs->battery_percent = fr->battery_percent;
	snprintf(rs->battery_status, sizeof(rs->battery_status), "%s", fr->battery_status);
	rs->low_power = fr->low_power;
	rs->low_power_frames += fr->low_power;
	rs->cap_fps = fr->cap_fps;
	if (rs->report_every > 0 && (now - rs->t_report) / 1e3 >= rs->report_every) {
		unsigned long k = (unsigned long)rs->n - rs->frames_report;
		double dt = (now - rs->t_report) / 1e3;
		fprintf(stderr, "isoterra: fps %.1f (%lu frames in %.2f s; %dx%d headless)%s%s\n", (double)k / dt, k, dt,
			fr->w, fr->h, rs->status[0] ? "; " : "", rs->status);
		rs->t_report = now;
		rs->frames_report = rs->n;
	}
	return 0;
}

/* ---- the JSON ----------------------------------------------------------- */
static void json_str(FILE *f, const char *s)
{
	fputc('"', f);
	for (; *s; s++) {
		unsigned char c = (unsigned char)*s;
		if (c == '"' || c == '\\')
			fprintf(f, "\\%c", c);
		else if (c < 0x20)
			fprintf(f, "\\u%04x", c);
		else
			fputc(c, f);
	}
	fputc('"', f);
}

/* "p50": .., "p95": .., "p99": .., "max": .., "mean": .. of v[0..n) (sorted in place) */
static void json_dist(FILE *f, const char *name, double *v, size_t n)
{
	double sum = 0;
	for (size_t i = 0; i < n; i++)
		sum += v[i];
	qsort(v, n, sizeof(double), cmp_double);
	fprintf(f, "  \"%s\": {\"p50\": %.3f, \"p95\": %.3f, \"p99\": %.3f, \"max\": %.3f, \"mean\": %.3f}", name,
		v[n / 2], v[(n * 95) / 100], v[(n * 99) / 100], v[n - 1], sum / (double)n);
}

/* The hitches (issue 29's measure): of the frames that began a second or
 * more after the first frame, the p99, the worst (when it began, s after
 * the first frame), and how many took over 3 x that p99.  null when the
 * run was not that long. */
static void json_hitches(FILE *f, const double *ft, size_t n)
{
	double *v = malloc(sizeof(double) * (n ? n : 1));
	double t = 0, worst_t = 0, worst = 0;
	size_t k = 0;
	for (size_t i = 1; v && i < n; i++) {
		if (t >= 1000.0) {
			if (ft[i] > worst) {
				worst = ft[i];
				worst_t = t / 1e3;
			}
			v[k++] = ft[i];
		}
		t += ft[i];
	}
	fputs("  \"after_first_second\": ", f);
	if (k == 0) {
		fputs("null", f);
		free(v);
		return;
	}
	qsort(v, k, sizeof(double), cmp_double);
	double p99 = v[(k * 99) / 100];
	size_t over = 0;
	for (size_t i = 0; i < k; i++)
		over += v[i] > 3.0 * p99;
	fprintf(f,
		"{\"frames\": %zu, \"p99\": %.3f, \"max\": %.3f, \"max_over_p99\": %.3f, \"over_3x_p99\": %zu, "
		"\"worst_at_s\": %.3f}",
		k, p99, worst, p99 > 0 ? worst / p99 : 0.0, over, worst_t);
	free(v);
}

static void cpu_model(char *out, size_t n)
{
	snprintf(out, n, "unknown");
	FILE *f = fopen("/proc/cpuinfo", "r");
	char line[256];
	while (f && fgets(line, sizeof(line), f)) {
		char *c = strchr(line, ':');
		if (c && (!strncmp(line, "model name", 10) || !strncmp(line, "Model", 5))) {
			c++;
			while (*c == ' ' || *c == '\t')
				c++;
			c[strcspn(c, "\n")] = 0;
			snprintf(out, n, "%s", c);
			break;
		}
	}
	if (f)
		fclose(f);
}

static void write_machine(FILE *f)
{
	struct utsname u;
	char cpu[160];
	double load[3] = { -1, -1, -1 };
	cpu_model(cpu, sizeof(cpu));
	if (getloadavg(load, 3) < 3)
		load[0] = load[1] = load[2] = -1;
	fputs("  \"machine\": {\"cpu\": ", f);
	json_str(f, cpu);
	fprintf(f, ", \"cores\": %ld, \"load_average\": [%.2f, %.2f, %.2f], \"kernel\": ", sysconf(_SC_NPROCESSORS_ONLN),
		load[0], load[1], load[2]);
	if (uname(&u) == 0) {
		char k[256];
		snprintf(k, sizeof(k), "%s %s %s", u.sysname, u.release, u.machine);
		json_str(f, k);
	} else {
		json_str(f, "unknown");
	}
	fputs("},\n", f);
}

static void write_json(struct results_sink *rs, FILE *f, const struct sink_end *end)
{
	const GLubyte *ren = glGetString(GL_RENDERER), *ver = glGetString(GL_VERSION);
	struct scene_counts c = { 0 };
	if (end->scene && end->scene->ops->counts)
		end->scene->ops->counts(end->scene, &c);
	size_t first = rs->n > 1 ? 1 : 0, n = rs->n - first; /* steady frames: all but the first */
	double total = 0;
	for (size_t i = first; i < rs->n; i++)
		total += rs->ft[i];
	fprintf(f, "{\n  \"program\": \"isoterra\", \"version\": \"%s\",\n", ISOTERRA_VERSION);
	fputs("  \"gl\": {\"renderer\": ", f);
	json_str(f, ren ? (const char *)ren : "unknown");
	fputs(", \"version\": ", f);
	json_str(f, ver ? (const char *)ver : "unknown");
	fputs("},\n", f);
	write_machine(f);
	fprintf(f, "  \"run\": {\"scene\": \"%s\", \"size\": ", rs->scene);
	json_str(f, rs->size);
	fprintf(f, ", \"grid\": %d, \"frames\": %zu, \"first_frame_ms\": %.3f, \"fps\": %.3f},\n", rs->grid, rs->n,
		rs->ft[0], total > 0 ? 1e3 * (double)n / total : 0.0);
	json_hitches(f, rs->ft, rs->n); /* before json_dist sorts the times */
	fputs(",\n", f);
	json_dist(f, "frame_ms", rs->ft + first, n);
	fputs(",\n", f);
	json_dist(f, "update_ms", rs->up + first, n);
	fputs(",\n", f);
	json_dist(f, "draw_ms", rs->dr + first, n);
	fprintf(f, ",\n  \"triangles\": %llu, \"extractions\": %llu, \"blocks_generated\": %llu, \"blocks_evicted\": %llu, "
		   "\"blocks_drawn\": %d,\n",
		c.triangles, c.extractions, c.blocks_generated, c.blocks_evicted, c.blocks_drawn);
	fprintf(f, "  \"blocks_probed\": %llu, \"blocks_skipped\": %llu,\n", c.blocks_probed, c.blocks_skipped);
	fputs("  \"governor\": ", f);
	json_str(f, rs->status);
	/* what the governor held on average (quality, beside the times) */
	if (c.governed)
		fprintf(f,
			",\n  \"held\": {\"render_scale\": %.3f, \"view_distance\": %.3f, \"near_lod\": %.3f, "
			"\"level_at_end\": %d}",
			c.held_scale, c.held_view, c.held_near_lod, c.held_level);
	else
		fputs(",\n  \"held\": null", f);
	fputs(",\n  \"power\": {\"battery_percent\": ", f);
	if (rs->battery_percent >= 0)
		fprintf(f, "%d", rs->battery_percent);
	else
		fputs("null", f);
	fputs(", \"battery_status\": ", f);
	json_str(f, rs->battery_percent >= 0 ? rs->battery_status : "none");
	fprintf(f, ", \"low_power\": %s, \"low_power_frames\": %lu, \"frame_cap_fps\": %.3f}", rs->low_power ? "true" : "false",
		rs->low_power_frames, rs->cap_fps);
	fputs("\n}\n", f);
}

static int results_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	struct results_sink *rs = (struct results_sink *)s;
	if (!rs->path[0] || !end->ok || rs->n == 0)
		return 0; /* a failed run leaves no results (and a previous file as it was) */
	/* stdout is a stream: written here, after the run went well */
	if (!strcmp(rs->path, "-")) {
		write_json(rs, stdout, end);
		if (fflush(stdout) != 0 || ferror(stdout)) {
			snprintf(err, errlen, "cannot write the results to standard output");
			return -1;
		}
		return 0;
	}
	if (atomic_open(&rs->af, rs->path, err, errlen) < 0)
		return -1;
	write_json(rs, rs->af.f, end);
	if (atomic_close(&rs->af, rs->path, err, errlen) < 0)
		return -1;
	rs->staged = true;
	return 0;
}

static int results_commit(struct sink *s, char *err, size_t errlen)
{
	struct results_sink *rs = (struct results_sink *)s;
	if (!rs->staged)
		return 0;
	rs->staged = false;
	return atomic_commit(&rs->af, rs->path, err, errlen);
}

static void results_destroy(struct sink *s)
{
	struct results_sink *rs = (struct results_sink *)s;
	atomic_abort(&rs->af); /* a staged file never committed */
	free(rs->ft);
	free(rs->up);
	free(rs->dr);
	free(rs);
}

static const struct sink_ops results_ops = {
	.frame = results_frame, .finish = results_finish, .commit = results_commit, .destroy = results_destroy
};

struct sink *sink_results_open(const struct params *p, bool headless, char *err, size_t errlen)
{
	if (!strcmp(p->results, "-") && !strcmp(p->out, "-")) {
		snprintf(err, errlen, "--results - and --out - both want standard output");
		return NULL;
	}
	struct results_sink *rs = calloc(1, sizeof(*rs));
	if (!rs) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	rs->base.ops = &results_ops;
	snprintf(rs->path, sizeof(rs->path), "%s", p->results);
	rs->report_every = headless ? p->fps_report : 0.0;
	rs->t_open = rs->t_prev = rs->t_report = clock_ms();
	snprintf(rs->scene, sizeof(rs->scene), "%s", p->scene == SCENE_WORLD ? "world" : "volume");
	snprintf(rs->size, sizeof(rs->size), "%s", p->size);
	rs->grid = p->grid;
	return &rs->base;
}
