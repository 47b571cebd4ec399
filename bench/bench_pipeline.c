/* isoterra — pipeline benchmark.
 *
 * The field comes from isoterra's own flags (everything after --, and every
 * option the bench does not know, parsed by cli_parse), so a comparison on
 * a given field is one command.  On that field and grid (--grid):
 *
 *  1. every pass apart (density, classify, pyramid = reduce + setup,
 *     vertices, indices; pipeline_profile: glFinish after every pass), with
 *     the flags' ambient occlusion and without it; AO = the vertex pass
 *     with AO and the sun's shadows minus without;
 *  2. whole runs: the density pass alone (and with every sample whole:
 *     --no-density-cut), the whole pipeline with and without AO and
 *     shadows, with the
 *     process's CPU time;
 *  3. the peers, when installed (bench/peer.h): libnoise's Perlin module as
 *     the same fBm, VTK's flying edges on the same volume;
 *  4. the compaction methods with identical work (AO and shadows off on
 *     all three: only the HistoPyramid path has them);
 *  5. the noise sources (ALU, 16^3 textures) for the density pass;
 *  6. with --sizes, density, whole pipeline and compaction methods at
 *     other grid sizes;
 *  7. one-shot: the program itself, whole processes, at the flags' grid
 *     against grid 2: what one extraction costs outside the loop
 *     (pipeline_oneshot.c; --no-oneshot leaves it out).
 *
 * Wall time around glFinish(), median [min-max] of the runs; series are
 * interleaved in rounds (bench_pipeline.h).  The load average is printed
 * at the start and at the end.
 *
 * usage: bench_pipeline [--quick] [--runs N] [--sizes 64,128] [--peer-threads N]
 *                       [--no-peers] [--no-oneshot] [--] [isoterra flags]
 * e.g.   bench_pipeline -- --preset fbm --octaves 7 --warp-amp 0 --noise-y-scale 1 --grid 128 */
#include "app.h"
#include "bench.h"
#include "bench_pipeline.h"
#include "terrain.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

struct options {
	int quick, runs, threads, peers, oneshot;
	int sizes[8], nsizes;
	int argc;          /* isoterra's flags, argv[0] = "isoterra" */
	char *argv[256];
};

static void usage(const char *argv0)
{
	printf("usage: %s [--quick] [--runs N] [--sizes 64,128] [--peer-threads N] [--no-peers] [--no-oneshot] [--]\n"
	       "       [isoterra flags]\n"
	       "  --quick            5 runs per series (default 9), no noise-source table\n"
	       "  --runs N           runs per series (at least 5)\n"
	       "  --sizes LIST       also density, whole pipeline and compaction at these grids\n"
	       "  --peer-threads N   libnoise and VTK threads (default 2)\n"
	       "  --no-peers         skip libnoise and VTK\n"
	       "  --no-oneshot       skip the one-shot row (the program as whole processes, --grid N against 2)\n"
	       "Everything else (and everything after --) is isoterra's own flags: the field,\n"
	       "--grid, --platform, ... (isoterra --help).\n",
	       argv0);
}

/* The bench's options; the rest into o->argv for cli_parse.  0 to run, 1
 * to exit with 0, 2 on a usage error. */
static int parse_options(int argc, char **argv, struct options *o)
{
	memset(o, 0, sizeof(*o));
	o->threads = 2;
	o->peers = 1;
	o->oneshot = 1;
	o->argv[o->argc++] = "isoterra";
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		bool has_val = i + 1 < argc;
		if (o->argc >= 255)
			return 2;
		if (!strcmp(a, "--")) {
			while (++i < argc && o->argc < 255)
				o->argv[o->argc++] = argv[i];
		} else if (!strcmp(a, "--quick")) {
			o->quick = 1;
		} else if (!strcmp(a, "--no-peers")) {
			o->peers = 0;
		} else if (!strcmp(a, "--no-oneshot")) {
			o->oneshot = 0;
		} else if (!strcmp(a, "--runs") && has_val) {
			o->runs = atoi(argv[++i]);
		} else if (!strcmp(a, "--peer-threads") && has_val) {
			o->threads = atoi(argv[++i]);
		} else if (!strcmp(a, "--sizes") && has_val) {
			for (char *s = strtok(argv[++i], ","); s && o->nsizes < 8; s = strtok(NULL, ","))
				o->sizes[o->nsizes++] = atoi(s);
		} else if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
			usage(argv[0]);
			return 1;
		} else {
			o->argv[o->argc++] = argv[i];
		}
	}
	if (!o->runs)
		o->runs = o->quick ? 5 : 9;
	if (o->runs < 5 || o->runs > MAX_RUNS || o->threads < 1) {
		fprintf(stderr, "bench_pipeline: --runs 5..%d, --peer-threads 1 or more\n", MAX_RUNS);
		return 2;
	}
	return 0;
}

