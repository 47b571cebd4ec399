/* isoterra — streaming world benchmark.
 *
 *  1. blocks per second: full 32^3 blocks through density (9 octaves) +
 *     HistoPyramid extraction, with ambient occlusion on and, as the
 *     baseline of the ratio, off (the chapter's GeForce 8800: 260 blocks/s);
 *  2. fly-through frame times (p50 / p99, ms) of the autopilot at 640x480
 *     and 1280x720 with live streaming under the per-frame budget; after
 *     the first second, the worst frame against the p99 (the hitches: how
 *     many frames exceed 3 x p99) and what the worst one did besides
 *     drawing: programs made, block arena chunks added or packed, blocks generated;
 *  3. peak resident memory;
 *  4. the world's own rate: a fresh world filling the autopilot's first
 *     view, blocks settled per second (generated, or proven empty by the
 *     coarse pre-pass without being generated), wall and CPU time.
 *  5. a 2x2 video wall: each tile's frame against the whole screen's, the
 *     same offline flight (a tile's cost: its share of the pixels plus what
 *     does not shrink with them);
 *  6. the frame cap: CPU time per second at --max-fps 30 against uncapped,
 *     the frame intervals of the paced run.
 * usage: bench_world [--quick] [--no-program] [--fill-only] [--wall] [--power] [--fly WxH]
 *                    [--seconds S] [--only full|governed] [--scale S] [--shader-dir DIR] [--platform NAME]
 * (--fill-only: measure 4 alone, three times; --wall: 5 alone; --power: 6 alone; --fly: only the two
 * fly-throughs of 2, at that size, --seconds S long each instead of 150
 * frames (2 to 3600), --only one of them; --scale: the full-quality one drawn at
 * that render scale, upscaled; --shader-dir: shaders read from DIR) */
#include "app.h"
#include "bench.h"
#include "world.h"
#include "terrain.h"
#include "governor.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* blocks/s over a 8 x 2 x 8 slab of blocks around the ground */
static double blocks_per_second(const struct params *p, int nb, uint32_t *tris)
{
	char err[512];
	struct grid g;
	memset(&g, 0, sizeof(g));
	g.nx = g.ny = g.nz = p->block_cells;
	g.cell = p->block_size / (float)p->block_cells;
	g.margin_extra = 6;
	struct params q = *p;
	q.closed = false;
	q.max_triangles = q.max_vertices = p->block_tris;
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &q, terrain_field(tr), err, sizeof(err));
	if (!pl) {
		fprintf(stderr, "bench: %s\n", err);
		terrain_destroy(tr);
		edits_destroy(ed);
		return -1;
	}
	bench_run(pl, &q); /* warm-up: shader compilation */
	glFinish();
	*tris = 0;
	double t0 = clock_ms();
	int done = 0;
	for (int i = 0; i < nb; i++) {
		g.base[0] = (i % 8) * g.nx;
		g.base[2] = ((i / 8) % 8) * g.nz;
		g.base[1] = (i / 64 % 2 - 1) * g.ny;
		pipeline_set_grid(pl, &g, 0.0f);
		bench_run(pl, &q);
		done++;
	}
	glFinish();
	double t = clock_ms() - t0;
	struct extract_stats st;
	pipeline_read_stats(pl, &st);
	*tris = st.triangles;
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
	return done / (t / 1e3);
}

/* A fresh world fills the autopilot's first view (world_fill: every wanted
 * block generated or known empty): blocks settled per second. */
