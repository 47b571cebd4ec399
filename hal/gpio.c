/* isoterra — GPIO knobs and buttons through libgpiod: 1.6 or 2.x, whichever
 * the build found (hal/meson.build), behind gpiod_backend.h.
 *
 * Every configured line is requested for both-edge events; each frame the
 * event fds are polled with a zero timeout and the events (with their
 * kernel timestamps) feed the decoders in rotary.c.  A chip that cannot be
 * opened, or whose lines cannot be requested, or that disappears (read
 * error, POLLERR, ENODEV from the periodic line-info check) is reported once
 * per problem (missing, or its lines refused: a chip that comes back with
 * a line busy says so) and retried every retry_s seconds (struct
 * hal_gpio_config). */
#include "hal.h"
#include "rotary.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef HAVE_LIBGPIOD
#include "gpiod_backend.h"

#include <dirent.h>
#endif

#define NLINES (3 * HAL_ENCODERS + HAL_BUTTONS) /* encoders: A, B, switch; buttons */

enum role { R_ENC_A, R_ENC_B, R_ENC_SW, R_BUTTON };

struct gline {
	int chip;         /* index into chips */
	int offset;
	enum role role;
	int ctl;          /* encoder or button index */
	bool active_low;
	enum hal_bias bias;
#ifdef HAVE_LIBGPIOD
	struct hal_gpiod_line *line;
#endif
	int fd;
	int level;
};

struct gchip {
	char name[HAL_NAME_MAX];
#ifdef HAVE_LIBGPIOD
	struct hal_gpiod_chip *chip;
#endif
	bool up;
	enum { CH_FINE, CH_MISSING, CH_LINES } problem; /* the last one reported */
	uint64_t next_try;
};

struct hal_gpio {
	struct gchip chips[NLINES];
	int nchips;
	struct gline lines[NLINES];
	int nlines;
	struct rotary enc[HAL_ENCODERS];
	struct rotary_config enc_cfg[HAL_ENCODERS];
	enum hal_turn enc_turn[HAL_ENCODERS];
	struct button sw[HAL_ENCODERS], btn[HAL_BUTTONS];
	enum hal_action sw_action[HAL_ENCODERS], btn_action[HAL_BUTTONS];
	uint64_t enc_debounce, btn_debounce, retry_ns, next_check;
	struct hal_log log;
};

static int chip_index(struct hal_gpio *g, const char *name)
{
	for (int i = 0; i < g->nchips; i++)
		if (!strcmp(g->chips[i].name, name))
			return i;
	snprintf(g->chips[g->nchips].name, HAL_NAME_MAX, "%s", name);
	return g->nchips++;
}

static int add_line(struct hal_gpio *g, const char *what, const char *chip, int offset, enum role role, int ctl,
		    bool active_low, enum hal_bias bias, char *err, size_t errlen)
{
	if (offset < 0)
		return 0;
	if (!chip || !chip[0]) {
		snprintf(err, errlen, "%s is line %d but no gpiochip is set (gpio_chip or the control's *_chip)", what,
			 offset);
		return -1;
	}
	int c = chip_index(g, chip);
	for (int i = 0; i < g->nlines; i++)
		if (g->lines[i].chip == c && g->lines[i].offset == offset) {
			snprintf(err, errlen, "%s: line %d of %s is used twice", what, offset, chip);
			return -1;
		}
	struct gline *l = &g->lines[g->nlines++];
	memset(l, 0, sizeof(*l));
	l->chip = c;
	l->offset = offset;
	l->role = role;
	l->ctl = ctl;
	l->active_low = active_low;
	l->bias = bias;
	l->fd = -1;
	return 0;
}

#ifdef HAVE_LIBGPIOD
static void chip_down(struct hal_gpio *g, int c)
{
	struct gchip *ch = &g->chips[c];
	for (int i = 0; i < g->nlines; i++) {
		struct gline *l = &g->lines[i];
		if (l->chip != c || !l->line)
			continue;
		hal_gpiod_line_release(l->line);
		l->line = NULL;
		l->fd = -1;
	}
	hal_gpiod_chip_close(ch->chip);
	ch->chip = NULL;
	ch->up = false;
}

