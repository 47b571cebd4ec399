/* isoterra — the platform layer's messages (platform_log.h): through the
 * program's callback, or errors and warnings to stderr without one. */
#include "platform_util.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static struct platform_log sink;

void platform_set_log(const struct platform_log *log)
{
	sink = log ? *log : (struct platform_log){ 0 };
}

static void deliver(enum platform_log_level level, const char *msg)
{
	static const char *const tag[] = { "error", "warning", "info", "debug" };
	if (sink.fn)
		sink.fn(sink.user, level, msg);
	else if (level <= PLATFORM_LOG_WARN)
		fprintf(stderr, "platform: %s: %s\n", tag[level], msg);
}

void platform_logf(enum platform_log_level level, const char *fmt, ...)
{
	if (!sink.fn && level > PLATFORM_LOG_WARN)
		return;
	char buf[1024];
	va_list ap, ap2;
	va_start(ap, fmt);
	va_copy(ap2, ap);
	int n = vsnprintf(buf, sizeof(buf), fmt, ap);
	va_end(ap);
	if (n < 0) {
		va_end(ap2);
		return;
	}
	if ((size_t)n < sizeof(buf)) {
		va_end(ap2);
		deliver(level, buf);
		return;
	}
	/* longer than the buffer: the whole line all the same */
	char *big = malloc((size_t)n + 1);
	if (big)
		vsnprintf(big, (size_t)n + 1, fmt, ap2);
	va_end(ap2);
	deliver(level, big ? big : buf);
	free(big);
}
