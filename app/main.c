/* isoterra — procedural GPU terrain: entry point. */
#include "app.h"
#include "probe.h"

/* platform/'s messages (platform_log.h) into the log: the same lines, at
 * the same levels, filtered by the log level as the program's own. */
static void platform_to_log(void *user, enum platform_log_level level, const char *msg)
{
	static const enum log_level lv[] = {
		[PLATFORM_LOG_ERROR] = LOG_ERROR, [PLATFORM_LOG_WARN] = LOG_WARN,
		[PLATFORM_LOG_INFO] = LOG_INFO, [PLATFORM_LOG_DEBUG] = LOG_DEBUG,
	};
	(void)user;
	log_msg((unsigned)level < ARRAY_SIZE(lv) ? lv[level] : LOG_DEBUG, "%s", msg);
}

int main(int argc, char **argv)
{
	struct params p;
	char err[512];
	platform_set_log(&(struct platform_log){ .fn = platform_to_log });
	switch (cli_parse(argc, argv, &p, err, sizeof(err))) {
	case CLI_EXIT_OK: return 0;
	case CLI_LIST_DEVICES:
		if (platform_list_devices(stdout, err, sizeof(err)) < 0) {
			log_error("%s", err);
			return 1;
		}
		return 0;
	case CLI_ERROR:
		log_error("%s", err);
		return 2;
	case CLI_RUN: break;
	}
	if (p.probe)
		return probe_run(&p);
	return run_program_args(&p, argc, argv);
}
