/* isoterra — a gamepad or joystick through evdev (hal.h): found by its
 * capabilities, hotplugged, read without blocking; what its inputs mean
 * is stick.c's.
 *
 * Raw evdev ioctls, no libevdev: what is needed is EVIOCGVERSION, three
 * EVIOCGBIT bitmaps, EVIOCGPROP, EVIOCGNAME, EVIOCGABS per axis and
 * EVIOCGKEY (the last two again after SYN_DROPPED, libevdev's resync in
 * a dozen lines); the event loop is keys.c's.  libevdev would add a
 * dependency to four build environments (Debian 12 and 13, the arm64
 * cross-build, the package) without making this file shorter.
 *
 * Hotplug: inotify on the device folder (IN_CREATE, and IN_ATTRIB for the
 * permissions udev sets just after), which needs no udev daemon (the VM
 * test has none) and no libudev; when the folder cannot be watched (no
 * /dev/input yet) it is rescanned every retry_s.  The node that goes
 * away reads ENODEV: reported once, closed, and the folder scanned again. */
#include "hal.h"
#include "stick.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <linux/input.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/inotify.h>
#include <sys/ioctl.h>
#include <unistd.h>

#define READS_PER_POLL 4 /* at most 4 x 64 events a frame: a poll always returns */
#define BITS_LONG (sizeof(unsigned long) * 8)
#define NLONGS(n) (((n) + BITS_LONG - 1) / BITS_LONG)

struct hal_gamepad {
	struct stick_config scfg;
	struct stick_binding map[STICK_ROLES][STICK_BINDINGS];
	struct stick_pad pad;
	char dir[HAL_NAME_MAX];     /* the folder scanned and watched */
	char device[HAL_NAME_MAX];  /* "" any; else this node only */
	char path[HAL_NAME_MAX];    /* the node open ("" none) */
	char name[128];
	int fd;                     /* the device, -1 none */
	int ino, wd;                /* inotify, -1 none; the folder's watch, -1 none */
	bool rescan;                /* the folder changed: scan it */
	uint64_t retry_ns, next_scan;
	bool said_none, said_access;
	struct hal_log log;
};

static bool bit(const unsigned long *bits, int n)
{
	return bits[n / BITS_LONG] >> (n % BITS_LONG) & 1;
}

/* The device's axes' ranges and values, its keys down (at open and after
 * SYN_DROPPED).  -1 with errno when an ioctl fails. */
static int read_state(struct hal_gamepad *g, const unsigned long *absbits)
{
	for (int a = 0; a < ABS_CNT; a++) {
		if (!bit(absbits, a))
			continue;
		struct input_absinfo ai;
		if (ioctl(g->fd, EVIOCGABS(a), &ai) < 0)
			return -1;
		struct stick_absinfo s = { .min = ai.minimum, .max = ai.maximum, .flat = ai.flat };
		stick_pad_set_abs(&g->pad, a, &s, ai.value);
	}
	unsigned long keys[NLONGS(KEY_CNT)];
	memset(keys, 0, sizeof(keys));
	if (ioctl(g->fd, EVIOCGKEY(sizeof(keys)), keys) < 0)
		return -1;
	for (int k = 0; k < KEY_CNT; k++)
		stick_pad_set_key(&g->pad, k, bit(keys, k));
	return 0;
}

/* Opens path and keeps it when it is a gamepad or joystick: 1, else 0
 * (why says what it is not; errno-style problems too), -2 when it is no
 * evdev node at all. */
