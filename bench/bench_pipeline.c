/* isoterra — pipeline benchmark.
 *
 * For 64^3, 128^3 and 256^3 cells (7 octaves, the GPU Gems density with ALU
 * Perlin noise): the bare density pass, the full pipeline (density +
 * HistoPyramid extraction), their ratio, Mvoxels/s and triangles/s; then the
 * same field through the three compaction methods (HistoPyramid, atomic
 * append, none) and the two noise sources (ALU, 16^3 textures), all as
 * ratios against a baseline measured in the same run.
 *
 * usage: bench_pipeline [--quick] [--platform NAME] [--sizes 64,128,256]
 * Times are wall-clock around glFinish(), median of repeated runs. */
#include "app.h"
#include "bench.h"
#include "terrain.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum what { DENSITY_ONLY, FULL };

/* median ms of repeated runs (at least min_reps, until ~budget ms) */
static double time_runs(struct pipeline *pl, const struct params *p, enum what w, int min_reps, double budget)
{
	double t[64];
	int n = 0;
	double start = clock_ms();
	/* warm-up (shader JIT, first-touch of buffers) */
	if (w == DENSITY_ONLY)
		bench_density(pl, p);
	else
		bench_run(pl, p);
	glFinish();
	while (n < 64 && (n < min_reps || clock_ms() - start < budget)) {
		double t0 = clock_ms();
		int rc = w == DENSITY_ONLY ? bench_density(pl, p) : bench_run(pl, p);
		glFinish();
		if (rc < 0)
			return -1;
		t[n++] = clock_ms() - t0;
	}
	qsort(t, (size_t)n, sizeof(double), bench_cmp_double);
	return t[n / 2];
}

/* Default parameters at grid size n (octaves: 0 keeps the default's) and
 * their pipeline; NULL with err when it cannot be created. */
static struct pipeline *open_pipeline(struct params *p, struct grid *g, int n, int octaves, const struct field *f,
				      char *err, size_t errlen)
{
	params_defaults(p);
	if (octaves)
		p->octaves = octaves;
	p->grid = n;
	grid_from_params(g, p);
	return pipeline_create(g, p, f, err, errlen);
}

/* Fixed field at grid size n: density pass, full pipeline and, from one
 * profiled run, where the time goes (written to breakdown). */
static void measure_size(const struct field *f, int n, double budget, char *breakdown, size_t len)
{
	char err[512];
	struct params p;
	struct grid g;
	struct pipeline *pl = open_pipeline(&p, &g, n, 7, f, err, sizeof(err));
	if (!pl) {
		printf("%-6d n/a: %s\n", n, err);
		return;
	}
	double td = time_runs(pl, &p, DENSITY_ONLY, 3, budget);
	double tf = time_runs(pl, &p, FULL, 3, budget);
	/* one profiled run: where the time goes */
	double ms[PASS_COUNT];
	pipeline_profile(pl, true, NULL);
	bench_run(pl, &p);
	glFinish();
	pipeline_profile(pl, false, ms);
	snprintf(breakdown, len, "%-6d density %8.2f  classify %8.2f  reduce+setup %8.2f  vertices %8.2f  indices %8.2f",
		 n, ms[PASS_DENSITY], ms[PASS_CLASSIFY], ms[PASS_REDUCE], ms[PASS_VERTICES], ms[PASS_INDICES]);
	struct extract_stats st;
	pipeline_read_stats(pl, &st);
	double vox = (double)g.nx * g.ny * g.nz;
	printf("%-6d %12.2f %12.2f %8.3f %10.1f %12.2f %10u%s\n", n, td, tf, tf / td, vox / (tf * 1e3),
	       st.triangles / (tf * 1e3), st.triangles, st.overflow ? " (overflow)" : "");
	pipeline_destroy(pl);
}

