/* isoterra — display benchmark: what showing a frame costs on a display
 * platform (gbm, wayland, x11) over rendering it offscreen.
 *
 * One static terrain frame (the mesh is extracted once) is drawn N times:
 *  1. baseline: renderer_draw + glFinish (the headless frame);
 *  2. + blit: the frame blitted to the window's back buffer, glFinish;
 *  3. + present: blit, eglSwapBuffers and the backend's events (page flip,
 *     frame callback, X events): what the display loop does per frame.
 * The three steps alternate in rounds of --frames frames (so a load change
 * on a shared machine hits all three alike); the median round is reported.
 * Ratios are to the baseline of the same run; the machine is printed.
 * On X11, --x11-present shm|swap chooses how a frame reaches the window
 * (the program's option; auto by default); both measures the two in one
 * run, twice each, alternated (MIT-SHM, swap, MIT-SHM, swap: a platform
 * each), and prints the present step of each and their ratio.  On a local
 * X server (its pid from the socket's peer credentials) each step also
 * prints the server's CPU time a frame (/proc/PID/schedstat): the copy a
 * present costs the server, which the program's own times do not show.
 * usage: bench_display [--platform NAME] [--size WxH] [--frames N]
 *                      [--rounds N] [--grid N] [--x11-present auto|shm|swap|both] */
#define _GNU_SOURCE /* struct ucred */
#include "app.h"
#include "bench.h"
#include "terrain.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#ifdef ISOTERRA_HAVE_X11
#include <xcb/xcb.h>
#endif

/* The local X server's pid (SO_PEERCRED of a connection of our own), 0
 * when there is none (no DISPLAY, a server over TCP, no x11 built in).
 * The connection stays open until the benchmark ends: an X server without
 * -noreset resets when its last client leaves, and refuses connections
 * meanwhile (a platform opened just after another closed: one xcb_connect
 * in five failed in a tight loop on Xvfb). */
static int x_server_pid(void)
{
	int pid = 0;
#ifdef ISOTERRA_HAVE_X11
	xcb_connection_t *c = xcb_connect(NULL, NULL);
	struct ucred cred;
	socklen_t len = sizeof(cred);
	if (!xcb_connection_has_error(c) &&
	    getsockopt(xcb_get_file_descriptor(c), SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0 && cred.pid > 0)
		pid = (int)cred.pid; /* c stays open: the kernel closes it at exit */
	else
		xcb_disconnect(c);
#endif
	return pid;
}

/* Nanoseconds process pid has run on a CPU (its main thread:
 * /proc/PID/schedstat), or -1. */
static double cpu_ns(int pid)
{
	char path[64];
	double ns = -1;
	snprintf(path, sizeof(path), "/proc/%d/schedstat", pid);
	FILE *f = pid > 0 ? fopen(path, "r") : NULL;
	if (f && fscanf(f, "%lf", &ns) != 1)
		ns = -1;
	if (f)
		fclose(f);
	return ns;
}

enum step { DRAW, BLIT, PRESENT };

static double run(struct platform *plat, struct renderer *r, const struct pipeline_draw *d, const struct camera *c,
		  const struct params *p, enum step s, int frames)
{
	double t0 = clock_ms();
	for (int f = 0; f < frames; f++) {
		if (renderer_draw(r, d, c, p) < 0)
			return -1;
		if (s >= BLIT && renderer_blit_to_default(r, plat->width, plat->height) < 0)
			return -1;
		if (s == PRESENT) {
			if (platform_present(plat) < 0 || platform_dispatch(plat) < 0)
				return -1;
		} else {
			glFinish();
		}
	}
	if (s == PRESENT)
		glFinish();
	return (clock_ms() - t0) / frames;
}

#define PRESENT_BOTH (-1)
#define PRESENT_BAD (-2)

/* --x11-present's word: PLATFORM_X11_PRESENT_*, PRESENT_BOTH or PRESENT_BAD
 * (the program's words, in its order, then both). */
static int present_arg(const char *s)
{
	static const char *const words[] = { "auto", "shm", "swap" };
	for (int k = 0; k < 3; k++)
		if (!strcmp(s, words[k]))
			return k;
	return strcmp(s, "both") ? PRESENT_BAD : PRESENT_BOTH;
}

struct options {
	const char *plat_name, *size;
	int frames, rounds, grid, x11_present;
};

/* One platform's medians: ms a frame per step, the X server's CPU ms a
 * frame per step (-1: unknown). */
struct result {
	double ms[3], server_ms[3];
	const char *how;
};

static int parse_args(int argc, char **argv, struct options *o)
{
	*o = (struct options){ .plat_name = "auto", .size = "640x480", .frames = 3, .rounds = 15, .grid = 64 };
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--platform") && i + 1 < argc)
			o->plat_name = argv[++i];
		else if (!strcmp(argv[i], "--size") && i + 1 < argc)
			o->size = argv[++i];
		else if (!strcmp(argv[i], "--frames") && i + 1 < argc)
			o->frames = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--rounds") && i + 1 < argc)
			o->rounds = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--grid") && i + 1 < argc)
			o->grid = atoi(argv[++i]);
		else if (!strcmp(argv[i], "--x11-present") && i + 1 < argc && present_arg(argv[i + 1]) != PRESENT_BAD)
			o->x11_present = present_arg(argv[++i]);
		else {
			fprintf(stderr, "usage: %s [--platform NAME] [--size WxH] [--frames N] [--rounds N] [--grid N] "
				"[--x11-present auto|shm|swap|both]\n", argv[0]);
			return -1;
		}
	}
	return 0;
}

