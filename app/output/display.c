/* isoterra — the display sink (gbm, wayland, x11; see sink.h): the
 * finished frame is blitted to the window and presented, window events are
 * handled (a resize re-creates the renderer, closing ends the run),
 * SIGINT/SIGTERM end the run cleanly (so the platform restores the
 * display), and the frame rate is reported on SIGUSR1 and every
 * --fps-report seconds. */
#include "sink.h"
#include "core.h"
#include "platform.h"
#include "render.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct display_sink {
	struct sink base;
	struct platform *plat;
	struct timespec start, last;
	unsigned long frames, frames_last;
	double report_every;
	/* copied from the platform each frame: the final report comes after
	 * the platform is closed */
	unsigned long presented, shown;
	const char *backend;
	char status[192]; /* the scene's, from the last frame */
};

static double seconds(const struct timespec *a, const struct timespec *b)
{
	return (double)(b->tv_sec - a->tv_sec) + (double)(b->tv_nsec - a->tv_nsec) * 1e-9;
}

static void report(struct display_sink *d, const struct timespec *now)
{
	const struct platform *plat = d->plat;
	double dt = seconds(&d->last, now);
	unsigned long n = d->frames - d->frames_last;
	fprintf(stderr, "isoterra: fps %.1f (%lu frames in %.2f s; %lu presented, %lu shown, %dx%d %s)%s%s\n",
		dt > 0 ? (double)n / dt : 0.0, n, dt, plat->presented, plat->shown, plat->width, plat->height,
		plat->backend->name, d->status[0] ? "; " : "", d->status);
	d->last = *now;
	d->frames_last = d->frames;
}

/* The window's new size: a renderer of that size (the upright picture's,
 * turned onto it as the old one was: --rotate) replaces fr->r. */
static int resize(struct display_sink *d, struct sink_frame *fr, char *err, size_t errlen)
{
	struct platform *plat = d->plat;
	char e[256];
	struct renderer *nr = renderer_create_turned(plat->width, plat->height, renderer_rotation(fr->r),
						     renderer_antialias(fr->r), e, sizeof(e));
	if (!nr) {
		snprintf(err, errlen, "resize to %dx%d: %s", plat->width, plat->height, e);
		return -1;
	}
	log_debug("resized %dx%d -> %dx%d", fr->w, fr->h, plat->width, plat->height);
	renderer_destroy(fr->r);
	fr->r = nr;
	fr->w = plat->width;
	fr->h = plat->height;
	return 0;
}

static int display_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	struct display_sink *d = (struct display_sink *)s;
	struct platform *plat = d->plat;
	if (renderer_blit_to_default(fr->r, plat->width, plat->height) < 0) {
		err[0] = 0; /* reported */
		return -1;
	}
	/* the frame finished first (its work: the GPU's, or a software
	 * rasterizer's threads'), so that what the present then takes beyond
	 * this thread's CPU time is time spent blocked: waiting for a vertical
	 * blank, a page flip's event, a compositor's frame callback, an X
	 * server's copy of a software frame (the server's work, not this
	 * process's) */
	glFinish();
	double t0 = clock_ms(), c0 = clock_thread_cpu_ms();
	if (platform_present(plat) < 0) {
		snprintf(err, errlen, "presenting the frame failed");
		return -1;
	}
	double waited = (clock_ms() - t0) - (clock_thread_cpu_ms() - c0);
	if (waited > 0.0)
		fr->wait_ms += waited;
	d->frames++;
	snprintf(d->status, sizeof(d->status), "%s", fr->status);
	int rc = platform_dispatch(plat);
	d->presented = plat->presented;
	d->shown = plat->shown;
	d->backend = plat->backend->name;
	if (rc < 0) {
		err[0] = 0; /* reported by the platform */
		return -1;
	}
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	if (signals_take_report() || (d->report_every > 0 && seconds(&d->last, &now) >= d->report_every))
		report(d, &now);
	int sig = signals_quit();
	if (sig) {
		log_info("%s: stopping", strsignal(sig));
		return 1;
	}
	if (rc > 0)
		return 1;
	if (plat->width != fr->w || plat->height != fr->h)
		return resize(d, fr, err, errlen);
	return 0;
}

static int display_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	(void)s;
	(void)end;
	(void)err;
	(void)errlen;
	return 0;
}

/* After platform_close (which restores the display): "N frames presented,
 * M shown, F fps". */
static void display_destroy(struct sink *s)
{
	struct display_sink *d = (struct display_sink *)s;
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	double dt = seconds(&d->start, &now);
	if (d->backend)
		log_info("%s: %lu frames presented, %lu shown, %.1f fps", d->backend, d->presented, d->shown,
			 dt > 0 ? (double)d->frames / dt : 0.0);
	free(d);
}

static const struct sink_ops display_ops = {
	.frame = display_frame, .finish = display_finish, .destroy = display_destroy
};

void sink_display_outputs(const struct params *p, struct platform_options *po)
{
	po->outputs = p->outputs;
	po->outputs_mirror = true;
	po->outputs_gap = po->outputs_gap_per_w = 0.0;
	/* the horizontal bezel alone: a tile large enough for any bezel (the
	 * outputs' own size is checked in sink_display_open); a bad wall was
	 * refused with the command line */
	enum { BIG = 16384 };
	struct wall_view v;
	char e[256];
	if (!p->outputs[0] || wall_view(p, BIG, BIG, 1, &v, e, sizeof(e)) < 0 || !v.on)
		return;
	po->outputs_mirror = false;
	if (p->bezel_mm[0])
		po->outputs_gap_per_w = (double)v.bezel[0] / BIG; /* pixels of gap per pixel of tile width */
	else
		po->outputs_gap = (double)v.bezel[0];
}

void sink_display_tiles(const struct platform *plat, int *tile_w, int *tile_h, int *across)
{
	if (plat->n_outputs < 2 || plat->outputs[1].x == plat->outputs[0].x)
		return; /* one output, or a mirror: the frame is one tile */
	*tile_w = plat->outputs[0].w;
	*tile_h = plat->outputs[0].h;
	*across = plat->n_outputs;
}

/* Several outputs along a wall's row: their tiles fit it, and the surface
 * is the wall's frame of that many tiles.  0, or -1 with err. */
static int check_tiles(const struct platform *plat, const struct params *p, char *err, size_t errlen)
{
	int tw = 0, th = 0, across = 1;
	sink_display_tiles(plat, &tw, &th, &across);
	if (across < 2)
		return 0;
	struct wall_view v;
	if (wall_view(p, tw, th, across, &v, err, errlen) < 0)
		return -1;
	int fw = wall_frame_width(&v, tw);
	if (fw != plat->width || th != plat->height) {
		snprintf(err, errlen, "outputs: the %d outputs' surface is %dx%d, the wall's frame of %d tiles of %dx%d is "
			 "%dx%d", plat->n_outputs, plat->width, plat->height, across, tw, th, fw, th);
		return -1;
	}
	return 0;
}

struct sink *sink_display_open(struct platform *plat, const struct params *p, char *err, size_t errlen)
{
	if (check_tiles(plat, p, err, errlen) < 0)
		return NULL;
	struct display_sink *d = calloc(1, sizeof(*d));
	if (!d) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	d->base.ops = &display_ops;
	d->plat = plat;
	d->report_every = p->fps_report;
	clock_gettime(CLOCK_MONOTONIC, &d->start);
	d->last = d->start;
	if (signals_watch_report() < 0)
		log_warn("cannot install the SIGUSR1 handler (frame rate on demand)");
	return &d->base;
}
