/* isoterra — the service manager's notifications through libsystemd's
 * sd_notify (notify.h). */
#include "notify.h"
#include "clock.h"
#include "log.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef ISOTERRA_HAVE_LIBSYSTEMD
#include <systemd/sd-daemon.h>

#define DEFAULT_INTERVAL_MS 1000.0 /* no WATCHDOG_USEC: STATUS= once a second */

struct notify {
	double interval_ms;    /* between pings: half of WATCHDOG_USEC */
	double last_ms;        /* the last ping (or READY=1) */
	int last_frames;       /* frames at the last ping */
	int frames;            /* frames completed */
	double fps;            /* over the last interval */
	bool failed;           /* a send failed: reported once */
};

static void send_state(struct notify *n, const char *what)
{
	char msg[160];
	snprintf(msg, sizeof(msg), "%s\nSTATUS=%d frames, %.1f fps", what, n->frames, n->fps);
	int rc = sd_notify(0, msg);
	if (rc < 0 && !n->failed) {
		log_warn("service notification (%s) failed: %s", what, strerror(-rc));
		n->failed = true;
	}
}

struct notify *notify_open(void)
{
	const char *sock = getenv("NOTIFY_SOCKET");
	if (!sock || !sock[0])
		return NULL;
	struct notify *n = calloc(1, sizeof(*n));
	if (!n) {
		log_warn("out of memory: no service notifications");
		return NULL;
	}
	uint64_t usec = 0;
	int wd = sd_watchdog_enabled(0, &usec);
	if (wd < 0)
		log_warn("WATCHDOG_USEC: %s; pinging every %.0f ms", strerror(-wd), DEFAULT_INTERVAL_MS);
	n->interval_ms = wd > 0 ? (double)usec / 2e3 : DEFAULT_INTERVAL_MS;
	return n;
}

void notify_frame(struct notify *n)
{
	if (!n)
		return;
	double now = clock_ms();
	n->frames++;
	if (n->frames == 1) {
		n->last_ms = now;
		n->last_frames = 1;
		send_state(n, "READY=1");
		return;
	}
	if (now - n->last_ms < n->interval_ms)
		return;
	n->fps = (double)(n->frames - n->last_frames) * 1e3 / (now - n->last_ms);
	n->last_ms = now;
	n->last_frames = n->frames;
	send_state(n, "WATCHDOG=1");
}

void notify_close(struct notify *n)
{
	if (!n)
		return;
	send_state(n, "STOPPING=1");
	free(n);
}

#else /* no libsystemd */

struct notify *notify_open(void)
{
	const char *sock = getenv("NOTIFY_SOCKET");
	if (sock && sock[0])
		log_warn("NOTIFY_SOCKET is set but this build has no libsystemd: no READY=1 or watchdog pings "
			 "(a Type=notify unit will time out)");
	return NULL;
}

void notify_frame(struct notify *n)
{
	(void)n;
}

void notify_close(struct notify *n)
{
	(void)n;
}

#endif