static const char *line_desc(const struct gline *l, char *buf, size_t len)
{
	static const char *const role_name[] = { "A", "B", "switch", "" };
	if (l->role == R_BUTTON)
		snprintf(buf, len, "button%d", l->ctl + 1);
	else
		snprintf(buf, len, "enc%d %s", l->ctl + 1, role_name[l->role]);
	return buf;
}

static int is_chip_entry(const struct dirent *d)
{
	return !strncmp(d->d_name, "gpiochip", 8);
}

/* The chip whose label is label, or NULL (errno ENOENT when none has it). */
static struct hal_gpiod_chip *chip_by_label(const char *label)
{
	struct dirent **names;
	int n = scandir("/dev", &names, is_chip_entry, alphasort);
	if (n < 0)
		return NULL;
	struct hal_gpiod_chip *found = NULL;
	for (int i = 0; i < n; i++) {
		char path[300];
		snprintf(path, sizeof(path), "/dev/%s", names[i]->d_name);
		struct hal_gpiod_chip *c = found ? NULL : hal_gpiod_chip_open(path);
		if (c && !strcmp(hal_gpiod_chip_label(c), label))
			found = c;
		else
			hal_gpiod_chip_close(c);
		free(names[i]);
	}
	free(names);
	if (!found)
		errno = ENOENT;
	return found;
}

/* The chip named descr, looked up as libgpiod 1.6's gpiod_chip_open_lookup
 * does, on either API: a number N is /dev/gpiochipN; anything else is first
 * a label (which stays when a chip comes back as another gpiochipN), then a
 * path (with a slash) or a name in /dev.  NULL with errno from the last
 * attempt. */
struct hal_gpiod_chip *hal_gpio_chip_lookup(const char *descr)
{
	char path[HAL_NAME_MAX + 16];
	if (descr[strspn(descr, "0123456789")] == 0) {
		snprintf(path, sizeof(path), "/dev/gpiochip%s", descr);
		return hal_gpiod_chip_open(path);
	}
	struct hal_gpiod_chip *c = chip_by_label(descr);
	if (c)
		return c;
	snprintf(path, sizeof(path), "%s%s", strchr(descr, '/') ? "" : "/dev/", descr);
	return hal_gpiod_chip_open(path);
}

/* Opens chip c and requests its lines; false (with a one-time report) when
 * anything is missing. */
static bool chip_up(struct hal_gpio *g, int c, uint64_t now)
{
	struct gchip *ch = &g->chips[c];
	ch->next_try = now + g->retry_ns;
	ch->chip = hal_gpio_chip_lookup(ch->name);
	if (!ch->chip) {
		if (ch->problem != CH_MISSING)
			hal_logf(&g->log, HAL_WARN, "gpio: cannot open gpiochip '%s': %s; controls on it are off, retrying every %g s", ch->name,
				 strerror(errno), (double)g->retry_ns / 1e9);
		ch->problem = CH_MISSING;
		return false;
	}
	for (int i = 0; i < g->nlines; i++) {
		struct gline *l = &g->lines[i];
		if (l->chip != c)
			continue;
		char d[32];
		const char *fail = NULL;
		if ((unsigned)l->offset >= hal_gpiod_chip_lines(ch->chip))
			fail = "no such line";
		else if (!(l->line = hal_gpiod_line_request(ch->chip, (unsigned)l->offset, l->bias, l->active_low)))
			fail = errno == EBUSY ? "busy (requested by another program)" : strerror(errno);
		else if ((l->fd = hal_gpiod_line_fd(l->line)) < 0 || (l->level = hal_gpiod_line_value(l->line)) < 0)
			fail = strerror(errno);
		if (fail) {
			if (ch->problem != CH_LINES)
				hal_logf(&g->log, HAL_WARN, "gpio: %s: line %d of '%s' (%s): %s; retrying every %g s", line_desc(l, d, sizeof(d)),
					 l->offset, ch->name, hal_gpiod_chip_label(ch->chip), fail, (double)g->retry_ns / 1e9);
			ch->problem = CH_LINES;
			chip_down(g, c);
			return false;
		}
	}
	/* initial levels -> decoders */
	for (int i = 0; i < g->nlines; i++) {
		struct gline *l = &g->lines[i];
		if (l->chip != c)
			continue;
		if (l->role == R_ENC_A || l->role == R_ENC_B) {
			int a = -1, b = -1;
			for (int k = 0; k < g->nlines; k++) {
				const struct gline *o = &g->lines[k];
				if (o->role <= R_ENC_B && o->ctl == l->ctl)
					*(o->role == R_ENC_A ? &a : &b) = o->level;
			}
			if (a >= 0 && b >= 0)
				rotary_init(&g->enc[l->ctl], &g->enc_cfg[l->ctl], a, b);
		} else if (l->role == R_ENC_SW) {
			button_init(&g->sw[l->ctl], g->btn_debounce, l->level);
		} else {
			button_init(&g->btn[l->ctl], g->btn_debounce, l->level);
		}
	}
	hal_logf(&g->log, HAL_INFO, "gpio: %s (%s) %s", hal_gpiod_chip_name(ch->chip), hal_gpiod_chip_label(ch->chip),
		 ch->problem != CH_FINE ? "is back" : "ready");
	ch->up = true;
	ch->problem = CH_FINE;
	return true;
}

