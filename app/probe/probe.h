/* isoterra — the probe folder's door: `isoterra --probe`, what this machine
 * offers against what the configured job needs (EGL, the GL limits and the
 * passes that need them, DRM, GPIO, V4L2, device permissions, the program
 * cache), in plain text on stdout and, with --results FILE, as JSON. */
#ifndef ISOTERRA_PROBE_H
#define ISOTERRA_PROBE_H

#include "params.h"

/* Runs every check for the job p describes, prints the report and writes
 * p->results (JSON, temp file + rename; "-" = stdout, the text then on
 * stderr).  0
 * when the job would run, 1 when something blocks it (the first blocking
 * reason is the report's last line), 2 when the JSON cannot be written. */
int probe_run(const struct params *p);

#endif
