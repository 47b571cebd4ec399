/* isoterra — procedural GPU terrain: entry point. */
#include "app.h"
#include "probe.h"

int main(int argc, char **argv)
{
	struct params p;
	char err[512];
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
