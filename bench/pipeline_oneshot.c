/* isoterra — the pipeline benchmark's one-shot row: the program run as a
 * user runs it, a whole process for one picture, at the flags' grid and at
 * grid 2 (the same start-up, programs and picture, next to no field), so
 * that their difference is what one extraction costs outside the loop that
 * bench_pipeline times: its buffers' first touch, its first run, drawing
 * its mesh.  The child's own results file splits its first frame into the
 * update (the pipeline's run) and the draw; the rest of that frame is the
 * scene's creation (its buffers), which the first frame's time holds.
 * The loop draws nothing and the process draws its mesh once: a process of
 * a few frames at each grid gives that draw warm, and the row's last line
 * compares like with like (the loop plus the warm draw), so that what is
 * left is the one-shot's own cost. */
#include "bench_pipeline.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { OS_WALL, OS_CPU, OS_FAULTS, OS_FRAME, OS_UPDATE, OS_DRAW, OS_WARM, OS_VALUES };
/* frames of the process that times the warm draw (OS_WARM): its draw's
 * p50 is a frame after the first */
#define WARM_FRAMES "5"

/* One process: isoterra <flags> --grid G --size 64x48 --count N --out FILE
 * --results JSON (the last of a repeated option wins).  warm 0: one frame
 * to a PNG, v[OS_WALL .. OS_DRAW]; warm 1: WARM_FRAMES frames to a Y4M,
 * v[OS_WARM] their draw's p50 (a frame after the first: the mesh drawn
 * again, as the loop would).  0 or -1. */
static int oneshot_run(char *const *flags, int nflags, int grid, int warm, double v[OS_VALUES])
{
	char results[] = "/tmp/isoterra-bench-oneshot-XXXXXX", out[64], g[16];
	int fd = mkstemp(results);
	if (fd < 0)
		return -1;
	close(fd);
	snprintf(out, sizeof(out), "%s.%s", results, warm ? "y4m" : "png");
	snprintf(g, sizeof(g), "%d", grid);
	char *args[300];
	int n = 0;
	args[n++] = "isoterra";
	for (int i = 1; i < nflags && n < 288; i++)
		args[n++] = flags[i];
	char *tail[] = { "--grid", g, "--size", "64x48", "--count", warm ? WARM_FRAMES : "1", "--out", out, "--results", results };
	for (size_t i = 0; i < sizeof(tail) / sizeof(tail[0]); i++)
		args[n++] = tail[i];
	args[n] = NULL;
	struct bench_child c;
	int rc = -1;
	char buf[8192];
	if (bench_spawn(ISOTERRA_PROGRAM, args, NULL, &c) == 0) {
		bench_read_text(results, buf, sizeof(buf));
		const char *a = strstr(buf, "\"first_frame_ms\""), *u = strstr(buf, "\"update_ms\""),
			   *d = strstr(buf, "\"draw_ms\"");
		if (warm) {
			if (d && sscanf(d, "\"draw_ms\": {\"p50\": %lf", &v[OS_WARM]) == 1)
				rc = 0;
		} else if (a && u && d && sscanf(a, "\"first_frame_ms\": %lf", &v[OS_FRAME]) == 1 &&
			   sscanf(u, "\"update_ms\": {\"p50\": %lf", &v[OS_UPDATE]) == 1 &&
			   sscanf(d, "\"draw_ms\": {\"p50\": %lf", &v[OS_DRAW]) == 1) {
			v[OS_WALL] = c.wall_ms;
			v[OS_CPU] = c.cpu_ms;
			v[OS_FAULTS] = (double)c.minflt;
			rc = 0;
		}
	}
	unlink(results);
	unlink(out);
	return rc;
}

void measure_oneshot(char *const *flags, int nflags, int grid, int runs, double loop_ms)
{
	printf("\none-shot: the program as a user runs it (%s <the flags> --size 64x48 --count 1 --out PNG),\n"
	       "a whole process at --grid %d and at --grid 2, %d rounds interleaved, ms median [min-max];\n"
	       "wall to its exit, CPU its user + system, minor page faults; its first frame from its --results;\n"
	       "the draw warm: the p50 of the draws of a process of " WARM_FRAMES " frames (--count " WARM_FRAMES ", to a Y4M):\n",
	       ISOTERRA_PROGRAM, grid, runs);
	if (runs > MAX_RUNS)
		runs = MAX_RUNS;
	double v[2][MAX_RUNS][OS_VALUES];
	int n = 0;
	for (int r = 0; r < runs; r++) {
		if (oneshot_run(flags, nflags, grid, 0, v[0][n]) < 0 || oneshot_run(flags, nflags, 2, 0, v[1][n]) < 0 ||
		    oneshot_run(flags, nflags, grid, 1, v[0][n]) < 0 || oneshot_run(flags, nflags, 2, 1, v[1][n]) < 0) {
			printf("  n/a: a run failed (run it by hand: isoterra <the flags> --grid %d --out o.png)\n", grid);
			return;
		}
		n++;
	}
	static const char *names[OS_VALUES] = { "process wall", "process CPU", "page faults", "first frame",
						"  its update", "  its draw", "draw, warm" };
	char a[64], b[64], c[64], gn[24];
	snprintf(gn, sizeof(gn), "--grid %d", grid);
	printf("  %-14s %-24s %-24s %-24s\n", "", gn, "--grid 2", "difference (pairs)");
	struct bench_stat diff[OS_VALUES];
	for (int k = 0; k < OS_VALUES; k++) {
		double x[MAX_RUNS], y[MAX_RUNS], d[MAX_RUNS];
		for (int i = 0; i < n; i++) {
			x[i] = v[0][i][k];
			y[i] = v[1][i][k];
			d[i] = x[i] - y[i];
		}
		int dec = k == OS_FAULTS ? 0 : 1;
		diff[k] = bench_stat_of(d, n);
		printf("  %-14s %-24s %-24s %-24s\n", names[k], bench_stat_str(bench_stat_of(x, n), dec, a, sizeof(a)),
		       bench_stat_str(bench_stat_of(y, n), dec, b, sizeof(b)), bench_stat_str(diff[k], dec, c, sizeof(c)));
	}
	if (loop_ms > 0)
		printf("  the difference against the loop's whole pipeline (%.1f ms, AO+sun as given): process wall %.2f x,\n"
		       "  its update (the pipeline's first run) %.2f x; its draw %.1f ms more; the rest of the first frame\n"
		       "  (the scene's creation) %.1f ms more; outside the first frame %.1f ms\n",
		       loop_ms, diff[OS_WALL].med / loop_ms, diff[OS_UPDATE].med / loop_ms, diff[OS_DRAW].med,
		       diff[OS_FRAME].med - diff[OS_UPDATE].med - diff[OS_DRAW].med,
		       diff[OS_WALL].med - diff[OS_FRAME].med);
	/* like for like: the loop draws nothing, the process draws its mesh;
	 * "draw, warm" is that draw once its programs and the driver's memory
	 * are made (the p50 of the draws of a process of WARM_FRAMES frames) */
	if (loop_ms > 0)
		printf("  like for like, against the loop's whole pipeline plus the mesh's warm draw (%.1f + %.1f ms):\n"
		       "  process wall %.2f x; what is left of the difference, %.1f ms, is the one-shot's own: its buffers'\n"
		       "  creation, the pipeline's and the draw's first runs, the process outside its first frame\n",
		       loop_ms, diff[OS_WARM].med, diff[OS_WALL].med / (loop_ms + diff[OS_WARM].med),
		       diff[OS_WALL].med - loop_ms - diff[OS_WARM].med);
}