static void fill_rate(const struct params *p_in)
{
	char err[512];
	struct params p = *p_in;
	struct edits *ed = edits_create();
	struct world *wd = world_create(&p, ed, err, sizeof(err));
	struct autopilot ap;
	if (!wd || autopilot_init(&ap, &p, ed) < 0) {
		fprintf(stderr, "bench: %s\n", err);
		world_destroy(wd);
		edits_destroy(ed);
		return;
	}
	struct camera c;
	autopilot_camera(&ap, &c, p.fov, 640.0f / 480.0f, p.view_distance * 1.2f);
	double t0 = clock_ms(), c0 = bench_cpu_ms();
	world_fill(wd, &p, &c, 0.0);
	glFinish();
	double t = clock_ms() - t0, cpu = bench_cpu_ms() - c0;
	struct world_stats st;
	world_get_stats(wd, &st);
	unsigned long long skipped = st.prepass_empty, settled = st.generated + skipped;
	printf("  fill the first view: %llu blocks settled (%llu generated, %llu of them empty; %llu skipped by the "
	       "pre-pass of %llu bounded) in %.0f ms wall, %.0f ms CPU: %.1f blocks/s settled, %.1f generated/s\n",
	       settled, (unsigned long long)st.generated, (unsigned long long)st.empty_found, skipped,
	       (unsigned long long)st.prepass_probed, t, cpu, settled / (t / 1e3), st.generated / (t / 1e3));
	autopilot_free(&ap);
	world_destroy(wd);
	edits_destroy(ed);
}

/* --scale S: the full-quality fly-throughs drawn at that render scale */
static float full_scale = 1.0f;

/* A world, its autopilot and a renderer for one flight (the fly-throughs
 * and the wall's): 0, or -1 (said on stderr, nothing left open). */
struct flight {
	struct renderer *r;
	struct edits *ed;
	struct world *wd;
	struct autopilot ap;
};

static int flight_open(struct flight *fl, const struct params *p, int w, int h)
{
	char err[512] = "out of memory";
	fl->r = renderer_create(w, h, p->antialias, err, sizeof(err));
	fl->ed = edits_create();
	fl->wd = fl->r && fl->ed ? world_create(p, fl->ed, err, sizeof(err)) : NULL;
	if (!fl->wd || autopilot_init(&fl->ap, p, fl->ed) < 0) {
		fprintf(stderr, "bench: %s\n", err);
		renderer_destroy(fl->r);
		world_destroy(fl->wd);
		edits_destroy(fl->ed);
		return -1;
	}
	world_keep_terms(fl->wd, p); /* as the scene does: the governor's steps compile nothing */
	return 0;
}

static void flight_close(struct flight *fl)
{
	autopilot_free(&fl->ap);
	world_destroy(fl->wd);
	edits_destroy(fl->ed);
	renderer_destroy(fl->r);
}

/* What one frame of a fly-through did besides drawing (for the worst
 * frame's cause). */
struct frame_note {
	double ms, t;           /* its time, and when it began (s from the start) */
	uint64_t generated;     /* blocks generated in it */
	uint64_t grown;         /* block arena chunks added in it */
	uint64_t packed;        /* block arena chunks packed in it */
	unsigned programs;      /* programs made in it (compiled or loaded from the cache) */
};

static unsigned programs_made(void)
{
	struct gpu_program_cache_stats cs = gpu_program_cache_stats();
	return cs.hits + cs.misses;
}

/* The hitches after the first second: the worst frame against the p99 of
 * those frames, how many exceed 3 x p99, and the worst one's cause. */
static void hitches(const struct frame_note *fn, int frames)
{
	int n = 0, worst = -1;
	double *ms = malloc(sizeof(double) * (size_t)frames);
	if (!ms)
		return;
	for (int f = 0; f < frames; f++)
		if (fn[f].t >= 1.0) {
			ms[n++] = fn[f].ms;
			if (worst < 0 || fn[f].ms > fn[worst].ms)
				worst = f;
		}
	if (n < 20 || worst < 0) {
		free(ms);
		return;
	}
	qsort(ms, (size_t)n, sizeof(double), bench_cmp_double);
	double p99 = ms[n * 99 / 100];
	int over = 0;
	for (int i = 0; i < n; i++)
		over += ms[i] > 3.0 * p99;
	free(ms);
	const struct frame_note *w = &fn[worst];
	char cause[160];
	if (w->programs)
		snprintf(cause, sizeof(cause), "%u program%s made (a compile or a cache load)", w->programs,
			 w->programs == 1 ? "" : "s");
	else if (w->grown || w->packed)
		snprintf(cause, sizeof(cause), "the block arena: %llu chunk%s added, %llu packed",
			 (unsigned long long)w->grown, w->grown == 1 ? "" : "s", (unsigned long long)w->packed);
	else if (w->generated)
		snprintf(cause, sizeof(cause), "block generation (%llu block%s)", (unsigned long long)w->generated,
			 w->generated == 1 ? "" : "s");
	else
		snprintf(cause, sizeof(cause), "drawing (no block generated, no program made, no growth)");
	printf("    after the first second: max %.1f ms = %.2f x p99 (%.1f ms), %d of %d frames over 3 x p99; the "
	       "worst, frame %d at %.1f s: %s\n",
	       w->ms, w->ms / p99, p99, over, n, worst, w->t, cause);
}