/* ---- series (bench_pipeline.h) ------------------------------------------ */

static int run_isoterra(struct series *s, struct run_sample *o)
{
	memset(o, 0, sizeof(*o));
	if (s->mode == S_PROFILED)
		pipeline_profile(s->pl, true, NULL);
	double t0 = clock_ms(), c0 = bench_cpu_ms();
	int rc = s->mode == S_DENSITY ? bench_density(s->pl, &s->p) : bench_run(s->pl, &s->p);
	glFinish();
	o->wall = clock_ms() - t0;
	o->cpu = bench_cpu_ms() - c0;
	if (s->mode == S_PROFILED)
		pipeline_profile(s->pl, false, o->pass);
	struct extract_stats st;
	if (rc == 0 && s->mode != S_DENSITY && s->triangles < 0 && pipeline_read_stats(s->pl, &st) == 0) {
		s->triangles = st.triangles;
		s->vertices = st.vertices;
		if (st.overflow)
			printf("  %s: output clamped to the capacity (raise --max-triangles)\n", s->name);
	}
	return rc;
}

static void isoterra_series(struct series *s, const char *name, struct pipeline *pl, const struct params *p,
			    enum series_mode mode)
{
	memset(s, 0, sizeof(*s));
	s->name = name;
	s->run = run_isoterra;
	s->pl = pl;
	s->p = *p;
	s->mode = mode;
	s->triangles = s->vertices = -1;
}

void series_rounds(struct series *const *s, int ns, int runs)
{
	struct run_sample warm;
	for (int i = 0; i < ns; i++)
		if (s[i]->run(s[i], &warm) < 0) {
			s[i]->failed = true;
			printf("  %s: n/a (failed, see above)\n", s[i]->name);
		}
	bool dots = isatty(STDERR_FILENO); /* progress, one dot a round */
	for (int r = 0; r < runs && r < MAX_RUNS; r++) {
		for (int i = 0; i < ns; i++)
			if (!s[i]->failed && s[i]->run(s[i], &s[i]->r[s[i]->n]) == 0)
				s[i]->n++;
		if (dots)
			fprintf(stderr, ".");
	}
	if (dots)
		fprintf(stderr, "\n");
}

struct bench_stat series_stat(const struct series *s, int what)
{
	double v[MAX_RUNS];
	int n = s->n < MAX_RUNS ? s->n : MAX_RUNS;
	for (int i = 0; i < n; i++) {
		const struct run_sample *r = &s->r[i];
		if (what == V_WALL)
			v[i] = r->wall;
		else if (what == V_CPU)
			v[i] = r->cpu;
		else if (what == V_AFTER_DENSITY)
			v[i] = r->pass[PASS_CLASSIFY] + r->pass[PASS_REDUCE] + r->pass[PASS_VERTICES] + r->pass[PASS_INDICES];
		else
			v[i] = r->pass[what];
	}
	return bench_stat_of(v, n);
}

/* ---- reports -------------------------------------------------------------- */

static void print_field(const struct options *o, const struct params *p)
{
	printf("field: isoterra");
	for (int i = 1; i < o->argc; i++)
		printf(" %s", o->argv[i]);
	printf("%s\n ", o->argc > 1 ? "" : " (the defaults)");
	static const char *const names[] = { "field",	  "shape",	    "fractal",	       "noise",	   "octaves",
					     "noise_freq", "lacunarity",    "hurst",	       "gain",	   "noise_amp",
					     "ground_slope", "seed",	    "warp_amp",	       "floor_strength", "rotated_octaves",
					     "closed",	  "ao_rays",	    "shadows",	       "shadow_steps", "iso" };
	for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
		char v[64];
		params_format(p, params_find(names[i]), v, sizeof(v));
		printf(" %s %s%s", names[i], v, i + 1 < sizeof(names) / sizeof(names[0]) ? "," : "\n");
	}
	struct grid g;
	grid_from_params(&g, p);
	printf("  grid %d x %d x %d cells of %g, from (%g, %g, %g); %ld density samples (corners + margin)\n", g.nx, g.ny,
	       g.nz, g.cell, g.origin[0], g.origin[1], g.origin[2], grid_dens_count(&g));
	if (p->fractal == FRACTAL_FBM)
		printf("  fbm octave weights: lacunarity^-hurst = %.5f per octave\n", pow(p->lacunarity, -p->hurst));
}

