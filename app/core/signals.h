/* isoterra — the one owner of the process's signals.
 *
 * SIGINT and SIGTERM ask the frame loop to stop cleanly (files closed, the
 * display restored); one more a second or later after the first kills at
 * once (the user insists).  One sooner is the same request: `timeout`
 * sends its signal to the program and again to its process group, and the
 * second often arrived after the first's handler (with SA_RESETHAND, 12
 * of 200 runs of a plain program died uncleanly under `timeout`).  SIGUSR1
 * asks a display for a frame-rate report.  SIGHUP asks for the
 * configuration to be read again (app/kiosk.c).  SIGPIPE is ignored while the
 * handlers are installed: a closed pipe is a write error (EPIPE).  The handlers only set flags; the
 * frame loop and the display sink read them.  No SA_RESTART: a blocking
 * wait returns EINTR and its caller sees the flag. */
#ifndef ISOTERRA_SIGNALS_H
#define ISOTERRA_SIGNALS_H

#include <stdbool.h>

/* Installs the SIGINT/SIGTERM handlers (clears the flags), ignores SIGPIPE.  -1 when they
 * cannot be installed. */
int signals_install(void);
/* Installs the SIGUSR1 handler (frame rate on demand; without it SIGUSR1
 * keeps its default action).  -1 when it cannot be installed. */
int signals_watch_report(void);
/* Puts back the handlers that were there before signals_install. */
void signals_restore(void);
/* The signal that asked to stop (SIGINT, SIGTERM), 0 if none. */
int signals_quit(void);
/* True once per SIGUSR1 received since the last call. */
bool signals_take_report(void);
/* True once per SIGHUP received since the last call (installed with the
 * SIGINT/SIGTERM handlers). */
bool signals_take_reload(void);

#endif