/* p50 of one fly-through (ms), -1 if it could not run: `frames` frames,
 * or, with seconds > 0, as many as that many seconds of flight take */
static double flythrough(const struct params *p_in, int w, int h, int frames, double seconds, bool governed)
{
	char err[512];
	struct params p = *p_in;
	snprintf(p.size, sizeof(p.size), "%dx%d", w, h);
	struct flight fl;
	if (flight_open(&fl, &p, w, h) < 0)
		return -1;
	struct renderer *r = fl.r;
	struct world *wd = fl.wd;
	struct autopilot *ap = &fl.ap;
	struct governor gov;
	struct governor_quality q = governor_level(0);
	governor_init(&gov, 1000.0 / (p.target_fps > 0 ? p.target_fps : 30.0));
	struct params eff = p;
	struct camera c;
	autopilot_camera(ap, &c, p.fov, (float)w / h, p.view_distance * 1.2f);
	if (!governed && full_scale < 1.0f && renderer_set_scale(r, full_scale, err, sizeof(err)) < 0)
		fprintf(stderr, "bench: %s\n", err);
	world_fill(wd, &p, &c, 0.0); /* start from a warm view, as a kiosk does after boot */
	int cap = seconds > 0 ? 4096 : frames;
	double *ft = malloc(sizeof(double) * (size_t)cap);
	struct frame_note *fn = malloc(sizeof(*fn) * (size_t)cap);
	if (!ft || !fn) {
		free(ft);
		free(fn);
		flight_close(&fl);
		return -1;
	}
	bool trace = getenv("BENCH_TRACE") != NULL; /* per-frame lines on stderr */
	double start = clock_ms(), cpu0 = bench_cpu_ms();
	struct world_stats before;
	world_get_stats(wd, &before);
	unsigned progs_before = programs_made();
	for (int f = 0; seconds > 0 || f < frames; f++) {
		double t0 = clock_ms();
		double t = (t0 - start) / 1e3;
		if (seconds > 0 && t >= seconds) {
			frames = f;
			break;
		}
		if (f == cap) { /* a timed flight: the notes grow */
			double *ft2 = realloc(ft, sizeof(double) * (size_t)cap * 2);
			ft = ft2 ? ft2 : ft;
			struct frame_note *fn2 = realloc(fn, sizeof(*fn) * (size_t)cap * 2);
			fn = fn2 ? fn2 : fn;
			if (!ft2 || !fn2) {
				fprintf(stderr, "bench: out of memory after %d frames\n", f);
				free(ft);
				free(fn);
				flight_close(&fl);
				return -1;
			}
			cap *= 2;
		}
		if (governed) /* the quality held since the last frame, as the scene gives it */
			ap->framing = q.framing;
		autopilot_advance(ap, t);
		autopilot_camera(ap, &c, p.fov, (float)w / h, p.view_distance * 1.2f);
		if (governed && world_hold_quality(wd, r, &q, &p, &eff, err, sizeof(err)) < 0) /* as the scene does */
			fprintf(stderr, "bench: %s\n", err);
		world_update(wd, &eff, &c, t, false);
		double tu = 0;
		if (trace) { /* the split costs a sync: only when tracing */
			glFinish();
			tu = clock_ms() - t0;
		}
		world_draw(wd, r, &c, &eff, t);
		glFinish();
		ft[f] = clock_ms() - t0;
		struct world_stats now;
		world_get_stats(wd, &now);
		unsigned progs = programs_made();
		fn[f] = (struct frame_note){ .ms = ft[f], .t = t, .generated = now.generated - before.generated,
					     .grown = now.arena_grown - before.arena_grown,
					     .packed = now.arena_packed - before.arena_packed, .programs = progs - progs_before };
		before = now;
		progs_before = progs;
		if (governed)
			q = governor_update(&gov, ft[f], clock_ms() / 1e3);
		if (trace) { /* per-frame trace: time, blocks drawn, generated so far */
			struct world_stats s2;
			world_get_stats(wd, &s2);
			fprintf(stderr, "frame %d: %.1f ms (update %.1f), %d drawn, %llu generated, level %d, held %.1f ms\n", f,
				ft[f], tu, s2.drawn, (unsigned long long)s2.generated, q.level,
				governed ? governor_held_ms(&gov) : 0.0);
		}
	}
	if (frames < 1) {
		free(ft);
		free(fn);
		flight_close(&fl);
		return -1;
	}
	double cpu_frame = (bench_cpu_ms() - cpu0) / frames;
	qsort(ft, (size_t)frames, sizeof(double), bench_cmp_double);
	struct world_stats st;
	world_get_stats(wd, &st);
	printf("  %-10s %4dx%-4d %4d frames  p50 %7.1f ms (%5.1f fps)  p95 %7.1f  p99 %7.1f  max %7.1f ms  drawn %d, "
	       "generated %llu, CPU %.1f ms a frame",
	       governed ? "governed" : "full", w, h, frames, ft[frames / 2], 1e3 / ft[frames / 2], ft[frames * 95 / 100],
	       ft[frames * 99 / 100], ft[frames - 1], st.drawn, (unsigned long long)st.generated, cpu_frame);
	if (governed)
		printf("  (held: render scale %.2f, view x%.2f, near LOD x%.2f on average; level %d at the end)",
		       governor_mean_scale(&gov), governor_mean_view(&gov), governor_mean_near_lod(&gov), q.level);
	printf("\n    block arena: %lld KB in %d chunks (%llu added, %llu packed) for %lld KB of meshes\n",
	       st.arena_bytes >> 10, st.arena_chunks, (unsigned long long)st.arena_grown,
	       (unsigned long long)st.arena_packed, st.arena_used >> 10);
	hitches(fn, frames);
	double p50 = ft[frames / 2];
	free(ft);
	free(fn);
	flight_close(&fl);
	return p50;
}

