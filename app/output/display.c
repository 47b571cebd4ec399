/* isoterra — the display side of the frame loop; see display.h. */
#include "display.h"
#include "log.h"

#include <signal.h>
#include <stdio.h>
#include <string.h>

static volatile sig_atomic_t quit_signal, fps_request;
static struct sigaction old_int, old_term, old_usr1;

static void on_quit(int sig)
{
	quit_signal = sig;
}

static void on_usr1(int sig)
{
	(void)sig;
	fps_request = 1;
}

static double seconds(const struct timespec *a, const struct timespec *b)
{
	return (double)(b->tv_sec - a->tv_sec) + (double)(b->tv_nsec - a->tv_nsec) * 1e-9;
}

void display_begin(struct display_loop *d, const struct platform *plat, const struct params *p)
{
	memset(d, 0, sizeof(*d));
	if (plat->headless)
		return;
	d->active = true;
	d->report_every = p->fps_report;
	clock_gettime(CLOCK_MONOTONIC, &d->start);
	d->last = d->start;
	quit_signal = 0;
	fps_request = 0;
	/* No SA_RESTART: a blocking wait returns EINTR and the loop sees the
	 * flag.  SA_RESETHAND: a second SIGINT/SIGTERM kills at once. */
	struct sigaction sa;
	memset(&sa, 0, sizeof(sa));
	sigemptyset(&sa.sa_mask);
	sa.sa_handler = on_quit;
	sa.sa_flags = SA_RESETHAND;
	if (sigaction(SIGINT, &sa, &old_int) != 0 || sigaction(SIGTERM, &sa, &old_term) != 0)
		log_warn("cannot install the SIGINT/SIGTERM handlers; the display is not restored on those");
	sa.sa_handler = on_usr1;
	sa.sa_flags = 0;
	if (sigaction(SIGUSR1, &sa, &old_usr1) != 0)
		log_warn("cannot install the SIGUSR1 handler (frame rate on demand)");
}

static void report(struct display_loop *d, const struct platform *plat, const struct timespec *now)
{
	double dt = seconds(&d->last, now);
	unsigned long n = d->frames - d->frames_last;
	fprintf(stderr, "isoterra: fps %.1f (%lu frames in %.2f s; %lu presented, %lu shown, %dx%d %s)\n",
	        dt > 0 ? (double)n / dt : 0.0, n, dt, plat->presented, plat->shown, plat->width, plat->height,
	        plat->backend->name);
	d->last = *now;
	d->frames_last = d->frames;
}

int display_frame(struct display_loop *d, struct platform *plat, struct renderer **r, int *w, int *h)
{
	if (renderer_blit_to_default(*r, plat->width, plat->height) < 0)
		return -1;
	if (platform_present(plat) < 0) {
		log_error("presenting the frame failed");
		return -1;
	}
	d->frames++;
	int rc = platform_dispatch(plat);
	d->presented = plat->presented;
	d->shown = plat->shown;
	d->backend = plat->backend->name;
	if (rc < 0)
		return -1;
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	if (fps_request || (d->report_every > 0 && seconds(&d->last, &now) >= d->report_every)) {
		fps_request = 0;
		report(d, plat, &now);
	}
	if (quit_signal) {
		log_info("%s: stopping", strsignal(quit_signal));
		return 1;
	}
	if (rc > 0)
		return 1;
	if (plat->width != *w || plat->height != *h) {
		char err[256];
		struct renderer *nr = renderer_create(plat->width, plat->height, err, sizeof(err));
		if (!nr) {
			log_error("resize to %dx%d: %s", plat->width, plat->height, err);
			return -1;
		}
		log_debug("resized %dx%d -> %dx%d", *w, *h, plat->width, plat->height);
		renderer_destroy(*r);
		*r = nr;
		*w = plat->width;
		*h = plat->height;
	}
	return 0;
}

void display_end(struct display_loop *d)
{
	if (!d->active)
		return;
	d->active = false;
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	double dt = seconds(&d->start, &now);
	if (d->backend)
		log_info("%s: %lu frames presented, %lu shown, %.1f fps", d->backend, d->presented, d->shown,
		         dt > 0 ? (double)d->frames / dt : 0.0);
	sigaction(SIGINT, &old_int, NULL);
	sigaction(SIGTERM, &old_term, NULL);
	sigaction(SIGUSR1, &old_usr1, NULL);
}