/* The same field at grid gsz through the three compaction methods. */
static void measure_compaction(const struct field *f, int gsz, double budget)
{
	char err[512];
	struct params p;
	struct grid g;
	struct pipeline *pl = open_pipeline(&p, &g, gsz, 7, f, err, sizeof(err));
	if (!pl) {
		printf("  %d^3: n/a: %s\n", gsz, err);
		return;
	}
	double base = 0;
	const char *names[] = { "histopyramid", "atomic-append", "none (15 verts/cell)" };
	for (int m = 0; m < 3; m++) {
		p.compaction = m;
		double t = time_runs(pl, &p, FULL, 3, budget);
		struct extract_stats st;
		pipeline_read_stats(pl, &st);
		if (t < 0) {
			printf("  %d^3 %-22s n/a (buffer over the GL limit)\n", gsz, names[m]);
			continue;
		}
		if (m == 0)
			base = t;
		printf("  %d^3 %-22s %10.2f ms  ratio %6.3f  drawn triangles %u\n", gsz, names[m], t, t / base,
		       st.triangles);
	}
	pipeline_destroy(pl);
}

/* The density pass with ALU noise and with 16^3 noise textures. */
static void measure_noise(const struct field *f, int n, double budget)
{
	char err[512];
	struct params p;
	struct grid g;
	struct pipeline *pl = open_pipeline(&p, &g, n, 0, f, err, sizeof(err));
	if (!pl)
		return;
	double ta = time_runs(pl, &p, DENSITY_ONLY, 3, budget);
	p.noise = NOISE_TEXTURE;
	double tt = time_runs(pl, &p, DENSITY_ONLY, 3, budget);
	printf("  alu (improved Perlin)   %10.2f ms  ratio 1.000\n", ta);
	printf("  texture (16^3 volumes)  %10.2f ms  ratio %.3f\n", tt, tt / ta);
	pipeline_destroy(pl);
}

int main(int argc, char **argv)
{
	const char *plat_name = "auto";
	int quick = 0;
	int sizes[8] = { 64, 128, 256 }, nsizes = 3;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--quick"))
			quick = 1;
		else if (!strcmp(argv[i], "--platform") && i + 1 < argc)
			plat_name = argv[++i];
		else if (!strcmp(argv[i], "--sizes") && i + 1 < argc) {
			nsizes = 0;
			for (char *s = strtok(argv[++i], ","); s && nsizes < 8; s = strtok(NULL, ","))
				sizes[nsizes++] = atoi(s);
		} else {
			fprintf(stderr, "usage: %s [--quick] [--platform NAME] [--sizes 64,128,256]\n", argv[0]);
			return 2;
		}
	}
	struct platform *plat = bench_open(plat_name, 64, 64);
	if (!plat)
		return 1;
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	const struct field *f = terrain_field(tr);
	printf("field: GPU Gems density, 7 octaves, ALU Perlin noise, default volume\n\n");
	double budget = quick ? 300 : 2000;

	char breakdown[8][160];
	memset(breakdown, 0, sizeof(breakdown));
	printf("%-6s %12s %12s %8s %10s %12s %10s\n", "grid", "density ms", "full ms", "ratio", "Mvox/s", "Mtris/s",
	       "triangles");
	for (int s = 0; s < nsizes; s++)
		measure_size(f, sizes[s], budget, breakdown[s], sizeof(breakdown[s]));

	printf("\nper pass (ms, one run with glFinish after every pass):\n");
	for (int s = 0; s < nsizes; s++)
		if (breakdown[s][0])
			printf("  %s\n", breakdown[s]);

	int cmp_grid = quick ? 64 : 128;
	printf("\ncompaction methods, same field, grid %d^3 (ratio = time / HistoPyramid time):\n", cmp_grid);
	for (int gsz = 64; gsz <= cmp_grid; gsz *= 2)
		measure_compaction(f, gsz, budget);

	printf("\nnoise source, density pass, grid %d^3, 9 octaves (ratio = time / ALU time):\n", cmp_grid);
	measure_noise(f, cmp_grid, budget);
	terrain_destroy(tr);
	edits_destroy(ed);
	platform_close(plat);
	return 0;
}