static void chip_gone(struct hal_gpio *g, int c, const char *why, uint64_t now)
{
	struct gchip *ch = &g->chips[c];
	hal_logf(&g->log, HAL_WARN, "gpio: gpiochip '%s' is gone (%s); controls on it are off, retrying every %g s", ch->name, why,
		 (double)g->retry_ns / 1e9);
	chip_down(g, c);
	ch->problem = CH_MISSING;
	ch->next_try = now + g->retry_ns;
}

struct edge {
	int line, level;
	uint64_t ts;
};

/* Stable insertion sort by timestamp (a few edges per frame; equal
 * timestamps keep their order of reading). */
static void sort_edges(struct edge *e, int n)
{
	for (int i = 1; i < n; i++) {
		struct edge x = e[i];
		int j = i;
		for (; j > 0 && e[j - 1].ts > x.ts; j--)
			e[j] = e[j - 1];
		e[j] = x;
	}
}

/* Event clock -> CLOCK_MONOTONIC (kernels before 5.7 stamped v1 events with
 * CLOCK_REALTIME). */
static uint64_t event_ns(uint64_t t, uint64_t now)
{
	uint64_t d = t > now ? t - now : now - t;
	if (d > 3600ull * 1000000000ull) {
		struct timespec rt;
		clock_gettime(CLOCK_REALTIME, &rt);
		uint64_t r = (uint64_t)rt.tv_sec * 1000000000ull + (uint64_t)rt.tv_nsec;
		t = t + now - r;
	}
	return t;
}
#endif

static const char *chip_or(const char *chip, const char *fallback)
{
	return chip && chip[0] ? chip : fallback;
}

/* Encoder e: its decoder and its lines (A, B, switch). */
static int add_encoder(struct hal_gpio *g, const struct hal_gpio_config *cfg, int e, char *err, size_t errlen)
{
	const struct hal_encoder_config *ec = &cfg->enc[e];
	const char *chip = chip_or(ec->chip, cfg->chip);
	if ((ec->a < 0) != (ec->b < 0)) {
		snprintf(err, errlen, "enc%d: set both enc%d_a and enc%d_b (or neither)", e + 1, e + 1, e + 1);
		return -1;
	}
	g->enc_cfg[e] = (struct rotary_config){ .steps_per_detent = ec->steps_per_detent,
						.debounce_ns = g->enc_debounce,
						.accel_ns = (uint64_t)(cfg->enc_accel_ms * 1e6),
						.accel_max = cfg->enc_accel_max };
	if (!rotary_init(&g->enc[e], &g->enc_cfg[e], 0, 0)) {
		snprintf(err, errlen, "enc%d_steps_per_detent must be 1, 2 or 4 (got %d)", e + 1, ec->steps_per_detent);
		return -1;
	}
	if ((unsigned)ec->sw_action >= HAL_ACTION_COUNT) {
		snprintf(err, errlen, "enc%d: bad switch action %d", e + 1, (int)ec->sw_action);
		return -1;
	}
	g->enc_turn[e] = ec->turn;
	g->sw_action[e] = ec->sw_action;
	button_init(&g->sw[e], g->btn_debounce, 0);
	static const char *const suffix[] = { "a", "b", "sw" };
	const int line[] = { ec->a, ec->b, ec->sw };
	const enum role role[] = { R_ENC_A, R_ENC_B, R_ENC_SW };
	for (int k = 0; k < 3; k++) {
		char what[32];
		snprintf(what, sizeof(what), "enc%d_%s", e + 1, suffix[k]);
		if (add_line(g, what, chip, line[k], role[k], e, ec->active_low, ec->bias, err, errlen) < 0)
			return -1;
	}
	return 0;
}

