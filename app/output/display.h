/* isoterra — the display side of the frame loop (gbm, wayland, x11): the
 * finished frame is blitted to the window and presented, window events are
 * handled (resize re-creates the renderer, close ends the loop), SIGINT and
 * SIGTERM end the loop cleanly (so the platform restores the display), and
 * the frame rate is reported on SIGUSR1 and every --fps-report seconds. */
#ifndef ISOTERRA_DISPLAY_H
#define ISOTERRA_DISPLAY_H

#include <time.h>

#include "params.h"
#include "platform.h"
#include "render.h"

struct display_loop {
	struct timespec start, last;
	unsigned long frames, frames_last;
	double report_every;
	bool active;
	/* copied from the platform each frame, for display_end */
	unsigned long presented, shown;
	const char *backend;
};

/* No-op for headless platforms.  Installs the signal handlers. */
void display_begin(struct display_loop *d, const struct platform *plat, const struct params *p);
/* Blit r's frame to the window, present, dispatch events, report.  On a
 * resize *r is re-created at the new size and *w, *h are updated.
 * Returns 1 to stop (closed, SIGINT/SIGTERM), 0 to go on, -1 on error
 * (logged). */
int display_frame(struct display_loop *d, struct platform *plat, struct renderer **r, int *w, int *h);
/* After platform_close (which restores the display): logs "N frames
 * presented, M shown, F fps" and restores the signal handlers. */
void display_end(struct display_loop *d);

#endif