/* One offline flight (frame f at f / 30 s, blocks generated as an offline
 * run does: gen_per_frame a frame, so each run does the same work) of the
 * whole wall (tile NULL) or of one tile of it: the mean frame ms (update +
 * draw, the GPU finished) and its CPU ms into *mean / *cpu.  0 or -1. */
static int wall_flight(const struct params *p_in, int tw, int th, const char *tile, int frames, double *mean,
		       double *cpu)
{
	char err[512];
	struct params p = *p_in;
	struct wall_view v;
	int cols = 1, rows = 1;
	sscanf(p.wall, "%dx%d", &cols, &rows);
	int w = tw, h = th;
	if (tile) {
		snprintf(p.tile, sizeof(p.tile), "%s", tile);
	} else { /* the whole virtual screen as one frame */
		w = cols * tw;
		h = rows * th;
		snprintf(p.wall, sizeof(p.wall), "1x1");
	}
	struct flight fl;
	if (wall_view(&p, w, h, 1, &v, err, sizeof(err)) < 0) {
		fprintf(stderr, "bench: %s\n", err);
		return -1;
	}
	if (flight_open(&fl, &p, w, h) < 0)
		return -1;
	struct camera c;
	float far = p.view_distance * 1.2f;
	autopilot_camera(&fl.ap, &c, p.fov, v.aspect, far);
	camera_window(&c, &v);
	world_fill(fl.wd, &p, &c, 0.0);
	double sum = 0.0, cpu0 = bench_cpu_ms();
	for (int f = 0; f < frames; f++) {
		double t0 = clock_ms(), t = f / 30.0;
		autopilot_advance(&fl.ap, t);
		autopilot_camera(&fl.ap, &c, p.fov, v.aspect, far);
		camera_window(&c, &v);
		world_update(fl.wd, &p, &c, t, true);
		world_draw(fl.wd, fl.r, &c, &p, t);
		glFinish();
		sum += clock_ms() - t0;
	}
	*cpu = (bench_cpu_ms() - cpu0) / frames;
	*mean = sum / frames;
	flight_close(&fl);
	return 0;
}

