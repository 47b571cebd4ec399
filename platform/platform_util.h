/* isoterra — helpers for the files under platform/ only (not part of the
 * platform's interface): its messages (platform_log.h's seam), the
 * monotonic clock and ARRAY_SIZE, defined here so that platform/ needs
 * nothing of the program. */
#ifndef ISOTERRA_PLATFORM_UTIL_H
#define ISOTERRA_PLATFORM_UTIL_H

#include "platform_log.h"

#include <time.h>

void platform_logf(enum platform_log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#define plog_error(...) platform_logf(PLATFORM_LOG_ERROR, __VA_ARGS__)
#define plog_warn(...) platform_logf(PLATFORM_LOG_WARN, __VA_ARGS__)
#define plog_info(...) platform_logf(PLATFORM_LOG_INFO, __VA_ARGS__)
#define plog_debug(...) platform_logf(PLATFORM_LOG_DEBUG, __VA_ARGS__)

/* CLOCK_MONOTONIC in milliseconds. */
static inline double platform_clock_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* Number of elements of an array (not a pointer). */
#ifndef ARRAY_SIZE
#define ARRAY_SIZE(a) (sizeof(a) / sizeof((a)[0]))
#endif

#endif