/* The three steps in alternating rounds; the median round of each (and
 * of the X server's CPU a frame, where known), printed.  0, or -1 when a
 * frame failed. */
static int measure(struct platform *plat, struct renderer *r, const struct pipeline_draw *d, const struct camera *c,
		   const struct params *p, const struct options *o, int server, struct result *res)
{
	static const char *names[] = { "draw (headless frame)", "draw + blit to window", "draw + blit + present" };
	int rounds = o->rounds;
	double *t = malloc(sizeof(double) * 6 * (size_t)rounds), *sv = t + 3 * rounds;
	if (!t)
		return -1;
	for (int k = 0; k < rounds; k++)
		for (int s = DRAW; s <= PRESENT; s++) {
			double n0 = cpu_ns(server);
			if ((t[s * rounds + k] = run(plat, r, d, c, p, (enum step)s, o->frames)) < 0) {
				free(t);
				return -1;
			}
			double n1 = cpu_ns(server);
			sv[s * rounds + k] = n0 >= 0 && n1 >= n0 ? (n1 - n0) / 1e6 / o->frames : -1;
		}
	for (int s = DRAW; s <= PRESENT; s++) {
		qsort(t + s * rounds, (size_t)rounds, sizeof(double), bench_cmp_double);
		qsort(sv + s * rounds, (size_t)rounds, sizeof(double), bench_cmp_double);
		res->ms[s] = t[s * rounds + rounds / 2];
		res->server_ms[s] = sv[s * rounds + rounds / 2];
	}
	free(t);
	for (int s = DRAW; s <= PRESENT; s++) {
		printf("  %-24s %8.2f ms/frame  %7.1f fps  ratio %.3f", names[s], res->ms[s], 1e3 / res->ms[s],
		       res->ms[s] / res->ms[DRAW]);
		if (res->server_ms[s] >= 0)
			printf("  X server %.2f ms/frame", res->server_ms[s]);
		putchar('\n');
	}
	printf("  presented %lu, shown %lu\n", plat->presented, plat->shown);
	return 0;
}

/* The platform with one present, the frame's pipeline and renderer, the
 * three steps measured.  0, or 1 (said). */
