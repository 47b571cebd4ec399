/* isoterra — curves benchmark: the 2D displacement map of Nascimento (2020)
 * ch. 9 on the GPU (shaders/curve_bake.comp).
 *
 * Terrain 2048 x 2048 world units, map 2048² texels, w = 15, λ = 15, the
 * thesis's dataset shapes (generated, seeded):
 *   A  3 paths dispersed over the terrain, 84 quadratics
 *   B  the same 3 paths concentrated in the bottom-right 512² corner
 *   C  one path across the whole terrain, 198 quadratics
 * Each dataset: the closed-form closest point through the 16² spatial hash
 * ("analytic+hash", fastest of repeated bakes) against the iterative
 * baseline (every curve as 32 line segments, no hash) in the same run, and
 * the ratio.  Then dataset C with other hash sizes.
 *
 * usage: bench_curves [--quick] [--platform NAME] [--res N]
 * Times are wall-clock around glFinish(); the CPU stages (curve pipeline,
 * hash build) are timed separately. */
#include "app.h"

#include <math.h>
#include "bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static double last_cpu; /* CPU ms of the fastest repetition of the last time_bake() */

static uint32_t rng = 2020u;
static float frand(void)
{
	rng = rng * 1664525u + 1013904223u;
	return (float)(rng >> 8) / 16777216.0f;
}

#define TERRAIN 2048.0f

/* A wandering path of n points from (x0, z0) heading to (x1, z1). */
static int add_path(struct curve_set *s, int n, float x0, float z0, float x1, float z1, float jitter)
{
	float *pts = malloc(sizeof(float) * 3 * (size_t)n);
	if (!pts)
		return -1;
	for (int i = 0; i < n; i++) {
		float t = (float)i / (float)(n - 1);
		float dx = x1 - x0, dz = z1 - z0, len = sqrtf(dx * dx + dz * dz);
		float off = (i == 0 || i == n - 1) ? 0.0f : (frand() - 0.5f) * jitter;
		pts[3 * i] = x0 + dx * t - dz / len * off;
		pts[3 * i + 1] = 40.0f * sinf(6.0f * t) + 20.0f * frand();
		pts[3 * i + 2] = z0 + dz * t + dx / len * off;
	}
	struct curve_path p;
	memset(&p, 0, sizeof(p));
	curve_path_defaults(&p, CURVE_ROAD);
	p.width = 15.0f;
	p.falloff = 15.0f;
	p.smoothing = 0.5f;
	p.npts = n;
	p.pts = pts;
	snprintf(p.label, sizeof(p.label), "bench path %d", s->npaths + 1);
	int rc = curve_set_add(s, &p);
	free(pts);
	return rc;
}

static void dataset(char which, struct curve_set *s)
{
	memset(s, 0, sizeof(*s));
	rng = 2020u;
	if (which == 'C') {
		add_path(s, 100, 20.0f, 30.0f, TERRAIN - 30.0f, TERRAIN - 20.0f, 300.0f); /* 99 cubics, 198 quadratics */
		return;
	}
	/* 3 paths of 15 points: 3 x 14 cubics x 2 = 84 quadratics */
	float sc = which == 'A' ? 1.0f : 0.25f, ox = which == 'A' ? 0.0f : TERRAIN * 0.75f;
	add_path(s, 15, ox + sc * 60, ox + sc * 200, ox + sc * 1990, ox + sc * 500, sc * 250.0f);
	add_path(s, 15, ox + sc * 150, ox + sc * 1900, ox + sc * 1800, ox + sc * 1200, sc * 250.0f);
	add_path(s, 15, ox + sc * 1000, ox + sc * 40, ox + sc * 900, ox + sc * 2000, sc * 250.0f);
}

/* best (minimum) ms of repeated bakes (at least min_reps, until ~budget ms):
 * the machine may be shared, the minimum is the least disturbed run */
static double time_bake(struct edits *ed, const struct params *p, const struct bake_opts *o, int min_reps, double budget)
{
	char err[512];
	double t[64];
	int n = 0;
	if (curves_bake(ed, p, o, NULL, err, sizeof(err)) < 0) { /* warm-up: compile, upload, first touch */
		fprintf(stderr, "bench: %s\n", err);
		return -1;
	}
	glFinish();
	double start = clock_ms();
	double best = 1e300;
	last_cpu = 0;
	while (n < 64 && (n < min_reps || clock_ms() - start < budget)) {
		double t0 = clock_ms(), c0 = bench_cpu_ms();
		int rc = curves_bake(ed, p, o, NULL, err, sizeof(err));
		glFinish();
		if (rc < 0) {
			fprintf(stderr, "bench: %s\n", err);
			return -1;
		}
		t[n] = clock_ms() - t0;
		if (t[n] < best) {
			best = t[n];
			last_cpu = bench_cpu_ms() - c0;
		}
		n++;
	}
	qsort(t, (size_t)n, sizeof(double), bench_cmp_double);
	return t[0];
}

static const char *const shapes[3] = { "3 paths dispersed", "3 paths concentrated (bottom-right 512^2)",
				      "1 path across the terrain" };

/* Dataset 'A' + d: building the curves, then analytic (with its CPU time),
 * dense and iterative bakes; one table row.  -1 when the curves cannot be
 * built, 1 when a bake failed, else 0. */
