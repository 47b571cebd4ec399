/* isoterra — development keys: the terminal in raw mode (stdin a tty) or an
 * evdev keyboard, mapped to the same inputs as the knobs:
 *   left/right or [ ]   choose the parameter      up/down or - +   change it
 *   p pause   s screenshot   n next preset   r reset   q / Esc quit
 *   manual camera: i/k forward/back, j/l turn, u/o up/down, y/h pitch */
#include "hal.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/input.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

struct hal_keys {
	int tty_fd;            /* -1 when not used */
	struct termios saved;
	int esc;
	int ev_fd;             /* evdev, -1 when not used */
	char ev_path[HAL_NAME_MAX];
	uint64_t ev_next_try;  /* while ev_fd < 0: when to try opening it again */
	bool ev_warned;        /* the failure to open it again is logged once */
	struct hal_log log;
};

#define EV_RETRY_NS 2000000000ull /* a vanished evdev keyboard: every 2 s */
#define EV_READS_PER_POLL 4        /* at most 4 x 32 events a frame: a poll always returns */

void hal_keys_feed_tty(const unsigned char *buf, size_t n, int *esc, struct hal_input *in)
{
	for (size_t i = 0; i < n; i++) {
		unsigned char c = buf[i];
		if (*esc == 1) { /* after ESC */
			*esc = c == '[' || c == 'O' ? 2 : 0;
			if (!*esc)
				in->actions[HAL_QUIT]++; /* a lone Esc followed by a key */
			continue;
		}
		if (*esc == 2) {
			*esc = 0;
			switch (c) {
			case 'A': in->change++; break;
			case 'B': in->change--; break;
			case 'C': in->select++; break;
			case 'D': in->select--; break;
			default: break;
			}
			continue;
		}
		switch (c) {
		case 27: *esc = 1; break;
		case ']': in->select++; break;
		case '[': in->select--; break;
		case '+': case '=': in->change++; break;
		case '-': case '_': in->change--; break;
		case 'p': case ' ': in->actions[HAL_PAUSE]++; break;
		case 's': in->actions[HAL_SCREENSHOT]++; break;
		case 'n': in->actions[HAL_PRESET]++; break;
		case 'r': in->actions[HAL_RESET]++; break;
		case 'q': case 3: in->actions[HAL_QUIT]++; break;
		case 'i': in->fly[HAL_FLY_FORWARD]++; break;
		case 'k': in->fly[HAL_FLY_FORWARD]--; break;
		case 'l': in->fly[HAL_FLY_YAW]++; break;
		case 'j': in->fly[HAL_FLY_YAW]--; break;
		case 'u': in->fly[HAL_FLY_UP]++; break;
		case 'o': in->fly[HAL_FLY_UP]--; break;
		case 'y': in->fly[HAL_FLY_PITCH]++; break;
		case 'h': in->fly[HAL_FLY_PITCH]--; break;
		default: break;
		}
	}
}

/* The terminal in raw mode (no echo, no line buffering, reads never
 * block); NULL when it cannot be (reported: keys are off). */
static struct hal_keys *open_tty(struct hal_keys *k)
{
	struct termios raw;
	if (tcgetattr(STDIN_FILENO, &k->saved) < 0) {
		hal_logf(&k->log, HAL_WARN, "keys: tcgetattr: %s; keys are off", strerror(errno));
		free(k);
		return NULL;
	}
	raw = k->saved;
	raw.c_lflag &= ~(tcflag_t)(ICANON | ECHO);
	raw.c_cc[VMIN] = 0;
	raw.c_cc[VTIME] = 0;
	if (tcsetattr(STDIN_FILENO, TCSANOW, &raw) < 0) {
		hal_logf(&k->log, HAL_WARN, "keys: tcsetattr: %s; keys are off", strerror(errno));
		free(k);
		return NULL;
	}
	k->tty_fd = STDIN_FILENO;
	hal_logf(&k->log, HAL_INFO,
		 "keys: arrows or [ ] select, - + change, p pause, s screenshot, n preset, r reset, q quit");
	return k;
}

/* Opens k->ev_path (non-blocking) and checks that it is an evdev node (the
 * EVIOCGVERSION ioctl answers): 0, -1 when it cannot be opened (missing,
 * no permission: worth retrying), -2 when it is a file of another kind. */