static int bench_present(const struct options *o, int w, int h, int present, int server, struct result *res)
{
	struct platform *plat = bench_open_present(o->plat_name, w, h, present);
	if (!plat)
		return 1;
	char err[512];
	if (plat->headless) {
		printf("platform %s is headless: nothing to present (run under X11, Wayland or on a KMS console)\n",
		       plat->backend->name);
		platform_close(plat);
		return 1;
	}
	w = plat->width;
	h = plat->height;
	res->how = plat->present_how ? plat->present_how : plat->backend->name;
	printf("platform %s (%s), %dx%d, grid %d^3, %d rounds of %d frames per step%s%s\n", plat->backend->name,
	       plat->device_desc, w, h, o->grid, o->rounds, o->frames, plat->present_how ? ", present: " : "",
	       plat->present_how ? plat->present_how : "");
	struct params p;
	params_defaults(&p);
	p.grid = o->grid;
	p.cam_spin = 0;
	struct grid g;
	grid_from_params(&g, &p);
	int rc = 1;
	struct renderer *r = NULL;
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	struct pipeline *pl = pipeline_create(&g, &p, terrain_field(tr), err, sizeof(err));
	if (!pl || !(r = renderer_create(w, h, p.antialias, err, sizeof(err))) || bench_run(pl, &p) < 0) {
		fprintf(stderr, "bench_display: %s\n", err);
		goto out;
	}
	struct pipeline_draw d;
	struct camera cam;
	pipeline_draw_info(pl, &d);
	camera_orbit(&cam, &p, &g, 0.0f, (float)w / (float)h);
	/* warm-up: shader compilation, first swap */
	if (run(plat, r, &d, &cam, &p, PRESENT, 3) < 0 || measure(plat, r, &d, &cam, &p, o, server, res) < 0)
		fprintf(stderr, "bench_display: a frame failed (see the log)\n");
	else
		rc = 0;
out:
	renderer_destroy(r);
	pipeline_destroy(pl);
	terrain_destroy(tr);
	edits_destroy(ed);
	platform_close(plat);
	return rc;
}

int main(int argc, char **argv)
{
	struct options o;
	int w, h;
	if (parse_args(argc, argv, &o) < 0)
		return 2;
	if (cli_parse_size(o.size, &w, &h) < 0 || o.frames < 1 || o.rounds < 1 || o.rounds > 1000 || o.grid < 2) {
		fprintf(stderr, "bench_display: bad --size, --frames, --rounds or --grid\n");
		return 2;
	}
	int server = getenv("DISPLAY") && getenv("DISPLAY")[0] ? x_server_pid() : 0;
	if (o.x11_present != PRESENT_BOTH) {
		struct result res;
		return bench_present(&o, w, h, o.x11_present, server, &res);
	}
	/* MIT-SHM, swap, MIT-SHM, swap; the medians of each present's two */
	static const int order[4] = { PLATFORM_X11_PRESENT_SHM, PLATFORM_X11_PRESENT_SWAP, PLATFORM_X11_PRESENT_SHM,
				      PLATFORM_X11_PRESENT_SWAP };
	struct result res[4];
	for (int i = 0; i < 4; i++)
		if (bench_present(&o, w, h, order[i], server, &res[i]) != 0)
			return 1;
	printf("present step (draw + blit + present less draw + blit), and the X server's CPU a frame over it:\n");
	double step[2] = { 0, 0 }, serv[2] = { 0, 0 };
	for (int k = 0; k < 2; k++) {
		for (int j = 0; j < 2; j++) {
			const struct result *r = &res[2 * j + k];
			step[k] += 0.5 * (r->ms[PRESENT] - r->ms[BLIT]);
			serv[k] += 0.5 * (r->server_ms[PRESENT] - r->server_ms[BLIT]);
		}
		const struct result *a = &res[k], *b = &res[k + 2];
		printf("  %-15s %.2f, %.2f ms (mean %.2f)", a->how, a->ms[PRESENT] - a->ms[BLIT], b->ms[PRESENT] - b->ms[BLIT],
		       step[k]);
		if (a->server_ms[PRESENT] >= 0 && b->server_ms[PRESENT] >= 0)
			printf("; X server %.2f, %.2f ms (mean %.2f)", a->server_ms[PRESENT] - a->server_ms[BLIT],
			       b->server_ms[PRESENT] - b->server_ms[BLIT], serv[k]);
		putchar('\n');
	}
	printf("  ratio MIT-SHM / swap: present step %.3f", step[0] / step[1]);
	if (server > 0 && serv[1] > 0)
		printf(", X server %.3f", serv[0] / serv[1]);
	putchar('\n');
	return 0;
}