/* A 2x2 wall of tw x th tiles: each tile's frame against the whole
 * screen's (one frame of 2tw x 2th), the same flight, interleaved
 * (whole, the tiles, whole, ...), `rounds` times; medians. */
static void wall_cost(const struct params *p_in, int tw, int th, int frames, int rounds)
{
	struct params p = *p_in;
	snprintf(p.wall, sizeof(p.wall), "2x2");
	static const char *tiles[4] = { "0,0", "1,0", "0,1", "1,1" };
	double whole[8], wcpu[8], tile[4][8], tcpu[4][8];
	printf("\na 2x2 video wall of %dx%d tiles (docs/WALL.md), offline flight of %d frames, %d interleaved rounds,\n"
	       "full quality; a frame's mean ms (update + draw), medians of the rounds:\n",
	       tw, th, frames, rounds);
	for (int k = 0; k < rounds && k < 8; k++) {
		if (wall_flight(&p, tw, th, NULL, frames, &whole[k], &wcpu[k]) < 0)
			return;
		for (int i = 0; i < 4; i++)
			if (wall_flight(&p, tw, th, tiles[i], frames, &tile[i][k], &tcpu[i][k]) < 0)
				return;
	}
	qsort(whole, (size_t)rounds, sizeof(double), bench_cmp_double);
	qsort(wcpu, (size_t)rounds, sizeof(double), bench_cmp_double);
	double wm = whole[rounds / 2], share = wm / 4.0;
	printf("  whole screen %dx%d   %7.1f ms  (spread %.1f-%.1f)  CPU %.1f ms   the baseline: a tile's share %.1f ms\n",
	       2 * tw, 2 * th, wm, whole[0], whole[rounds - 1], wcpu[rounds / 2], share);
	double sum = 0.0, sum_cpu = 0.0;
	for (int i = 0; i < 4; i++) {
		qsort(tile[i], (size_t)rounds, sizeof(double), bench_cmp_double);
		qsort(tcpu[i], (size_t)rounds, sizeof(double), bench_cmp_double);
		double tm = tile[i][rounds / 2];
		sum += tm;
		sum_cpu += tcpu[i][rounds / 2];
		printf("  tile %s %dx%d     %7.1f ms  (spread %.1f-%.1f)  CPU %.1f ms   %.2f of its pixel share\n", tiles[i],
		       tw, th, tm, tile[i][0], tile[i][rounds - 1], tcpu[i][rounds / 2], tm / share);
	}
	/* the tiles differ by what they show (sky is cheap, near rock is not):
	 * their sum against the whole is the like-for-like figure */
	printf("  the four tiles together %.1f ms, CPU %.1f ms: %.2f x the whole screen's frame; a tile costs its\n"
	       "  share of the pixels plus %.1f ms on average (%.0f %% of a share): the flight, the block plan and\n"
	       "  the blocks each tile's frustum holds, which do not shrink with the pixels\n",
	       sum, sum_cpu, sum / wm, (sum - wm) / 4.0, 100.0 * (sum - wm) / 4.0 / share);
}

/* The program run as a user runs it: wall time to its exit (the PNG
 * written) and its peak RSS; -1 when it failed.  cache: $XDG_CACHE_HOME
 * for the run (Mesa's shader cache and isoterra's program cache). */
static double program_run(char *const *args, const char *cache, double *rss_mb)
{
	struct bench_child c;
	if (bench_spawn(ISOTERRA_PROGRAM, args, cache, &c) < 0)
		return -1;
	*rss_mb = c.rss_mb;
	return c.wall_ms;
}

