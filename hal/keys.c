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
#include <termios.h>
#include <unistd.h>

struct hal_keys {
	int tty_fd;            /* -1 when not used */
	struct termios saved;
	int esc;
	int ev_fd;             /* evdev, -1 when not used */
	char ev_path[HAL_NAME_MAX];
	uint64_t ev_next_try;  /* while ev_fd < 0: when to try opening it again */
	struct hal_log log;
};

#define EV_RETRY_NS 2000000000ull /* a vanished evdev keyboard: every 2 s */

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
	k->ev_fd = open(k->ev_path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
	if (k->ev_fd < 0) {
		hal_logf(&k->log, HAL_WARN, "keys: cannot open %s: %s; retrying every 2 s", k->ev_path, strerror(errno));
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
	if (k->ev_path[0] && k->ev_fd < 0) {
		uint64_t now = hal_now_ns();
		if (now >= k->ev_next_try) {
			k->ev_next_try = now + EV_RETRY_NS;
			if ((k->ev_fd = open(k->ev_path, O_RDONLY | O_NONBLOCK | O_CLOEXEC)) >= 0)
				hal_logf(&k->log, HAL_INFO, "keys: %s opened", k->ev_path);
		}
	}
	if (k->ev_fd >= 0) {
		struct input_event ev[32];
		for (;;) {
			ssize_t n = read(k->ev_fd, ev, sizeof(ev));
			if (n < 0) {
				if (errno != EAGAIN && errno != EINTR) {
					hal_logf(&k->log, HAL_WARN, "keys: %s: %s; retrying every 2 s", k->ev_path,
						 strerror(errno));
					close(k->ev_fd);
					k->ev_fd = -1;
					k->ev_next_try = hal_now_ns() + EV_RETRY_NS;
				}
				break;
			}
			for (size_t i = 0; i < (size_t)n / sizeof(ev[0]); i++)
				if (ev[i].type == EV_KEY && ev[i].value >= 1) /* press and auto-repeat */
					evdev_key(ev[i].code, in);
			if ((size_t)n < sizeof(ev))
				break;
		}
	}
}
