/* isoterra — power care on a handheld (docs/HANDHELD.md): the battery read
 * from the power supply class (/sys/class/power_supply, or a fake tree in
 * tests), and the low-power profile it switches: below battery_low percent
 * while discharging, the frame cap drops to low_power_fps and the world
 * holds at least low_power_quality of the governor's ladder; back above
 * the threshold plus a margin of 5 (or charging), the profile ends.  The
 * frame cap itself (max_fps) is the frame loop's (run.c). */
#ifndef ISOTERRA_POWER_H
#define ISOTERRA_POWER_H

#include <stdbool.h>
#include <stddef.h>

#include "params.h"

struct battery {
	bool present;
	int percent;        /* 0..100 (capacity, else energy_now / energy_full) */
	bool charging;      /* status Charging or Full, or a mains supply online */
	char status[16];    /* the status file: Charging, Discharging, Full, ... */
	char name[32];      /* the supply's folder name: BAT0, axp20x-battery ... */
};

/* The first supply of type Battery under dir (sorted by name), and whether
 * a Mains/USB supply is online.  0 (b->present false when there is none),
 * or -1 with err when dir cannot be read. */
int power_read(const char *dir, struct battery *b, char *err, size_t errlen);

struct power;
/* The folder: $ISOTERRA_POWER_SUPPLY when set, else p->power_supply.  A
 * missing folder is not an error (no battery: the profile never holds).
 * Read on a display (live), and offline only when the folder was named
 * (the option or the variable: tests): an offline render on a laptop's
 * battery stays the same picture.  NULL only out of memory. */
struct power *power_create(const struct params *p, bool live);
void power_destroy(struct power *pw);
/* Once a frame (now: seconds, monotonic): the battery read again every 5 s
 * (the first call reads it); a change of the profile is logged.  True
 * while the low-power profile holds. */
bool power_update(struct power *pw, const struct params *p, double now);
/* What was read last (present false: none). */
const struct battery *power_battery(const struct power *pw);
bool power_low(const struct power *pw);

#endif
