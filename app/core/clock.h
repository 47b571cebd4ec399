/* isoterra — the one monotonic clock every part of the program reads, and
 * the wall clock that the boards of a video wall share (NTP/PTP). */
#ifndef ISOTERRA_CLOCK_H
#define ISOTERRA_CLOCK_H

#include <errno.h>
#include <time.h>

/* CLOCK_MONOTONIC in milliseconds. */
static inline double clock_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* This thread's CPU time in milliseconds (what it waited for, asleep or
 * blocked, not counted). */
static inline double clock_thread_cpu_ms(void)
{
	struct timespec ts;
	if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0)
		return 0.0;
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* The CLOCK_REALTIME tick now: whole periods of 1/fps since the Unix
 * epoch (every board of a wall agrees on it to their clocks' sync). */
static inline long long clock_realtime_tick(double fps)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	return (long long)(((double)ts.tv_sec + (double)ts.tv_nsec / 1e9) * fps);
}

/* Sleeps until second s of clock id (an absolute deadline: a late wake-up
 * does not add up; the frame cap on CLOCK_MONOTONIC, a wall's next tick on
 * CLOCK_REALTIME).  0, or clock_nanosleep's error number. */
static inline int clock_sleep_until(clockid_t id, double s)
{
	struct timespec ts = { .tv_sec = (time_t)s };
	ts.tv_nsec = (long)((s - (double)ts.tv_sec) * 1e9);
	if (ts.tv_nsec >= 1000000000L)
		ts.tv_nsec = 999999999L;
	int rc;
	while ((rc = clock_nanosleep(id, TIMER_ABSTIME, &ts, NULL)) == EINTR)
		;
	return rc;
}

#endif
