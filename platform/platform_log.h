/* isoterra — the platform layer's reporting seam.
 *
 * platform/ is a library below the program: it includes nothing of app/
 * (its only include folder is platform/).  Its messages go, one line each
 * without a trailing newline, to the callback the program sets once at
 * start with platform_set_log; the program formats and filters them (its
 * log level).  Without one (a test, a benchmark), errors and warnings go
 * to stderr as "platform: error: ..." and the rest is dropped. */
#ifndef ISOTERRA_PLATFORM_LOG_H
#define ISOTERRA_PLATFORM_LOG_H

enum platform_log_level { PLATFORM_LOG_ERROR, PLATFORM_LOG_WARN, PLATFORM_LOG_INFO, PLATFORM_LOG_DEBUG };

struct platform_log {
	void (*fn)(void *user, enum platform_log_level level, const char *msg);
	void *user;
};

/* Where the platform's messages go from now on (copied); NULL, or a NULL
 * fn: the stderr default above.  Set it before platform_open. */
void platform_set_log(const struct platform_log *log);

#endif