static int evdev_open(struct hal_keys *k, char *why, size_t len)
{
	int fd = open(k->ev_path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
	if (fd < 0) {
		snprintf(why, len, "cannot open %s: %s", k->ev_path, strerror(errno));
		return -1;
	}
	int version = 0;
	if (ioctl(fd, EVIOCGVERSION, &version) < 0) {
		snprintf(why, len, "%s is not an evdev input device (EVIOCGVERSION: %s)", k->ev_path, strerror(errno));
		close(fd);
		return -2;
	}
	k->ev_fd = fd;
	return 0;
}

struct hal_keys *hal_keys_open(const struct hal_keys_config *cfg, char *err, size_t errlen)
{
	err[0] = 0;
	enum hal_keys_mode mode = cfg->mode;
	if (mode == HAL_KEYS_OFF)
		return NULL;
	if (mode == HAL_KEYS_EVDEV && (!cfg->evdev || !cfg->evdev[0])) {
		snprintf(err, errlen, "--keyboard evdev needs --keyboard-evdev /dev/input/eventN");
		return NULL;
	}
	bool tty = isatty(STDIN_FILENO);
	if (mode == HAL_KEYS_TTY && !tty) {
		snprintf(err, errlen, "--keyboard tty: standard input is not a terminal");
		return NULL;
	}
	if (mode == HAL_KEYS_AUTO && !tty)
		return NULL;
	struct hal_keys *k = calloc(1, sizeof(*k));
	if (!k) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	k->tty_fd = k->ev_fd = -1;
	k->log = cfg->log;
	if (mode != HAL_KEYS_EVDEV)
		return open_tty(k);
	snprintf(k->ev_path, sizeof(k->ev_path), "%s", cfg->evdev);
	char why[HAL_NAME_MAX + 96];
	int rc = evdev_open(k, why, sizeof(why));
	if (rc == -2) { /* a file of another kind: a configuration error, not a missing device */
		snprintf(err, errlen, "--keyboard-evdev %s", why);
		free(k);
		return NULL;
	}
	if (rc < 0) {
		hal_logf(&k->log, HAL_WARN, "keys: %s; retrying every 2 s", why);
		k->ev_warned = true;
		k->ev_next_try = hal_now_ns() + EV_RETRY_NS;
	}
	return k;
}

void hal_keys_close(struct hal_keys *k)
{
	if (!k)
		return;
	if (k->tty_fd >= 0)
		tcsetattr(k->tty_fd, TCSANOW, &k->saved);
	if (k->ev_fd >= 0)
		close(k->ev_fd);
	free(k);
}

static void evdev_key(int code, struct hal_input *in)
{
	switch (code) {
	case KEY_UP: case KEY_EQUAL: case KEY_KPPLUS: in->change++; break;
	case KEY_DOWN: case KEY_MINUS: case KEY_KPMINUS: in->change--; break;
	case KEY_RIGHT: case KEY_RIGHTBRACE: in->select++; break;
	case KEY_LEFT: case KEY_LEFTBRACE: in->select--; break;
	case KEY_P: case KEY_SPACE: in->actions[HAL_PAUSE]++; break;
	case KEY_S: in->actions[HAL_SCREENSHOT]++; break;
	case KEY_N: in->actions[HAL_PRESET]++; break;
	case KEY_R: in->actions[HAL_RESET]++; break;
	case KEY_Q: case KEY_ESC: in->actions[HAL_QUIT]++; break;
	case KEY_I: in->fly[HAL_FLY_FORWARD]++; break;
	case KEY_K: in->fly[HAL_FLY_FORWARD]--; break;
	case KEY_L: in->fly[HAL_FLY_YAW]++; break;
	case KEY_J: in->fly[HAL_FLY_YAW]--; break;
	case KEY_U: in->fly[HAL_FLY_UP]++; break;
	case KEY_O: in->fly[HAL_FLY_UP]--; break;
	case KEY_Y: in->fly[HAL_FLY_PITCH]++; break;
	case KEY_H: in->fly[HAL_FLY_PITCH]--; break;
	default: break;
	}
}

int hal_keys_feed_evdev(const void *buf, size_t n, struct hal_input *in)
{
	if (n % sizeof(struct input_event))
		return -1;
	const unsigned char *b = buf;
	for (size_t i = 0; i < n / sizeof(struct input_event); i++) {
		struct input_event ev;
		memcpy(&ev, b + i * sizeof(ev), sizeof(ev));
		if (ev.type == EV_KEY && ev.value >= 1) /* press and auto-repeat */
			evdev_key(ev.code, in);
	}
	return (int)(n / sizeof(struct input_event));
}

static void evdev_lost(struct hal_keys *k, const char *why)
{
	hal_logf(&k->log, HAL_WARN, "keys: %s: %s; retrying every 2 s", k->ev_path, why);
	close(k->ev_fd);
	k->ev_fd = -1;
	k->ev_warned = true;
	k->ev_next_try = hal_now_ns() + EV_RETRY_NS;
}

static void evdev_retry(struct hal_keys *k)
{
	uint64_t now = hal_now_ns();
	if (now < k->ev_next_try)
		return;
	k->ev_next_try = now + EV_RETRY_NS;
	char why[HAL_NAME_MAX + 96];
	if (evdev_open(k, why, sizeof(why)) == 0) {
		hal_logf(&k->log, HAL_INFO, "keys: %s opened", k->ev_path);
		k->ev_warned = false;
	} else if (!k->ev_warned) {
		hal_logf(&k->log, HAL_WARN, "keys: %s; retrying every 2 s", why);
		k->ev_warned = true;
	}
}

/* At most EV_READS_PER_POLL reads: a device that never runs dry (or a
 * flood of events) cannot hold the frame loop. */
static void evdev_poll(struct hal_keys *k, struct hal_input *in)
{
	struct input_event ev[32];
	for (int r = 0; r < EV_READS_PER_POLL; r++) {
		ssize_t n = read(k->ev_fd, ev, sizeof(ev));
		if (n < 0) {
			if (errno != EAGAIN && errno != EINTR)
				evdev_lost(k, strerror(errno));
			return;
		}
		if (n == 0) {
			evdev_lost(k, "end of file");
			return;
		}
		if (hal_keys_feed_evdev(ev, (size_t)n, in) < 0) { /* evdev only ever returns whole events */
			char why[96];
			snprintf(why, sizeof(why), "a read of %zd bytes is not a whole number of events", n);
			evdev_lost(k, why);
			return;
		}
		if ((size_t)n < sizeof(ev))
			return;
	}
}

void hal_keys_poll(struct hal_keys *k, struct hal_input *in)
{
	if (!k)
		return;
	if (k->tty_fd >= 0) {
		unsigned char buf[64];
		ssize_t n = read(k->tty_fd, buf, sizeof(buf)); /* VMIN 0 VTIME 0: never blocks */
		if (n > 0)
			hal_keys_feed_tty(buf, (size_t)n, &k->esc, in);
	}
	if (k->ev_path[0] && k->ev_fd < 0)
		evdev_retry(k);
	if (k->ev_fd >= 0)
		evdev_poll(k, in);
}