struct hal_gpio *hal_gpio_open(const struct hal_gpio_config *cfg, char *err, size_t errlen)
{
	err[0] = 0;
	struct hal_gpio *g = calloc(1, sizeof(*g));
	if (!g) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	g->log = cfg->log;
	g->enc_debounce = (uint64_t)(cfg->enc_debounce_ms * 1e6);
	g->btn_debounce = (uint64_t)(cfg->button_debounce_ms * 1e6);
	g->retry_ns = (uint64_t)(cfg->retry_s * 1e9);
	int rc = 0;
	for (int e = 0; e < HAL_ENCODERS && rc == 0; e++)
		rc = add_encoder(g, cfg, e, err, errlen);
	const char *bchip = chip_or(cfg->button_chip, cfg->chip);
	for (int b = 0; b < HAL_BUTTONS && rc == 0; b++) {
		char what[32];
		snprintf(what, sizeof(what), "button%d_line", b + 1);
		if ((unsigned)cfg->button[b].action >= HAL_ACTION_COUNT) {
			snprintf(err, errlen, "button%d: bad action %d", b + 1, (int)cfg->button[b].action);
			rc = -1;
			break;
		}
		g->btn_action[b] = cfg->button[b].action;
		button_init(&g->btn[b], g->btn_debounce, 0);
		rc = add_line(g, what, bchip, cfg->button[b].line, R_BUTTON, b, cfg->button_active_low, cfg->button_bias,
			      err, errlen);
	}
	if (rc < 0 || g->nlines == 0) {
		free(g);
		return NULL;
	}
#ifdef HAVE_LIBGPIOD
	uint64_t now = hal_now_ns();
	hal_logf(&g->log, HAL_DEBUG, "gpio: libgpiod %s", hal_gpiod_version());
	for (int c = 0; c < g->nchips; c++)
		chip_up(g, c, now);
	g->next_check = now + g->retry_ns;
#else
	hal_logf(&g->log, HAL_WARN,
		 "gpio: this build has no libgpiod (install libgpiod-dev and rebuild); GPIO controls are off");
#endif
	return g;
}

void hal_gpio_close(struct hal_gpio *g)
{
	if (!g)
		return;
#ifdef HAVE_LIBGPIOD
	for (int c = 0; c < g->nchips; c++)
		chip_down(g, c);
#endif
	free(g);
}

#ifdef HAVE_LIBGPIOD
/* (Re)opens missing chips; checks now and then that open ones are still
 * there (a removed chip's lines answer ENODEV). */
static void check_chips(struct hal_gpio *g, uint64_t now)
{
	bool check = now >= g->next_check;
	if (check)
		g->next_check = now + g->retry_ns;
	for (int c = 0; c < g->nchips; c++) {
		struct gchip *ch = &g->chips[c];
		if (!ch->up && now >= ch->next_try)
			chip_up(g, c, now);
		else if (ch->up && check) {
			for (int i = 0; i < g->nlines; i++)
				if (g->lines[i].chip == c && g->lines[i].line) {
					if (hal_gpiod_chip_check(ch->chip, (unsigned)g->lines[i].offset) < 0)
						chip_gone(g, c, strerror(errno), now);
					break;
				}
		}
	}
}