static int try_open(struct hal_gamepad *g, const char *path, char *why, size_t len)
{
	int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0) {
		snprintf(why, len, "cannot open %s: %s", path, strerror(errno));
		if (errno == EACCES && !g->said_access) { /* not in group input: say it once */
			hal_logf(&g->log, HAL_INFO, "gamepad: %s", why);
			g->said_access = true;
		}
		return 0;
	}
	unsigned long types[NLONGS(EV_CNT)], abs[NLONGS(ABS_CNT)], key[NLONGS(KEY_CNT)], props[NLONGS(INPUT_PROP_CNT)];
	memset(types, 0, sizeof(types));
	memset(abs, 0, sizeof(abs));
	memset(key, 0, sizeof(key));
	memset(props, 0, sizeof(props));
	int version;
	if (ioctl(fd, EVIOCGVERSION, &version) < 0 || ioctl(fd, EVIOCGBIT(0, sizeof(types)), types) < 0) {
		snprintf(why, len, "%s is not an evdev input device: %s", path, strerror(errno));
		close(fd);
		return -2;
	}
	if (!bit(types, EV_ABS) || !bit(types, EV_KEY) || ioctl(fd, EVIOCGBIT(EV_ABS, sizeof(abs)), abs) < 0 ||
	    ioctl(fd, EVIOCGBIT(EV_KEY, sizeof(key)), key) < 0 || !bit(abs, ABS_X) || !bit(abs, ABS_Y)) {
		snprintf(why, len, "%s has no ABS_X and ABS_Y", path);
		close(fd);
		return 0;
	}
	/* a gamepad's or joystick's button (the kernel's joydev takes the
	 * same range), or the D-pad's */
	bool buttons = false;
	for (int k = BTN_JOYSTICK; k < BTN_DIGI && !buttons; k++)
		buttons = bit(key, k);
	for (int k = BTN_DPAD_UP; k <= BTN_DPAD_RIGHT && !buttons; k++)
		buttons = bit(key, k);
	if (!buttons) {
		snprintf(why, len, "%s has no gamepad or joystick button", path);
		close(fd);
		return 0;
	}
	/* a motion sensor's node (a DS4's) has axes too, never buttons; say no anyway */
	if (ioctl(fd, EVIOCGPROP(sizeof(props)), props) >= 0 && bit(props, INPUT_PROP_ACCELEROMETER)) {
		snprintf(why, len, "%s is an accelerometer", path);
		close(fd);
		return 0;
	}
	char name[sizeof(g->name)];
	if (ioctl(fd, EVIOCGNAME(sizeof(name)), name) < 0)
		snprintf(name, sizeof(name), "?");
	name[sizeof(name) - 1] = 0;
	g->fd = fd;
	stick_pad_init(&g->pad, &g->scfg, g->map);
	if (read_state(g, abs) < 0) {
		snprintf(why, len, "%s: reading its state: %s", path, strerror(errno));
		close(fd);
		g->fd = -1;
		return 0;
	}
	stick_pad_settle(&g->pad, hal_now_ns());
	snprintf(g->path, sizeof(g->path), "%s", path);
	snprintf(g->name, sizeof(g->name), "%s", name);
	return 1;
}

/* eventN, numerically: the first gamepad plugged in is usually the lowest. */
static int event_number(const char *name)
{
	if (strncmp(name, "event", 5) || !name[5])
		return -1;
	char *end;
	long n = strtol(name + 5, &end, 10);
	return *end || n < 0 || n > INT_MAX ? -1 : (int)n;
}

/* -2 (why) when the named node is no evdev node, else 0. */
static int scan(struct hal_gamepad *g, char *why, size_t len)
{
	if (g->device[0]) {
		int rc = try_open(g, g->device, why, len);
		if (rc == 1 || rc == -2)
			return rc == -2 ? -2 : 0;
		if (!g->said_none) {
			hal_logf(&g->log, HAL_INFO, "gamepad: %s; waiting for it", why);
			g->said_none = true;
		}
		return 0;
	}
	DIR *d = opendir(g->dir);
	if (!d)
		return 0;
	int best = -1;
	struct dirent *e;
	/* lowest first: a few nodes, tried in order of their numbers */
	for (int pass = 0; pass < 64; pass++) {
		int next = INT_MAX;
		rewinddir(d);
		while ((e = readdir(d)) != NULL) {
			int n = event_number(e->d_name);
			if (n > best && n < next)
				next = n;
		}
		if (next == INT_MAX)
			break;
		best = next;
		char path[HAL_NAME_MAX + 32];
		snprintf(path, sizeof(path), "%s/event%d", g->dir, next);
		if (try_open(g, path, why, len) == 1) {
			closedir(d);
			return 0;
		}
	}
	closedir(d);
	return 0;
}

