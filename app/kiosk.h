/* isoterra — a kiosk's lifecycle inside the frame loop: SIGHUP reads the
 * configuration again (the command line parsed anew, so its --config file
 * too) and applies what can change live, and the attract playlist
 * (--playlist "alpine:60, canyon:45, /etc/isoterra/night.conf:30") cycles
 * its shows with a crossfade, the seed one higher each cycle.
 *
 * Reload: a file that does not parse is reported (FILE:LINE: ...) and the
 * running configuration kept.  A good one applies the terrain's parameters
 * (P_SHADER), the live ones (P_LIVE) and the playlist; any other that
 * changed (platform, size, outputs, knobs ...) is reported as needing a
 * restart and kept as it runs. */
#ifndef ISOTERRA_KIOSK_H
#define ISOTERRA_KIOSK_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"

struct kiosk;
struct renderer;

/* argc/argv: the command line to parse again on SIGHUP (kept, not copied;
 * argc 0: reload refused with a message).  Checks the playlist (its presets
 * and files) and applies its first show to p.  NULL with err on a bad
 * playlist. */
struct kiosk *kiosk_create(struct params *p, int argc, char **argv, char *err, size_t errlen);
void kiosk_destroy(struct kiosk *k); /* NULL is fine */
/* Before frame `index` is drawn: a pending SIGHUP reload, the playlist's
 * next show (the frame drawn last kept for the crossfade).  t: the run's
 * clock in seconds (wall clock on a display, index / fps headless). */
void kiosk_frame_begin(struct kiosk *k, struct params *p, struct renderer *r, double t);
/* When the current show began (the run's clock, s): each show's flight
 * starts from its own spawn.  0 with no playlist (NULL k too). */
double kiosk_show_start(const struct kiosk *k);
/* After the scene drew the frame: the crossfade from the last show over
 * it.  0, or -1 with err.  NULL k: 0. */
int kiosk_frame_end(struct kiosk *k, struct renderer *r, char *err, size_t errlen);

#endif