/* The vertex pass casts rays (AO, the sun's) for p. */
static bool lit(const struct params *p)
{
	return p->ao_rays > 0 || (p->shadows > 0.0f && p->shadow_steps > 0);
}

static const char *stat_str(const struct series *s, int what, char *buf, size_t len)
{
	if (!s || s->failed || !s->n)
		return "n/a";
	return bench_stat_str(series_stat(s, what), 1, buf, len);
}

/* Per pass, with the flags' AO and sun shadows and without (off may be
 * NULL: both off in the flags already). */
static void print_passes(const struct series *on, const struct series *off, int runs)
{
	static const char *const names[PASS_COUNT] = { "density", "classify", "pyramid (reduce+setup)", "vertices",
						       "indices" };
	char a[64], b[64];
	printf("\nper pass, HistoPyramid (glFinish after every pass), wall ms median [min-max] of %d runs:\n", runs);
	printf("  %-24s %-28s %s\n", "pass", lit(&on->p) ? "AO, shadows as given" : "AO, shadows off (as given)",
	       off ? "off (--ao-rays 0 --shadows 0)" : "");
	for (int k = 0; k < PASS_COUNT; k++)
		printf("  %-24s %-28s %s\n", names[k], stat_str(on, k, a, sizeof(a)), off ? stat_str(off, k, b, sizeof(b)) : "");
	printf("  %-24s %-28s %s\n", "all but density", stat_str(on, V_AFTER_DENSITY, a, sizeof(a)),
	       off ? stat_str(off, V_AFTER_DENSITY, b, sizeof(b)) : "");
	printf("  %-24s %-28s %s\n", "whole run (wall)", stat_str(on, V_WALL, a, sizeof(a)),
	       off ? stat_str(off, V_WALL, b, sizeof(b)) : "");
	printf("  %-24s %-28s %s\n", "whole run (process CPU)", stat_str(on, V_CPU, a, sizeof(a)),
	       off ? stat_str(off, V_CPU, b, sizeof(b)) : "");
	if (off && on->n && off->n) {
		double ao = series_stat(on, PASS_VERTICES).med - series_stat(off, PASS_VERTICES).med;
		printf("  AO (%d rays x (%d short + %d long) steps) and sun (%d steps) = vertex pass with - without "
		       "(medians): %.1f ms, %.0f%% of the run\n",
		       on->p.ao_rays, on->p.ao_short_steps, on->p.ao_long_steps, on->p.shadows > 0 ? on->p.shadow_steps : 0,
		       ao, 100 * ao / series_stat(on, V_WALL).med);
	}
}

/* Whole runs (no glFinish between passes) against the density pass alone;
 * full[0] with the flags' AO, full[1] (if nfull is 2) without. */
static void print_whole(const struct series *dens, const struct series *dens_whole, const struct series *const *full,
			int nfull, const struct grid *g)
{
	char a[64], b[64];
	printf("\nwhole runs (glFinish at the end only), ms median [min-max]; /dens: ratio of the medians to the density pass's:\n");
	printf("  %-28s %-26s %-26s %9s %8s %7s %8s %9s %9s\n", "", "wall", "process CPU", "wall/dens", "CPU/dens",
	       "Mvox/s", "Mtris/s", "triangles", "vertices");
	printf("  %-28s %-26s %-26s\n", "density pass alone", stat_str(dens, V_WALL, a, sizeof(a)),
	       stat_str(dens, V_CPU, b, sizeof(b)));
	if (!dens->n)
		return;
	double dw = series_stat(dens, V_WALL).med, dc = series_stat(dens, V_CPU).med;
	if (dens_whole && dens_whole->n) /* the far samples' cut off: every sample's octaves (docs/PIPELINE.md) */
		printf("  %-28s %-26s %-26s %9.3f %8.3f\n", "  every sample whole", stat_str(dens_whole, V_WALL, a, sizeof(a)),
		       stat_str(dens_whole, V_CPU, b, sizeof(b)), series_stat(dens_whole, V_WALL).med / dw,
		       series_stat(dens_whole, V_CPU).med / dc);
	double vox = (double)g->nx * g->ny * g->nz;
	for (int i = 0; i < nfull; i++) {
		const struct series *s = full[i];
		if (!s->n)
			continue;
		double t = series_stat(s, V_WALL).med;
		printf("  %-28s %-26s %-26s %9.3f %8.3f %7.2f %8.3f %9ld %9ld\n", s->name, stat_str(s, V_WALL, a, sizeof(a)),
		       stat_str(s, V_CPU, b, sizeof(b)), t / dw, series_stat(s, V_CPU).med / dc, vox / (t * 1e3),
		       s->triangles / (t * 1e3), s->triangles, s->vertices);
	}
	if (nfull == 2 && full[0]->n && full[1]->n)
		printf("  AO+sun, process CPU: whole run with - without (medians): %.1f ms\n",
		       series_stat(full[0], V_CPU).med - series_stat(full[1], V_CPU).med);
}