static void watch(struct hal_gamepad *g)
{
	if (g->ino < 0 || g->wd >= 0)
		return;
	g->wd = inotify_add_watch(g->ino, g->dir, IN_CREATE | IN_ATTRIB | IN_MOVED_TO);
}

/* Drains the folder's events: any node created or changed asks for a scan.
 * A failing inotify is given up for the periodic rescan. */
static void drain(struct hal_gamepad *g)
{
	if (g->ino < 0)
		return;
	char buf[4096] __attribute__((aligned(__alignof__(struct inotify_event))));
	for (;;) {
		ssize_t n = read(g->ino, buf, sizeof(buf));
		if (n < 0) {
			if (errno == EAGAIN || errno == EINTR)
				return;
			hal_logf(&g->log, HAL_WARN, "gamepad: inotify: %s; rescanning every %.1f s instead", strerror(errno),
				 (double)g->retry_ns / 1e9);
			close(g->ino);
			g->ino = g->wd = -1;
			return;
		}
		for (ssize_t off = 0; off + (ssize_t)sizeof(struct inotify_event) <= n;) {
			const struct inotify_event *ev = (const struct inotify_event *)(buf + off);
			if (ev->mask & IN_IGNORED) /* the folder itself went away */
				g->wd = -1;
			else if (ev->len && !strncmp(ev->name, "event", 5))
				g->rescan = true;
			off += (ssize_t)sizeof(struct inotify_event) + ev->len;
		}
	}
}

struct hal_gamepad *hal_gamepad_open(const struct hal_gamepad_config *cfg, char *err, size_t errlen)
{
	err[0] = 0;
	if (!cfg->enabled)
		return NULL;
	struct hal_gamepad *g = calloc(1, sizeof(*g));
	if (!g) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	g->fd = g->ino = g->wd = -1;
	g->log = cfg->log;
	stick_map_default(g->map);
	char e[256];
	if (stick_map_parse(cfg->map, g->map, e, sizeof(e)) < 0) {
		snprintf(err, errlen, "gamepad_map: %s", e);
		free(g);
		return NULL;
	}
	g->scfg = (struct stick_config){ .deadzone = cfg->deadzone,
					 .trigger_deadzone = cfg->trigger_deadzone,
					 .curve = cfg->curve < 1.0f ? 1.0f : cfg->curve,
					 .repeat_delay_ms = cfg->repeat_delay_ms,
					 .repeat_ms = cfg->repeat_ms };
	snprintf(g->device, sizeof(g->device), "%s", cfg->device ? cfg->device : "");
	if (g->device[0]) { /* watch the node's folder */
		snprintf(g->dir, sizeof(g->dir), "%s", g->device);
		char *slash = strrchr(g->dir, '/');
		if (slash && slash != g->dir)
			*slash = 0;
		else
			snprintf(g->dir, sizeof(g->dir), slash ? "/" : ".");
	} else {
		snprintf(g->dir, sizeof(g->dir), "%s", cfg->dir && cfg->dir[0] ? cfg->dir : "/dev/input");
	}
	g->retry_ns = (uint64_t)((cfg->retry_s > 0 ? cfg->retry_s : 2.0) * 1e9);
	g->ino = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
	if (g->ino < 0)
		hal_logf(&g->log, HAL_WARN, "gamepad: inotify: %s; rescanning every %.1f s", strerror(errno), cfg->retry_s);
	watch(g);
	char why[HAL_NAME_MAX + 96];
	if (scan(g, why, sizeof(why)) == -2) { /* a file of another kind: a configuration error */
		snprintf(err, errlen, "gamepad_device %s", why);
		hal_gamepad_close(g);
		return NULL;
	}
	g->next_scan = hal_now_ns() + g->retry_ns;
	if (g->fd >= 0) {
		hal_logf(&g->log, HAL_INFO, "gamepad: %s (%s) opened", g->name, g->path);
	} else if (!g->device[0]) {
		hal_logf(&g->log, HAL_INFO, "gamepad: none in %s yet; one plugged in is picked up", g->dir);
		g->said_none = true;
	}
	return g;
}

void hal_gamepad_close(struct hal_gamepad *g)
{
	if (!g)
		return;
	if (g->fd >= 0)
		close(g->fd);
	if (g->ino >= 0)
		close(g->ino);
	free(g);
}

