/* isoterra — what every benchmark shares (the clock is app/clock.h's): a comparator
 * for medians and percentiles, and the machine line printed at the top of
 * every report (numbers mean nothing without it). */
#ifndef ISOTERRA_BENCH_H
#define ISOTERRA_BENCH_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "clock.h"
#include "gpu.h"
#include "log.h"
#include "platform.h"
#include "pipeline.h"

/* The extraction engine's passes, the reason printed on failure: 0 or -1. */
static inline int bench_report(int rc, const char *pass, const char *err)
{
	if (rc < 0 && err[0])
		fprintf(stderr, "%s: %s\n", pass, err);
	return rc;
}

static inline int bench_run(struct pipeline *pl, const struct params *p)
{
	char err[512];
	return bench_report(pipeline_run(pl, p, err, sizeof(err)), "pipeline_run", err);
}

static inline int bench_density(struct pipeline *pl, const struct params *p)
{
	char err[512];
	return bench_report(pipeline_density(pl, p, err, sizeof(err)), "pipeline_density", err);
}

static inline int bench_cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

/* The spread of repeated measurements: median, minimum, maximum of n. */
struct bench_stat {
	double med, min, max;
	int n;
};

static inline struct bench_stat bench_stat_of(const double *v, int n)
{
	struct bench_stat s = { 0, 0, 0, 0 };
	double t[256];
	if (n > 256)
		n = 256;
	if (n <= 0)
		return s;
	memcpy(t, v, (size_t)n * sizeof(double));
	qsort(t, (size_t)n, sizeof(double), bench_cmp_double);
	s.med = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
	s.min = t[0];
	s.max = t[n - 1];
	s.n = n;
	return s;
}

/* "median [min-max]" with the given decimals, into buf (returned). */
static inline const char *bench_stat_str(struct bench_stat s, int decimals, char *buf, size_t len)
{
	snprintf(buf, len, "%.*f [%.*f-%.*f]", decimals, s.med, decimals, s.min, decimals, s.max);
	return buf;
}

/* This process's CPU time in ms (llvmpipe's threads included). */
static inline double bench_cpu_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* The 1-minute load average (-1 when unknown): a shared machine's numbers
 * are read with it. */
static inline double bench_loadavg(void)
{
	double l = -1;
	FILE *f = fopen("/proc/loadavg", "r");
	if (f) {
		if (fscanf(f, "%lf", &l) != 1)
			l = -1;
		fclose(f);
	}
	return l;
}

/* A program run as a user runs it (bench_spawn): wall ms to its exit, its
 * CPU ms (user + system), peak RSS (MB) and minor page faults. */
struct bench_child {
	double wall_ms, cpu_ms, rss_mb;
	long minflt;
};

/* Runs program with args (args[0] its name, NULL-terminated), its stderr
 * to /dev/null, $XDG_CACHE_HOME set to cache unless NULL (Mesa's shader
 * cache and isoterra's program cache), and waits for it: 0 when it exited
 * with 0 (c filled), else -1. */
static inline int bench_spawn(const char *program, char *const *args, const char *cache, struct bench_child *c)
{
	double t0 = clock_ms();
	pid_t pid = fork();
	if (pid == 0) {
		if (cache)
			setenv("XDG_CACHE_HOME", cache, 1);
		if (!freopen("/dev/null", "w", stderr))
			_exit(127);
		execv(program, args);
		_exit(127);
	}
	int status = 0;
	struct rusage ru;
	if (pid < 0 || wait4(pid, &status, 0, &ru) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
		return -1;
	c->wall_ms = clock_ms() - t0;
	c->cpu_ms = (double)(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) * 1e3 +
		    (double)(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec) / 1e3;
	c->rss_mb = (double)ru.ru_maxrss / 1024.0;
	c->minflt = ru.ru_minflt;
	return 0;
}

/* A small text file (a run's --results) into buf, NUL-terminated; "" when
 * it cannot be read. */
static inline void bench_read_text(const char *path, char *buf, size_t len)
{
	FILE *f = fopen(path, "r");
	size_t n = f ? fread(buf, 1, len - 1, f) : 0;
	if (f)
		fclose(f);
	buf[n] = 0;
}

/* "machine: CPU model, N cores, load average L" and "GL: renderer | version". */
static inline void bench_print_machine(const struct gpu_caps *caps)
{
	char cpu[256] = "unknown CPU";
	FILE *f = fopen("/proc/cpuinfo", "r");
	if (f) {
		char line[512];
		while (fgets(line, sizeof(line), f))
			if (!strncmp(line, "model name", 10)) {
				char *c = strchr(line, ':');
				if (c) {
					snprintf(cpu, sizeof(cpu), "%s", c + 2);
					cpu[strcspn(cpu, "\n")] = 0;
				}
				break;
			}
		fclose(f);
	}
	printf("machine: %s, %ld cores, load average %.2f at the start\n", cpu, sysconf(_SC_NPROCESSORS_ONLN),
	       bench_loadavg());
	printf("GL: %s | %s\n", caps->renderer, caps->version);
}

/* The GL context every benchmark runs in: the platform (auto, device,
 * surfaceless, or a display at w x h), GLES 3.1 checked, the machine line
 * printed; x11_present: how frames reach an X11 window
 * (PLATFORM_X11_PRESENT_*; bench_open: auto).  NULL after one line on
 * stderr. */
static inline struct platform *bench_open_present(const char *plat_name, int w, int h, int x11_present)
{
	char err[512];
	log_set_level(LOG_WARN);
	struct platform_options po = { .name = plat_name, .width = w, .height = h, .x11_present = x11_present };
	struct platform *plat = platform_open(&po, err, sizeof(err));
	struct gpu_caps caps;
	if (plat && gpu_init(&caps, false, err, sizeof(err)) == 0) {
		bench_print_machine(&caps);
		return plat;
	}
	fprintf(stderr, "bench: %s\n", err);
	platform_close(plat);
	return NULL;
}

static inline struct platform *bench_open(const char *plat_name, int w, int h)
{
	return bench_open_present(plat_name, w, h, PLATFORM_X11_PRESENT_AUTO);
}

#endif