/* Reads every pending edge of every line into ev (at most
 * NLINES * HAL_GPIOD_EVENTS), sorted by kernel timestamp.
 *
 * Each line has its own event fd, so the edges of an encoder's A and B
 * lines arrive in separate queues: when several accumulated since the last
 * frame (a slow frame, a fast turn), decoding one queue after the other
 * would scramble the Gray sequence.  All of them are merged by their kernel
 * timestamps first. */
static int read_edges(struct hal_gpio *g, uint64_t now, struct edge *ev_all)
{
	struct pollfd pfd[NLINES];
	int idx[NLINES], n = 0;
	for (int i = 0; i < g->nlines; i++)
		if (g->lines[i].line && g->lines[i].fd >= 0) {
			pfd[n].fd = g->lines[i].fd;
			pfd[n].events = POLLIN;
			pfd[n].revents = 0;
			idx[n++] = i;
		}
	int pr = n ? poll(pfd, (nfds_t)n, 0) : 0;
	if (pr < 0 && errno != EINTR)
		hal_logf(&g->log, HAL_WARN, "gpio: poll: %s", strerror(errno));
	int nev = 0;
	for (int k = 0; k < n && pr > 0; k++) {
		struct gline *l = &g->lines[idx[k]];
		if (!l->line) /* its chip went away while handling an earlier fd */
			continue;
		if (pfd[k].revents & (POLLERR | POLLHUP | POLLNVAL)) {
			chip_gone(g, l->chip, "poll error", now);
			continue;
		}
		if (!(pfd[k].revents & POLLIN))
			continue;
		struct hal_gpiod_edge ev[HAL_GPIOD_EVENTS];
		int ne = hal_gpiod_line_read(l->line, ev, HAL_GPIOD_EVENTS);
		if (ne < 0) {
			chip_gone(g, l->chip, strerror(errno), now);
			continue;
		}
		for (int e = 0; e < ne; e++)
			ev_all[nev++] = (struct edge){ .line = idx[k], .level = ev[e].rising, .ts = event_ns(ev[e].ts_ns, now) };
	}
	sort_edges(ev_all, nev);
	return nev;
}

/* The edges, in time order, into the decoders. */
static void decode_edges(struct hal_gpio *g, const struct edge *ev, int nev)
{
	for (int e = 0; e < nev; e++) {
		struct gline *l = &g->lines[ev[e].line];
		int level = ev[e].level;
		uint64_t ts = ev[e].ts;
		l->level = level;
		switch (l->role) {
		case R_ENC_A: rotary_edge(&g->enc[l->ctl], 0, level, ts); break;
		case R_ENC_B: rotary_edge(&g->enc[l->ctl], 1, level, ts); break;
		case R_ENC_SW: button_edge(&g->sw[l->ctl], level, ts); break;
		case R_BUTTON: button_edge(&g->btn[l->ctl], level, ts); break;
		}
	}
}
#endif

void hal_gpio_poll(struct hal_gpio *g, uint64_t now, struct hal_input *in)
{
	if (!g)
		return;
#ifdef HAVE_LIBGPIOD
	check_chips(g, now);
	struct edge ev[NLINES * HAL_GPIOD_EVENTS];
	decode_edges(g, ev, read_edges(g, now, ev));
#endif
	/* settle what has been stable long enough; collect */
	for (int e = 0; e < HAL_ENCODERS; e++) {
		rotary_flush(&g->enc[e], now);
		int d = rotary_take(&g->enc[e]);
		if (g->enc_turn[e] == HAL_TURN_SELECT)
			in->select += d;
		else
			in->change += d;
		button_flush(&g->sw[e], now);
		in->actions[g->sw_action[e]] += button_take(&g->sw[e]);
	}
	for (int b = 0; b < HAL_BUTTONS; b++) {
		button_flush(&g->btn[b], now);
		in->actions[g->btn_action[b]] += button_take(&g->btn[b]);
	}
}