static int measure_dataset(struct edits *ed, int d, const struct params *p, struct bake_opts *o, double budget)
{
	char err[512];
	struct curve_set s;
	dataset((char)('A' + d), &s);
	double t0 = clock_ms();
	if (edits_set_curves(ed, &s, 16, err, sizeof(err)) < 0) {
		fprintf(stderr, "bench: %s\n", err);
		return -1;
	}
	double build_ms = clock_ms() - t0;
	const struct edits *e = ed;
	o->iterative = false;
	double ta = time_bake(ed, p, o, 3, budget);
	double ca = last_cpu;
	o->dense = true;
	double td = time_bake(ed, p, o, 2, budget / 3);
	o->dense = false;
	o->iterative = true;
	double ti = time_bake(ed, p, o, 1, 0);
	o->iterative = false;
	printf("%-3c %-40s %6d %9.2f %9d %12.1f %9.1f %10.1f %14.1f %7.1fx\n", 'A' + d, shapes[d], e->quads.nquads,
	       build_ms, e->hash.nindex, ta, ca, td, ti, ti / ta);
	curve_set_free(&s);
	return ta < 0 || ti < 0 || td < 0 ? 1 : 0;
}

/* Dataset C, analytic, through hashes of 1 (not above 512^2 texels) to 64^2
 * cells.  0, or -1 when the curves cannot be built. */
static int measure_hash_sizes(struct edits *ed, const struct params *p, struct bake_opts *o, int res, double budget)
{
	char err[512];
	struct curve_set s;
	dataset('C', &s);
	int dims[5] = { 1, 8, 16, 32, 64 };
	o->iterative = false;
	for (int i = 0; i < 5; i++) {
		if (dims[i] == 1 && res > 512)
			continue; /* every curve at every texel: minutes at 2048^2 on llvmpipe */
		if (edits_set_curves(ed, &s, dims[i], err, sizeof(err)) < 0) {
			fprintf(stderr, "bench: %s\n", err);
			return -1;
		}
		const struct edits *e = ed;
		double t = time_bake(ed, p, o, 3, budget / 2);
		printf("  hash %2dx%-2d  %8.1f ms (cpu %7.1f)   entries %5d   max per cell %3d\n", dims[i], dims[i], t,
		       last_cpu, e->hash.nindex, e->hash.max_per_cell);
	}
	curve_set_free(&s);
	return 0;
}

int main(int argc, char **argv)
{
	const char *plat_name = "auto";
	int quick = 0, res = 2048;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--quick"))
			quick = 1;
		else if (!strcmp(argv[i], "--platform") && i + 1 < argc)
			plat_name = argv[++i];
		else if (!strcmp(argv[i], "--res") && i + 1 < argc)
			res = atoi(argv[++i]);
		else {
			fprintf(stderr, "usage: %s [--quick] [--platform NAME] [--res N]\n", argv[0]);
			return 2;
		}
	}
	if (quick)
		res = res > 512 ? 512 : res;
	if (res < 8 || res > 8192) {
		fprintf(stderr, "bench: --res %d out of range 8..8192\n", res);
		return 2;
	}
	struct platform *plat = bench_open(plat_name, 64, 64);
	if (!plat)
		return 1;
	char err[512];
	struct edits *ed = edits_create();
	printf("displacement map %dx%d over %gx%g world units, w = 15, lambda = 15, hash 16x16, iterative baseline: 32 "
	       "line segments per curve, no hash\n\n",
	       res, res, (double)TERRAIN, (double)TERRAIN);
	struct params p;
	params_defaults(&p);
	struct bake_opts o = { { res, res }, { 0.0f, 0.0f }, { TERRAIN, TERRAIN }, false, false };
	double budget = quick ? 500 : 3000;
	int status = 0;

	{
		struct curve_set none = { .paths = NULL, .npaths = 0 };
		edits_set_curves(ed, &none, 16, err, sizeof(err));
		printf("floor: the same dispatch with no curves: %.1f ms\n\n", time_bake(ed, &p, &o, 3, budget / 2));
	}
	printf("analytic = closed form + hash over the 8x8 tiles that overlap a padded box; dense = the same, every texel;\n"
	       "ratio = iterative / analytic\n");
	printf("(times: the fastest of the repetitions, wall clock; \"(cpu)\" = the process's CPU time for that bake,\n"
	       " llvmpipe's threads included: on an idle machine wall ~ cpu / cores)\n");
	printf("%-3s %-40s %6s %9s %9s %12s %9s %10s %14s %8s\n", "set", "shape", "quads", "build ms", "entries",
	       "analytic ms", "(cpu)", "dense ms", "iterative ms", "ratio");
	int rc = 0;
	for (int d = 0; d < 3; d++) {
		rc = measure_dataset(ed, d, &p, &o, budget);
		if (rc < 0)
			break;
		if (rc > 0)
			status = 1;
	}

	printf("\ndataset C, analytic, by hash size (entries = cell list length; max = longest cell list):\n");
	if (rc < 0 || measure_hash_sizes(ed, &p, &o, res, budget) < 0)
		status = 1;
	printf("\nload average %.2f at the end\n", bench_loadavg());
	edits_destroy(ed);
	platform_close(plat);
	return status;
}
