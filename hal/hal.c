/* isoterra — the hardware layer's common parts (see hal.h): the clock and
 * the reporting seam. */
#include "hal.h"

#include <stdarg.h>
#include <stdio.h>
#include <time.h>

uint64_t hal_now_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

void hal_logf(const struct hal_log *log, enum hal_level level, const char *fmt, ...)
{
	if (!log || !log->fn)
		return;
	char msg[512];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	log->fn(log->user, level, msg);
}