/* ---- measurements ----------------------------------------------------------- */

static struct pipeline *open_pipeline(const struct params *p, struct grid *g, const struct field *f)
{
	char err[512];
	grid_from_params(g, p);
	struct pipeline *pl = pipeline_create(g, p, f, err, sizeof(err));
	if (!pl)
		printf("  grid %d: n/a: %s\n", p->grid, err);
	return pl;
}

/* 1-3: the passes, whole runs and peers at the flags' grid; the whole
 * pipeline's median wall ms with the flags' AO (0: none measured). */
static double measure_grid(const struct params *p, const struct field *f, const struct options *o)
{
	struct grid g;
	struct pipeline *pl = open_pipeline(p, &g, f);
	if (!pl)
		return 0.0;
	struct params off = *p;
	off.ao_rays = 0;
	off.shadows = 0.0f;
	bool ao = lit(p);
	struct params whole = *p;
	whole.density_cut = false;
	struct series dens, dens_whole, full, full_off, prof, prof_off;
	isoterra_series(&dens, "density pass alone", pl, p, S_DENSITY);
	isoterra_series(&dens_whole, "density pass, no cut", pl, &whole, S_DENSITY);
	isoterra_series(&full, ao ? "whole pipeline, AO+sun as given" : "whole pipeline (AO+sun off)", pl, p, S_FULL);
	isoterra_series(&full_off, "whole pipeline, AO+sun off", pl, &off, S_FULL);
	isoterra_series(&prof, "profiled, AO+sun as given", pl, p, S_PROFILED);
	isoterra_series(&prof_off, "profiled, AO+sun off", pl, &off, S_PROFILED);
	struct series *s[6 + PEER_SERIES] = { &dens, &full, &prof };
	int ns = 3;
	if (p->density_cut)
		s[ns++] = &dens_whole;
	if (ao) {
		s[ns++] = &full_off;
		s[ns++] = &prof_off;
	}
	struct peers *pe = o->peers ? peers_open(p, &g, pl, o->threads, s, &ns) : NULL;
	printf("\nmeasuring: %d series x %d runs, interleaved (one run of each per round)\n", ns, o->runs);
	fflush(stdout);
	series_rounds(s, ns, o->runs);
	print_passes(&prof, ao ? &prof_off : NULL, o->runs);
	const struct series *fulls[2] = { &full, &full_off };
	print_whole(&dens, p->density_cut ? &dens_whole : NULL, fulls, ao ? 2 : 1, &g);
	peers_report(pe, &dens, ao ? &prof_off : &prof, ao ? &full_off : &full);
	peers_close(pe);
	pipeline_destroy(pl);
	return full.n ? series_stat(&full, V_WALL).med : 0.0;
}

/* Rows: wall and CPU median [min-max], their medians' ratios to row 0's
 * and, with counts, the triangles and vertices written. */
static void print_ratio_table(const struct series *m, int n, bool counts)
{
	char a[64], b[64];
	printf("  %-40s %-26s %-26s %6s %6s%s\n", "", "wall", "process CPU", "r.wall", "r.CPU",
	       counts ? " triangles  vertices" : "");
	for (int i = 0; i < n; i++) {
		if (!m[i].n || !m[0].n) {
			printf("  %-40s n/a\n", m[i].name);
			continue;
		}
		printf("  %-40s %-26s %-26s %6.3f %6.3f", m[i].name, stat_str(&m[i], V_WALL, a, sizeof(a)),
		       stat_str(&m[i], V_CPU, b, sizeof(b)), series_stat(&m[i], V_WALL).med / series_stat(&m[0], V_WALL).med,
		       series_stat(&m[i], V_CPU).med / series_stat(&m[0], V_CPU).med);
		if (counts && m[i].triangles >= 0)
			printf(" %9ld %9ld", m[i].triangles, m[i].vertices);
		printf("\n");
	}
}

/* 4: the same field at grid n through the three compaction methods, AO
 * off on all. */
