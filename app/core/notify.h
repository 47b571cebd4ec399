/* isoterra — telling the service manager how the run goes (systemd's
 * notification socket, sd_notify(3)): READY=1 once the first frame is done,
 * WATCHDOG=1 while frames keep completing, a STATUS= line with the frame
 * rate, STOPPING=1 when the frame loop ends.  Only when NOTIFY_SOCKET is
 * set (a Type=notify unit); a build without libsystemd sends nothing and
 * says so once. */
#ifndef ISOTERRA_NOTIFY_H
#define ISOTERRA_NOTIFY_H

struct notify;

/* NULL when there is nothing to tell (NOTIFY_SOCKET unset, or no libsystemd). */
struct notify *notify_open(void);
/* A frame completed: READY=1 after the first, then WATCHDOG=1 and STATUS=
 * at most every half of WATCHDOG_USEC (every second without it).  Called
 * only from the frame loop, so a loop that stalls stops the pings. */
void notify_frame(struct notify *n);
/* STOPPING=1 with the final STATUS=, and frees n (NULL: nothing). */
void notify_close(struct notify *n);

#endif
