/* isoterra — the pipeline benchmark's measuring machinery, shared by
 * bench_pipeline.c (isoterra's passes) and pipeline_peers.c (libnoise and
 * VTK on the same field and grid).
 *
 * A series is one thing timed again and again (isoterra's density pass, its
 * whole pipeline, libnoise's volume, ...).  Series are run in rounds: one
 * run of every series per round, so a change of load on the shared machine
 * hits all of them alike; each gets one untimed warm-up run first (shader
 * JIT, first touch of buffers, thread start-up). */
#ifndef ISOTERRA_BENCH_PIPELINE_H
#define ISOTERRA_BENCH_PIPELINE_H

#include <stdbool.h>

#include "bench.h"
#include "params.h"
#include "pipeline.h"

#define MAX_RUNS 64

struct run_sample {
	double wall, cpu;         /* ms: wall clock around glFinish, process CPU time */
	double pass[PASS_COUNT];  /* ms per pass (profiled isoterra runs only) */
};

enum series_mode { S_DENSITY, S_FULL, S_PROFILED };

struct series {
	const char *name;
	/* one run: 0, or -1 (the series is dropped with its reason printed) */
	int (*run)(struct series *s, struct run_sample *out);
	/* isoterra's series: a pipeline, the parameters, what is run */
	struct pipeline *pl;
	struct params p;
	enum series_mode mode;
	/* a peer's: its context and which of its volumes */
	void *ctx;
	int k;
	/* results: runs, and the output of the warm-up run */
	struct run_sample r[MAX_RUNS];
	int n;
	bool failed;
	long triangles, vertices;
};

/* What a statistic is taken of: wall, CPU, one pass, or the passes after
 * the density pass together. */
enum { V_WALL = -1, V_CPU = -2, V_AFTER_DENSITY = -3 };
/* 0..PASS_COUNT-1: that pass's wall ms */

void series_rounds(struct series *const *s, int ns, int runs);
struct bench_stat series_stat(const struct series *s, int what);

/* ---- peers (pipeline_peers.c) ---------------------------------------- */
struct peers;
/* The peers of field p on grid g (pipeline pl: isoterra's density volume is
 * read back for VTK): their series appended to s[*ns..] (at most
 * PEER_SERIES), threads each.  Prints why a peer is skipped; NULL when none
 * runs. */
#define PEER_SERIES 3
struct peers *peers_open(const struct params *p, const struct grid *g, struct pipeline *pl, int threads,
			 struct series **s, int *ns);
/* The peers' figures and the ratios isoterra / peer: density pass vs
 * libnoise, the passes after density vs flying edges, the whole pipeline
 * vs libnoise + flying edges; iso_* are isoterra's series without AO. */
void peers_report(const struct peers *pe, const struct series *iso_density, const struct series *iso_profiled,
		  const struct series *iso_full);
void peers_close(struct peers *pe);

/* ---- one-shot (pipeline_oneshot.c) -------------------------------------- */
/* The program (ISOTERRA_PROGRAM) with isoterra's flags (flags[1..nflags-1])
 * as whole processes at --grid `grid` and --grid 2, runs rounds
 * interleaved: wall, CPU, page faults and the first frame's update and
 * draw, and their differences against loop_ms, the loop's whole pipeline
 * (<= 0: no ratios). */
void measure_oneshot(char *const *flags, int nflags, int grid, int runs, double loop_ms);

#endif
