/* isoterra — command line. */
#ifndef ISOTERRA_CLI_H
#define ISOTERRA_CLI_H

#include <stddef.h>
#include "params.h"

enum cli_result { CLI_RUN, CLI_EXIT_OK, CLI_ERROR };

/* Parses argv over the defaults: --preset and --config are applied first (in
 * that order), then every other option in command-line order, so explicit
 * flags win.  Options: every table entry as --name VALUE or --name=VALUE
 * (bools also as --name / --no-name), --set name=value, --help, --version,
 * --list-presets.  Validates cross-field constraints (size WxH, file
 * extensions).  On CLI_ERROR err holds one clear line. */
enum cli_result cli_parse(int argc, char **argv, struct params *p, char *err, size_t errlen);
/* Parses "WxH"; 0 or -1. */
int cli_parse_size(const char *s, int *w, int *h);
void cli_print_help(const char *argv0);

#endif
