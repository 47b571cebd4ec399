/* isoterra — signal flags (see signals.h). */
#include "signals.h"

#include <signal.h>
#include <string.h>
#include <time.h>

static volatile sig_atomic_t quit_signal, report_request, reload_request;
static volatile sig_atomic_t quit_at; /* CLOCK_MONOTONIC seconds of the first */
static struct sigaction old_int, old_term, old_usr1, old_pipe, old_hup;
static bool installed, watching;

/* Async-signal-safe: clock_gettime, signal, raise. */
static void on_quit(int sig)
{
	struct timespec now;
	sig_atomic_t t = clock_gettime(CLOCK_MONOTONIC, &now) == 0 ? (sig_atomic_t)now.tv_sec : 0;
	if (!quit_signal) {
		quit_signal = sig;
		quit_at = t;
	} else if (t - quit_at >= 2) { /* whole seconds: at least one apart */
		signal(sig, SIG_DFL);
		raise(sig);
	}
}

static void on_usr1(int sig)
{
	(void)sig;
	report_request = 1;
}

static void on_hup(int sig)
{
	(void)sig;
	reload_request = 1;
}

int signals_install(void)
{
	quit_signal = 0;
	quit_at = 0;
	report_request = 0;
	reload_request = 0;
	struct sigaction sa;
	memset(&sa, 0, sizeof(sa));
	sigemptyset(&sa.sa_mask);
	sa.sa_handler = on_quit;
	struct sigaction *keep_int = installed ? NULL : &old_int, *keep_term = installed ? NULL : &old_term;
	if (sigaction(SIGINT, &sa, keep_int) != 0 || sigaction(SIGTERM, &sa, keep_term) != 0)
		return -1;
	/* a reader that goes away (--out - | head) is a write error (EPIPE)
	 * reported like any other, not a silent death */
	struct sigaction ign;
	memset(&ign, 0, sizeof(ign));
	sigemptyset(&ign.sa_mask);
	ign.sa_handler = SIG_IGN;
	if (sigaction(SIGPIPE, &ign, installed ? NULL : &old_pipe) != 0)
		return -1;
	/* SIGHUP: reload the configuration (a kiosk's systemctl reload) */
	struct sigaction hup;
	memset(&hup, 0, sizeof(hup));
	sigemptyset(&hup.sa_mask);
	hup.sa_handler = on_hup;
	if (sigaction(SIGHUP, &hup, installed ? NULL : &old_hup) != 0)
		return -1;
	installed = true;
	return 0;
}

int signals_watch_report(void)
{
	report_request = 0;
	struct sigaction sa;
	memset(&sa, 0, sizeof(sa));
	sigemptyset(&sa.sa_mask);
	sa.sa_handler = on_usr1;
	if (sigaction(SIGUSR1, &sa, watching ? NULL : &old_usr1) != 0)
		return -1;
	watching = true;
	return 0;
}

void signals_restore(void)
{
	if (installed) {
		sigaction(SIGINT, &old_int, NULL);
		sigaction(SIGTERM, &old_term, NULL);
		sigaction(SIGPIPE, &old_pipe, NULL);
		sigaction(SIGHUP, &old_hup, NULL);
	}
	if (watching)
		sigaction(SIGUSR1, &old_usr1, NULL);
	installed = watching = false;
}

int signals_quit(void)
{
	return quit_signal;
}

bool signals_take_report(void)
{
	if (!report_request)
		return false;
	report_request = 0;
	return true;
}

bool signals_take_reload(void)
{
	if (!reload_request)
		return false;
	reload_request = 0;
	return true;
}
