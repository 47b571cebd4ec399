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
 * (the program's option; auto by default): run it once with each,
 * alternated, to compare the two.
 * usage: bench_display [--platform NAME] [--size WxH] [--frames N]
 *                      [--rounds N] [--grid N] [--x11-present auto|shm|swap] */
#include "app.h"
#include "bench.h"
#include "terrain.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

struct options {
	const char *plat_name, *size;
	int frames, rounds, grid, x11_present;
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
		else if (!strcmp(argv[i], "--x11-present") && i + 1 < argc && !strcmp(argv[i + 1], "shm"))
			o->x11_present = PLATFORM_X11_PRESENT_SHM, i++;
		else if (!strcmp(argv[i], "--x11-present") && i + 1 < argc && !strcmp(argv[i + 1], "swap"))
			o->x11_present = PLATFORM_X11_PRESENT_SWAP, i++;
		else if (!strcmp(argv[i], "--x11-present") && i + 1 < argc && !strcmp(argv[i + 1], "auto"))
			o->x11_present = PLATFORM_X11_PRESENT_AUTO, i++;
		else {
			fprintf(stderr, "usage: %s [--platform NAME] [--size WxH] [--frames N] [--rounds N] [--grid N] "
				"[--x11-present auto|shm|swap]\n", argv[0]);
			return -1;
		}
	}
	return 0;
}

/* The three steps in alternating rounds; the median round of each, printed.
 * 0, or -1 when a frame failed. */
static int measure(struct platform *plat, struct renderer *r, const struct pipeline_draw *d, const struct camera *c,
		   const struct params *p, const struct options *o)
{
	static const char *names[] = { "draw (headless frame)", "draw + blit to window", "draw + blit + present" };
	int rounds = o->rounds;
	double ms[3], *t = malloc(sizeof(double) * 3 * (size_t)rounds);
	if (!t)
		return -1;
	for (int k = 0; k < rounds; k++)
		for (int s = DRAW; s <= PRESENT; s++)
			if ((t[s * rounds + k] = run(plat, r, d, c, p, (enum step)s, o->frames)) < 0) {
				free(t);
				return -1;
			}
	for (int s = DRAW; s <= PRESENT; s++) {
		qsort(t + s * rounds, (size_t)rounds, sizeof(double), bench_cmp_double);
		ms[s] = t[s * rounds + rounds / 2];
	}
	free(t);
	for (int s = DRAW; s <= PRESENT; s++)
		printf("  %-24s %8.2f ms/frame  %7.1f fps  ratio %.3f\n", names[s], ms[s], 1e3 / ms[s], ms[s] / ms[DRAW]);
	printf("  presented %lu, shown %lu\n", plat->presented, plat->shown);
	return 0;
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
	struct platform *plat = bench_open_present(o.plat_name, w, h, o.x11_present);
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
	printf("platform %s (%s), %dx%d, grid %d^3, %d rounds of %d frames per step%s%s\n", plat->backend->name,
	       plat->device_desc, w, h, o.grid, o.rounds, o.frames, plat->present_how ? ", present: " : "",
	       plat->present_how ? plat->present_how : "");
	struct params p;
	params_defaults(&p);
	p.grid = o.grid;
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
	if (run(plat, r, &d, &cam, &p, PRESENT, 3) < 0 || measure(plat, r, &d, &cam, &p, &o) < 0)
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
