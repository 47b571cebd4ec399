/* isoterra — logging. */
#include "log.h"

#include <stdarg.h>
#include <stdio.h>

static enum log_level level = LOG_INFO;

void log_set_level(enum log_level lvl) { level = lvl; }
enum log_level log_get_level(void) { return level; }

void log_msg(enum log_level lvl, const char *fmt, ...)
{
	static const char *const tag[] = { "error", "warning", "info", "debug" };
	if (lvl > level)
		return;
	va_list ap;
	va_start(ap, fmt);
	fprintf(stderr, "isoterra: %s: ", tag[lvl]);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
}
