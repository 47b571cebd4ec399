/* isoterra — command line. */
#ifndef ISOTERRA_CLI_H
#define ISOTERRA_CLI_H

#include <stddef.h>
#include "params.h"

/* CLI_LIST_DEVICES: --list-devices was given (the caller lists them: the
 * command line only reads text). */
enum cli_result { CLI_RUN, CLI_EXIT_OK, CLI_LIST_DEVICES, CLI_ERROR };

/* Parses argv over the defaults: --preset and --config are applied first (in
 * that order), then every other option in command-line order, so explicit
 * flags win.  Options: every table entry as --name VALUE or --name=VALUE
 * (bools also as --name / --no-name), --set name=value, --help, --version,
 * --list-presets, --list-devices.  Validates cross-field constraints (size WxH, file
 * extensions).  On CLI_ERROR err holds one clear line. */
enum cli_result cli_parse(int argc, char **argv, struct params *p, char *err, size_t errlen);
/* Parses "WxH"; 0 or -1. */
int cli_parse_size(const char *s, int *w, int *h);
/* What --out names: a PNG (written for the last frame), a PNG sequence (one
 * %d or %0Nd in the name: every frame) or a Y4M stream (.y4m, or - for
 * stdout); names end in .png / .y4m in any case.  The one check of the
 * output name, used by cli_parse and by the sinks.  0, or -1 with err. */
enum cli_out_kind { CLI_OUT_PNG, CLI_OUT_PNG_SEQUENCE, CLI_OUT_Y4M };
int cli_parse_out(const char *out, enum cli_out_kind *kind, char *err, size_t errlen);
/* "frame%04d.png" style names (--out, screenshot): pattern with n (>= 0) in
 * place of its %d / %Nd / %0Nd (printf's meaning, N up to
 * CLI_NAME_WIDTH_MAX) into buf.  1 when the pattern has one, 0 when it has
 * none (buf = pattern), -1 when it is malformed (more than one %, another
 * conversion, a wider N), -2 when the name does not fit len (never cut). */
#define CLI_NAME_WIDTH_MAX 4096
int cli_numbered_name(const char *pattern, int n, char *buf, size_t len);
/* The one check of a file the run will write (what: "out", "export_mesh",
 * ...), before any work: its name (pattern expanded for frame number last)
 * and its temp file's fit the system's name and path limits, its directory
 * exists and is writable, the name is not a directory.  0, or -1 with err. */
int cli_check_dest(const char *what, const char *pattern, int last, char *err, size_t errlen);
void cli_print_help(const char *argv0);

#endif