const char *hal_gamepad_device(const struct hal_gamepad *g)
{
	return g && g->fd >= 0 ? g->path : "";
}

static void lost(struct hal_gamepad *g, const char *why)
{
	hal_logf(&g->log, HAL_WARN, "gamepad: %s (%s): %s; waiting for a gamepad", g->name, g->path, why);
	close(g->fd);
	g->fd = -1;
	g->path[0] = 0;
	stick_pad_release(&g->pad);
	g->rescan = true; /* another one may be there already */
	g->said_none = true;
}

/* At most READS_PER_POLL reads: a flood of events cannot hold the frame loop. */
static void read_events(struct hal_gamepad *g, uint64_t now)
{
	struct input_event ev[64];
	for (int r = 0; r < READS_PER_POLL; r++) {
		ssize_t n = read(g->fd, ev, sizeof(ev));
		if (n < 0) {
			if (errno != EAGAIN && errno != EINTR)
				lost(g, strerror(errno));
			return;
		}
		if (n == 0 || n % (ssize_t)sizeof(ev[0])) {
			lost(g, n ? "a read that is not a whole number of events" : "end of file");
			return;
		}
		bool resync = false;
		for (size_t i = 0; i < (size_t)n / sizeof(ev[0]); i++)
			resync |= stick_pad_event(&g->pad, now, ev[i].type, ev[i].code, ev[i].value) != 0;
		if (resync) { /* the kernel's buffer overran: read the state instead */
			unsigned long abs[NLONGS(ABS_CNT)];
			memset(abs, 0, sizeof(abs));
			for (int a = 0; a < ABS_CNT; a++)
				if (g->pad.has_abs[a])
					abs[a / BITS_LONG] |= 1ul << (a % BITS_LONG);
			if (read_state(g, abs) < 0) {
				lost(g, strerror(errno));
				return;
			}
			stick_pad_resync(&g->pad, now);
		}
		if ((size_t)n < sizeof(ev))
			return;
	}
}

void hal_gamepad_poll(struct hal_gamepad *g, uint64_t now_ns, struct hal_input *in)
{
	if (!g)
		return;
	drain(g);
	if (g->fd < 0) {
		bool periodic = now_ns >= g->next_scan;
		if (periodic) {
			g->next_scan = now_ns + g->retry_ns;
			watch(g); /* the folder may exist now */
		}
		if (g->rescan || (periodic && g->wd < 0)) {
			g->rescan = false;
			char why[HAL_NAME_MAX + 96];
			scan(g, why, sizeof(why)); /* a node of another kind, named: said at the start */
			if (g->fd >= 0) {
				hal_logf(&g->log, HAL_INFO, "gamepad: %s (%s) opened", g->name, g->path);
				g->said_none = false;
			}
		}
	}
	if (g->fd < 0)
		return;
	read_events(g, now_ns);
	if (g->fd < 0)
		return;
	struct stick_out o;
	stick_pad_take(&g->pad, now_ns, &o);
	in->select += o.presses[STICK_SELECT_NEXT] - o.presses[STICK_SELECT_PREV];
	in->change += o.presses[STICK_CHANGE_UP] - o.presses[STICK_CHANGE_DOWN];
	in->actions[HAL_RESET] += o.presses[STICK_RESET];
	in->actions[HAL_AUTOPILOT] += o.presses[STICK_AUTOPILOT];
	in->actions[HAL_PAUSE] += o.presses[STICK_PAUSE];
	in->actions[HAL_SCREENSHOT] += o.presses[STICK_SCREENSHOT];
	in->actions[HAL_PRESET] += o.presses[STICK_PRESET];
	in->actions[HAL_QUIT] += o.presses[STICK_QUIT];
	in->stick[HAL_FLY_FORWARD] += o.axis[STICK_FORWARD];
	in->stick[HAL_FLY_RIGHT] += o.axis[STICK_STRAFE];
	in->stick[HAL_FLY_UP] += o.axis[STICK_CLIMB] - o.axis[STICK_DESCEND];
	in->stick[HAL_FLY_YAW] += o.axis[STICK_YAW];
	in->stick[HAL_FLY_PITCH] += o.axis[STICK_PITCH];
}