/* One run of the program with extra arguments: wall and CPU ms (the child's
 * user + system), and its results' frame interval p50 / p95 (ms).  0 or -1. */
static int capped_run(const char *cap, double *wall, double *cpu, double *p50, double *p95)
{
	char results[] = "/tmp/isoterra-bench-power-XXXXXX", png[64];
	int fd = mkstemp(results);
	if (fd < 0)
		return -1;
	close(fd);
	snprintf(png, sizeof(png), "%s.png", results);
	char *args[] = { "isoterra", "--size", "320x240", "--grid", "32", "--count", "150", "--results", results,
			 "--out", png, cap ? "--max-fps" : NULL, (char *)cap, NULL };
	struct bench_child c;
	int rc = -1;
	if (bench_spawn(ISOTERRA_PROGRAM, args, NULL, &c) == 0) {
		*wall = c.wall_ms;
		*cpu = c.cpu_ms;
		char buf[8192];
		bench_read_text(results, buf, sizeof(buf));
		const char *fm = strstr(buf, "\"frame_ms\"");
		if (fm && sscanf(fm, "\"frame_ms\": {\"p50\": %lf, \"p95\": %lf", p50, p95) == 2)
			rc = 0;
	}
	unlink(results);
	unlink(png);
	return rc;
}

/* The frame cap (--max-fps 30) against the same run uncapped: the volume
 * at 320x240, grid 32 (a frame far under the cap's 33 ms here), 150
 * frames, interleaved, n rounds; CPU time per second of the run and the
 * frame intervals. */
static void power_cost(int n)
{
	double w[2][8], c[2][8], i50[2][8], i95[2][8];
	printf("\nthe frame cap: --max-fps 30 against uncapped, the volume at 320x240, --grid 32, 150 frames,\n"
	       "%d interleaved rounds (medians; CPU: the process's user + system time per second of its run):\n", n);
	for (int k = 0; k < n && k < 8; k++)
		for (int m = 0; m < 2; m++)
			if (capped_run(m ? "30" : NULL, &w[m][k], &c[m][k], &i50[m][k], &i95[m][k]) < 0) {
				printf("  the program failed\n");
				return;
			}
	double cps[2], fps[2];
	for (int m = 0; m < 2; m++) {
		double r[8], fr[8];
		for (int k = 0; k < n; k++) {
			r[k] = c[m][k] / (w[m][k] / 1e3);
			fr[k] = 150.0 / (w[m][k] / 1e3);
		}
		qsort(r, (size_t)n, sizeof(double), bench_cmp_double);
		qsort(fr, (size_t)n, sizeof(double), bench_cmp_double);
		qsort(i50[m], (size_t)n, sizeof(double), bench_cmp_double);
		qsort(i95[m], (size_t)n, sizeof(double), bench_cmp_double);
		cps[m] = r[n / 2];
		fps[m] = fr[n / 2];
		printf("  %-9s %6.1f fps  CPU %6.1f ms per second [%.1f-%.1f]  frame interval p50 %6.2f ms, p95 %6.2f ms%s\n",
		       m ? "capped 30" : "uncapped", fps[m], cps[m], r[0], r[n - 1], i50[m][n / 2], i95[m][n / 2],
		       m ? " (the cap: 33.33)" : "");
	}
	printf("  CPU per second capped / uncapped = %.3f; p95 interval off the cap by %.2f ms\n", cps[1] / cps[0],
	       i95[1][n / 2] - 1000.0 / 30.0);
}

/* Start to PNG written, no flags, caches warm and empty; peak RSS of the
 * no-flag run and of a short world run (median of n runs, interleaved). */