static void measure_compaction(const struct params *p, int n, const struct field *f, int runs)
{
	static const char *const names[3] = { "HistoPyramid (shared vertices, indexed)", "atomic append (unshared)",
					      "none (15 vertices per cell)" };
	struct params q = *p;
	q.ao_rays = 0;
	q.shadows = 0.0f;
	q.grid = n;
	struct grid g;
	printf("\ncompaction methods, identical work: AO and shadows off on all three (only the HistoPyramid path has\n"
	       "them),\n"
	       "grid %d, whole runs, ms median [min-max], ratios of the medians to HistoPyramid's:\n", n);
	struct pipeline *pl = open_pipeline(&q, &g, f);
	if (!pl)
		return;
	struct series m[3], *s[3];
	for (int i = 0; i < 3; i++) {
		q.compaction = i;
		isoterra_series(&m[i], names[i], pl, &q, S_FULL);
		s[i] = &m[i];
	}
	series_rounds(s, 3, runs);
	print_ratio_table(m, 3, true);
	pipeline_destroy(pl);
}

/* 5: the density pass with ALU noise and with the 16^3 noise textures. */
static void measure_noise(const struct params *p, const struct field *f, int runs)
{
	struct params q = *p;
	struct grid g;
	printf("\nnoise source, density pass, grid %d, ms median [min-max], ratios of the medians to ALU's:\n", p->grid);
	struct pipeline *pl = open_pipeline(&q, &g, f);
	if (!pl)
		return;
	struct series m[2], *s[2] = { &m[0], &m[1] };
	q.noise = NOISE_ALU;
	isoterra_series(&m[0], "alu (improved Perlin)", pl, &q, S_DENSITY);
	q.noise = NOISE_TEXTURE;
	isoterra_series(&m[1], "texture (16^3 volumes)", pl, &q, S_DENSITY);
	series_rounds(s, 2, runs);
	print_ratio_table(m, 2, false);
	pipeline_destroy(pl);
}

/* 6: density pass and whole pipeline at other grid sizes. */
static void measure_sizes(const struct params *p, const struct field *f, const struct options *o)
{
	for (int i = 0; i < o->nsizes; i++) {
		struct params q = *p;
		q.grid = o->sizes[i];
		struct grid g;
		printf("\ngrid %d (the flags' field and AO), ms median [min-max], ratios of the medians to the density pass's:\n",
		       q.grid);
		struct pipeline *pl = open_pipeline(&q, &g, f);
		if (!pl)
			continue;
		struct series m[2], *s[2] = { &m[0], &m[1] };
		isoterra_series(&m[0], "density pass alone", pl, &q, S_DENSITY);
		isoterra_series(&m[1], "whole pipeline", pl, &q, S_FULL);
		series_rounds(s, 2, o->runs);
		print_ratio_table(m, 2, true);
		if (m[1].n)
			printf("  %.2f Mvoxels/s, %.3f Mtriangles/s (whole, wall)\n",
			       (double)g.nx * g.ny * g.nz / (series_stat(&m[1], V_WALL).med * 1e3),
			       m[1].triangles / (series_stat(&m[1], V_WALL).med * 1e3));
		pipeline_destroy(pl);
		measure_compaction(p, q.grid, f, o->runs);
	}
}

int main(int argc, char **argv)
{
	struct options o;
	setvbuf(stdout, NULL, _IOLBF, 0); /* in order with the GL and pipeline messages on stderr */
	int rc = parse_options(argc, argv, &o);
	if (rc)
		return rc == 1 ? 0 : 2;
	struct params p;
	char err[512];
	enum cli_result cr = cli_parse(o.argc, o.argv, &p, err, sizeof(err));
	if (cr != CLI_RUN) {
		if (cr == CLI_ERROR)
			fprintf(stderr, "bench_pipeline: %s\n", err);
		return cr == CLI_ERROR ? 2 : 0;
	}
	struct platform *plat = bench_open(p.platform, 64, 64);
	if (!plat)
		return 1;
	shader_set_dir(p.shader_dir); /* --shader-dir: try a shader's edit on the same field */
	print_field(&o, &p);
	printf("  %d runs per series%s; wall ms around glFinish; CPU = this process's CPU time (llvmpipe's and\n"
	       "  libnoise's threads included; VTK's: its child's)\n",
	       o.runs, o.quick ? " (--quick)" : "");
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	const struct field *f = terrain_field(tr);
	double loop_ms = measure_grid(&p, f, &o);
	measure_compaction(&p, p.grid, f, o.runs);
	if (o.oneshot)
		measure_oneshot(o.argv, o.argc, p.grid, o.runs * 2, loop_ms);
	if (!o.quick)
		measure_noise(&p, f, o.runs);
	if (o.nsizes)
		measure_sizes(&p, f, &o);
	printf("\nload average %.2f at the end\n", bench_loadavg());
	terrain_destroy(tr);
	edits_destroy(ed);
	platform_close(plat);
	return 0;
}
