/* isoterra — the battery and the low-power profile (power.h). */
#include "power.h"
#include "core.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define READ_EVERY_S 5.0
#define HYSTERESIS 5 /* percent above battery_low before the profile ends */

/* The first line of dir/name/file, trimmed; 0 or -1. */
static int read_attr(const char *dir, const char *name, const char *file, char *buf, size_t len)
{
	char path[1024];
	if (snprintf(path, sizeof(path), "%s/%s/%s", dir, name, file) >= (int)sizeof(path))
		return -1;
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	bool ok = fgets(buf, (int)len, f) != NULL;
	fclose(f);
	if (!ok)
		return -1;
	buf[strcspn(buf, "\r\n")] = 0;
	return 0;
}

static int read_long(const char *dir, const char *name, const char *file, long *v)
{
	char buf[64], *end;
	if (read_attr(dir, name, file, buf, sizeof(buf)) < 0)
		return -1;
	errno = 0;
	*v = strtol(buf, &end, 10);
	return end == buf || *end || errno ? -1 : 0;
}

static int by_name(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

int power_read(const char *dir, struct battery *b, char *err, size_t errlen)
{
	memset(b, 0, sizeof(*b));
	DIR *d = opendir(dir);
	if (!d) {
		snprintf(err, errlen, "power supply folder %s: %s", dir, strerror(errno));
		return -1;
	}
	char *names[64];
	int n = 0;
	struct dirent *e;
	while ((e = readdir(d)) && n < 64)
		if (e->d_name[0] != '.' && (names[n] = strdup(e->d_name)))
			n++;
	closedir(d);
	qsort(names, (size_t)n, sizeof(names[0]), by_name);
	bool mains = false;
	for (int i = 0; i < n; i++) {
		char type[32];
		if (read_attr(dir, names[i], "type", type, sizeof(type)) < 0)
			continue;
		if (strcmp(type, "Battery")) { /* Mains, USB, ...: charging when online */
			long online;
			if (read_long(dir, names[i], "online", &online) == 0 && online > 0)
				mains = true;
			continue;
		}
		if (b->present)
			continue;
		long pct = -1, now, full;
		if (read_long(dir, names[i], "capacity", &pct) < 0) {
			if (read_long(dir, names[i], "energy_now", &now) == 0 &&
			    read_long(dir, names[i], "energy_full", &full) == 0 && full > 0)
				pct = now * 100 / full;
			else if (read_long(dir, names[i], "charge_now", &now) == 0 &&
				 read_long(dir, names[i], "charge_full", &full) == 0 && full > 0)
				pct = now * 100 / full;
		}
		long present = 1;
		read_long(dir, names[i], "present", &present);
		if (pct < 0 || !present)
			continue;
		b->present = true;
		b->percent = pct > 100 ? 100 : (int)pct;
		snprintf(b->name, sizeof(b->name), "%s", names[i]);
		if (read_attr(dir, names[i], "status", b->status, sizeof(b->status)) < 0)
			snprintf(b->status, sizeof(b->status), "Unknown");
		b->charging = !strcmp(b->status, "Charging") || !strcmp(b->status, "Full");
	}
	for (int i = 0; i < n; i++)
		free(names[i]);
	if (b->present && mains)
		b->charging = true;
	return 0;
}

struct power {
	char dir[512];
	struct battery bat;
	double next_read;
	bool low, warned;
	bool off; /* offline without a named folder: never read */
};

struct power *power_create(const struct params *p, bool live)
{
	struct power *pw = calloc(1, sizeof(*pw));
	if (!pw)
		return NULL;
	const char *env = getenv("ISOTERRA_POWER_SUPPLY");
	snprintf(pw->dir, sizeof(pw->dir), "%s", env && env[0] ? env : p->power_supply);
	pw->off = !live && !(env && env[0]) && !strcmp(p->power_supply, "/sys/class/power_supply");
	pw->next_read = -1.0;
	return pw;
}

void power_destroy(struct power *pw)
{
	free(pw);
}

bool power_update(struct power *pw, const struct params *p, double now)
{
	if (!pw || pw->off)
		return false;
	if (pw->next_read >= 0 && now < pw->next_read)
		return pw->low;
	pw->next_read = now + READ_EVERY_S;
	char err[600];
	bool had = pw->bat.present;
	if (power_read(pw->dir, &pw->bat, err, sizeof(err)) < 0 && !pw->warned) {
		/* no power supply class (a desktop, a container): no battery */
		log_debug("%s: no battery", err);
		pw->warned = true;
	}
	if (pw->bat.present != had)
		log_info("battery %s%s", pw->bat.present ? pw->bat.name : "gone",
			 pw->bat.present ? "" : ": the low-power profile is off");
	bool low = pw->low;
	if (!pw->bat.present || pw->bat.charging || p->battery_low <= 0)
		low = false;
	else if (pw->bat.percent <= p->battery_low)
		low = true;
	else if (pw->bat.percent > p->battery_low + HYSTERESIS)
		low = false;
	if (low != pw->low)
		log_info("battery %s %d%% %s: %s", pw->bat.name, pw->bat.percent, pw->bat.status,
			 low ? "the low-power profile holds" : "the low-power profile ends");
	pw->low = low;
	return low;
}

const struct battery *power_battery(const struct power *pw)
{
	static const struct battery none;
	return pw ? &pw->bat : &none;
}

bool power_low(const struct power *pw)
{
	return pw && pw->low;
}