static void program_runs(int n)
{
	char dir[] = "/tmp/isoterra-bench-XXXXXX";
	if (!mkdtemp(dir)) {
		perror("bench: mkdtemp");
		return;
	}
	char warm[64], cold[64], png[64], world_png[64];
	snprintf(warm, sizeof(warm), "%s/warm", dir);
	snprintf(png, sizeof(png), "%s/a.png", dir);
	snprintf(world_png, sizeof(world_png), "%s/w.png", dir);
	char *plain[] = { "isoterra", "--out", png, NULL };
	char *world[] = { "isoterra", "--scene", "world", "--count", "30", "--size", "640x360", "--out", world_png, NULL };
	double rss = 0, rss_w = 0;
	program_run(plain, warm, &rss); /* fills the warm caches */
	double tw[16], tc[16], rw[16], rp[16];
	n = n > 16 ? 16 : n;
	int ok = 0;
	for (int i = 0; i < n; i++) {
		snprintf(cold, sizeof(cold), "%s/cold%d", dir, i);
		tw[ok] = program_run(plain, warm, &rp[ok]);
		tc[ok] = program_run(plain, cold, &rss);
		if (tw[ok] < 0 || tc[ok] < 0 || program_run(world, warm, &rw[ok]) < 0) {
			fprintf(stderr, "bench: %s failed\n", ISOTERRA_PROGRAM);
			break;
		}
		ok++;
	}
	if (ok) {
		qsort(tw, (size_t)ok, sizeof(double), bench_cmp_double);
		qsort(tc, (size_t)ok, sizeof(double), bench_cmp_double);
		qsort(rw, (size_t)ok, sizeof(double), bench_cmp_double);
		qsort(rp, (size_t)ok, sizeof(double), bench_cmp_double);
		rss_w = rw[ok / 2];
		printf("\nthe program, no flags (1280x720 PNG), %d interleaved runs, median [min-max]:\n", ok);
		printf("  start to PNG written, caches warm   %7.0f ms [%.0f-%.0f]\n", tw[ok / 2], tw[0], tw[ok - 1]);
		printf("  start to PNG written, caches empty  %7.0f ms [%.0f-%.0f]  ratio warm/empty %.3f\n", tc[ok / 2],
		       tc[0], tc[ok - 1], tw[ok / 2] / tc[ok / 2]);
		printf("  peak RSS, no flags                  %7.1f MB (goal <= 120 MB)\n", rp[ok / 2]);
		printf("  peak RSS, --scene world --count 30 --size 640x360  %.1f MB (goal <= 150 MB)\n", rss_w);
	}
	char cmd[128];
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "bench: cannot remove %s\n", dir);
}

