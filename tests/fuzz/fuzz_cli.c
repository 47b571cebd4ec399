/* isoterra — libFuzzer harness: the command line (app/params/cli.c over
 * app/params/params.c): the input split at NUL bytes into arguments after
 * "isoterra".  Standard input reads as empty (--config /dev/stdin) and
 * standard output (--help, --version) goes nowhere. */
#include "cli.h"
#include "log.h"

#include <fcntl.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_ARGS 64

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
const char *platform_backend_names(void);

/* cli.c names the display backends in --help; the real list comes from
 * platform/, which this harness does not link (nor need). */
const char *platform_backend_names(void)
{
	return "surfaceless, device";
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	int null = open("/dev/null", O_RDWR);
	if (null < 0 || dup2(null, STDIN_FILENO) < 0 || dup2(null, STDOUT_FILENO) < 0)
		abort();
	close(null);
	log_set_level(LOG_ERROR); /* cli_parse's notes and warnings: not what is checked */
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char *text = malloc(size + 1);
	if (!text)
		return 0;
	memcpy(text, data, size);
	text[size] = 0;
	char *argv[MAX_ARGS + 2];
	int argc = 0;
	argv[argc++] = (char *)"isoterra";
	for (size_t i = 0; i <= size && argc <= MAX_ARGS; i += strlen(text + i) + 1)
		argv[argc++] = text + i;
	argv[argc] = NULL;
	struct params p;
	char err[512];
	err[0] = 0;
	enum cli_result r = cli_parse(argc, argv, &p, err, sizeof(err));
	if (r == CLI_ERROR && !err[0])
		abort(); /* an error always says what it is */
	free(text);
	return 0;
}