int main(int argc, char **argv)
{
	const char *plat_name = "auto";
	int quick = 0, program = 1, fill_only = 0, fly_w = 0, fly_h = 0;
	bool wall_only = false, power_only = false;
	double fly_s = 0.0;  /* --seconds: a timed flight instead of 150 frames */
	int fly_only = 0;    /* --only: 1 full quality, 2 governed, 0 both */
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--quick"))
			quick = 1;
		else if (!strcmp(argv[i], "--no-program"))
			program = 0;
		else if (!strcmp(argv[i], "--wall"))
			wall_only = true;
		else if (!strcmp(argv[i], "--power"))
			power_only = true;
		else if (!strcmp(argv[i], "--fill-only"))
			fill_only = 1;
		else if (!strcmp(argv[i], "--platform") && i + 1 < argc)
			plat_name = argv[++i];
		else if (!strcmp(argv[i], "--shader-dir") && i + 1 < argc)
			shader_set_dir(argv[++i]); /* try a shader's edit on the same flight */
		else if (!strcmp(argv[i], "--scale") && i + 1 < argc && sscanf(argv[i + 1], "%f", &full_scale) == 1 &&
			 full_scale >= 0.5f && full_scale <= 1.0f)
			i++;
		else if (!strcmp(argv[i], "--fly") && i + 1 < argc && sscanf(argv[i + 1], "%dx%d", &fly_w, &fly_h) == 2 &&
			 fly_w >= 16 && fly_h >= 16 && fly_w <= 8192 && fly_h <= 8192)
			i++;
		else if (!strcmp(argv[i], "--seconds") && i + 1 < argc && sscanf(argv[i + 1], "%lf", &fly_s) == 1 &&
			 fly_s >= 2.0 && fly_s <= 3600.0)
			i++;
		else if (!strcmp(argv[i], "--only") && i + 1 < argc &&
			 (!strcmp(argv[i + 1], "full") || !strcmp(argv[i + 1], "governed"))) {
			fly_only = !strcmp(argv[++i], "full") ? 1 : 2;
		} else {
			fprintf(stderr, "usage: %s [--quick] [--no-program] [--fill-only] [--wall] [--power] [--fly WxH]\n"
				"       [--seconds S] [--only full|governed] [--scale S] [--shader-dir DIR] [--platform NAME]\n",
				argv[0]);
			return 2;
		}
	}
	struct platform *plat = bench_open(plat_name, 64, 64);
	if (!plat)
		return 1;
	struct params p;
	params_defaults(&p);
	p.scene = 1;
	if ((fly_s > 0 || fly_only) && !fly_w) {
		fprintf(stderr, "bench: --seconds and --only go with --fly WxH\n");
		return 2;
	}
	if (fly_w) { /* only the two fly-throughs at one size (profiling, hitches over minutes) */
		int fr = quick ? 40 : 150;
		double full = fly_only != 2 ? flythrough(&p, fly_w, fly_h, fr, fly_s, false) : -1;
		double gov = fly_only != 1 ? flythrough(&p, fly_w, fly_h, fr, fly_s, true) : -1;
		if (full > 0 && gov > 0)
			printf("  %dx%d: p50 governed / full = %.3f\n", fly_w, fly_h, gov / full);
		platform_close(plat);
		return 0;
	}
	if (power_only) {
		power_cost(quick ? 2 : 5);
		platform_close(plat);
		return 0;
	}
	if (wall_only) {
		wall_cost(&p, 640, 360, quick ? 30 : 90, quick ? 3 : 5);
		platform_close(plat);
		return 0;
	}
	if (fill_only) {
		printf("\nthe streaming world (default field, %d^3-cell blocks, %d levels):\n", p.block_cells, p.lod_levels);
		for (int i = 0; i < 3; i++)
			fill_rate(&p);
		platform_close(plat);
		return 0;
	}
	int nb = quick ? 32 : 128;
	uint32_t tris;
	printf("\nblocks per second (%d^3 cells, %d octaves, %d blocks around the ground):\n", p.block_cells, p.octaves,
	       nb);
	struct params q = p;
	q.ao_rays = 0;
	double base = blocks_per_second(&q, nb, &tris);
	double ao = blocks_per_second(&p, nb, &tris);
	printf("  without AO  %7.1f blocks/s  ratio 1.000\n", base);
	printf("  with AO     %7.1f blocks/s  ratio %.3f  (%d rays x (%d + %d) steps; GeForce 8800 in the chapter: 260)\n",
	       ao, ao / base, p.ao_rays, p.ao_short_steps, p.ao_long_steps);

	printf("\nthe streaming world (default field, %d^3-cell blocks, %d levels):\n", p.block_cells, p.lod_levels);
	fill_rate(&p);

	printf("\nautopilot fly-through, live streaming (budget %.0f ms/frame), full quality and under the frame-time\n"
	       "governor (target %.0f fps), frame times in ms:\n",
	       p.gen_budget_ms, p.target_fps > 0 ? p.target_fps : 30.0);
	int sizes[2][2] = { { 640, 480 }, { 1280, 720 } };
	for (int i = 0; i < 2; i++) {
		int fr = quick ? 40 : 150;
		double full = flythrough(&p, sizes[i][0], sizes[i][1], fr, 0.0, false);
		double gov = flythrough(&p, sizes[i][0], sizes[i][1], fr, 0.0, true);
		if (full > 0 && gov > 0)
			printf("  %dx%d: p50 governed / full = %.3f\n", sizes[i][0], sizes[i][1], gov / full);
	}

	wall_cost(&p, 640, 360, quick ? 30 : 90, quick ? 3 : 5);
	power_cost(quick ? 2 : 5);

	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	printf("\npeak RSS of this benchmark process: %.1f MB\n", ru.ru_maxrss / 1024.0);
	platform_close(plat);
	if (program)
		program_runs(quick ? 1 : 5);
	return 0;
}
