/* isoterra — a gamepad's state and its stick math (see stick.h). */
#include "stick.h"

#include <linux/input-event-codes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

_Static_assert(STICK_ABS_MAX == ABS_CNT, "the axes' table covers every ABS code");
_Static_assert(STICK_KEY_MAX == KEY_CNT, "the keys' bitmap covers every KEY code");

static const char *const role_names[STICK_ROLES] = {
	[STICK_FORWARD] = "forward",	     [STICK_STRAFE] = "strafe",
	[STICK_YAW] = "yaw",		     [STICK_PITCH] = "pitch",
	[STICK_CLIMB] = "climb",	     [STICK_DESCEND] = "descend",
	[STICK_SELECT_NEXT] = "select_next", [STICK_SELECT_PREV] = "select_prev",
	[STICK_CHANGE_UP] = "change_up",     [STICK_CHANGE_DOWN] = "change_down",
	[STICK_RESET] = "reset",	     [STICK_AUTOPILOT] = "autopilot",
	[STICK_PAUSE] = "pause",	     [STICK_SCREENSHOT] = "screenshot",
	[STICK_PRESET] = "preset",	     [STICK_QUIT] = "quit",
};

const char *stick_role_name(enum stick_role r)
{
	return (unsigned)r < STICK_ROLES ? role_names[r] : "?";
}

/* ---- the math -------------------------------------------------------------- */
static float clampf(float v, float lo, float hi)
{
	return v < lo ? lo : v > hi ? hi : v;
}

float stick_norm_centred(int v, const struct stick_absinfo *ai)
{
	if (ai->max <= ai->min)
		return 0.0f;
	double mid = ((double)ai->min + ai->max) / 2.0, half = ((double)ai->max - ai->min) / 2.0;
	return clampf((float)((v - mid) / half), -1.0f, 1.0f);
}

float stick_norm_trigger(int v, const struct stick_absinfo *ai)
{
	if (ai->max <= ai->min)
		return 0.0f;
	return clampf((float)(((double)v - ai->min) / ((double)ai->max - ai->min)), 0.0f, 1.0f);
}

float stick_flat_fraction(const struct stick_absinfo *ai)
{
	if (ai->max <= ai->min || ai->flat <= 0)
		return 0.0f;
	return clampf((float)(ai->flat / (((double)ai->max - ai->min) / 2.0)), 0.0f, 1.0f);
}

/* A magnitude m (0..1) past the dead zone dz, rescaled to 0..1, curved. */
static float shape(float m, float dz, float curve)
{
	m = clampf(m, 0.0f, 1.0f);
	if (m <= dz || dz >= 1.0f)
		return 0.0f;
	float r = (m - dz) / (1.0f - dz);
	return curve == 1.0f ? r : powf(r, curve);
}

void stick_radial(float x, float y, float dz, float curve, float *ox, float *oy)
{
	float m = sqrtf(x * x + y * y);
	if (m <= 0.0f) {
		*ox = *oy = 0.0f;
		return;
	}
	float r = shape(m, dz, curve);
	*ox = x / m * r;
	*oy = y / m * r;
}

float stick_trigger(float t, float dz, float curve)
{
	return shape(t, dz, curve);
}

/* ---- names ------------------------------------------------------------------- */
struct code_name {
	const char *name;
	enum stick_src src;
	int code;
};
#define A(x) { #x, STICK_ABS, x }
#define K(x) { #x, STICK_KEY, x }
static const struct code_name code_names[] = {
	A(ABS_X), A(ABS_Y), A(ABS_Z), A(ABS_RX), A(ABS_RY), A(ABS_RZ), A(ABS_THROTTLE), A(ABS_RUDDER),
	A(ABS_WHEEL), A(ABS_GAS), A(ABS_BRAKE), A(ABS_HAT0X), A(ABS_HAT0Y), A(ABS_HAT1X), A(ABS_HAT1Y),
	A(ABS_HAT2X), A(ABS_HAT2Y), A(ABS_HAT3X), A(ABS_HAT3Y),
	K(BTN_SOUTH), K(BTN_EAST), K(BTN_C), K(BTN_NORTH), K(BTN_WEST), K(BTN_Z), K(BTN_TL), K(BTN_TR),
	K(BTN_TL2), K(BTN_TR2), K(BTN_SELECT), K(BTN_START), K(BTN_MODE), K(BTN_THUMBL), K(BTN_THUMBR),
	K(BTN_A), K(BTN_B), K(BTN_X), K(BTN_Y), /* aliases of SOUTH, EAST, NORTH, WEST */
	K(BTN_DPAD_UP), K(BTN_DPAD_DOWN), K(BTN_DPAD_LEFT), K(BTN_DPAD_RIGHT),
	K(BTN_TRIGGER), K(BTN_THUMB), K(BTN_THUMB2), K(BTN_TOP), K(BTN_TOP2), K(BTN_PINKIE), K(BTN_BASE),
	K(BTN_BASE2), K(BTN_BASE3), K(BTN_BASE4), K(BTN_BASE5), K(BTN_BASE6), K(BTN_DEAD),
	K(BTN_TRIGGER_HAPPY1), K(BTN_TRIGGER_HAPPY2), K(BTN_TRIGGER_HAPPY3), K(BTN_TRIGGER_HAPPY4),
	K(KEY_UP), K(KEY_DOWN), K(KEY_LEFT), K(KEY_RIGHT), K(KEY_ENTER), K(KEY_SPACE), K(KEY_ESC),
	K(KEY_BACK), K(KEY_HOMEPAGE), K(KEY_MENU),
};
#undef A
#undef K

const char *stick_binding_name(const struct stick_binding *b, char *buf, size_t len)
{
	if (b->src == STICK_NONE) {
		snprintf(buf, len, "none");
		return buf;
	}
	const char *sign = b->sign < 0 ? "-" : "";
	for (size_t i = 0; i < sizeof(code_names) / sizeof(code_names[0]); i++)
		if (code_names[i].src == b->src && code_names[i].code == b->code) {
			snprintf(buf, len, "%s%s", sign, code_names[i].name);
			return buf;
		}
	snprintf(buf, len, "%s%s:%d", sign, b->src == STICK_ABS ? "abs" : "key", b->code);
	return buf;
}

/* One binding from text (no spaces): 0, or -1 with err. */
static int parse_binding(const char *t, struct stick_binding *b, char *err, size_t errlen)
{
	*b = (struct stick_binding){ .src = STICK_NONE, .sign = 1 };
	if (!strcasecmp(t, "none"))
		return 0;
	const char *s = t;
	if (*s == '-' || *s == '+')
		b->sign = *s++ == '-' ? -1 : 1;
	for (size_t i = 0; i < sizeof(code_names) / sizeof(code_names[0]); i++)
		if (!strcasecmp(s, code_names[i].name)) {
			b->src = code_names[i].src;
			b->code = code_names[i].code;
			return 0;
		}
	bool abs = !strncasecmp(s, "abs:", 4), key = !strncasecmp(s, "key:", 4);
	if (abs || key) {
		char *end;
		long v = strtol(s + 4, &end, 0);
		long max = abs ? STICK_ABS_MAX : STICK_KEY_MAX;
		if (end != s + 4 && !*end && v >= 0 && v < max) {
			b->src = abs ? STICK_ABS : STICK_KEY;
			b->code = (int)v;
			return 0;
		}
		snprintf(err, errlen, "'%s': the code must be 0..%ld", t, max - 1);
		return -1;
	}
	snprintf(err, errlen, "'%s' is no input name (ABS_*, BTN_*, abs:N, key:N or none)", t);
	return -1;
}

void stick_map_default(struct stick_binding map[STICK_ROLES][STICK_BINDINGS])
{
	memset(map, 0, sizeof(struct stick_binding) * STICK_ROLES * STICK_BINDINGS);
#define BIND(role, slot, s, c, sg) map[role][slot] = (struct stick_binding){ s, c, sg }
	BIND(STICK_FORWARD, 0, STICK_ABS, ABS_Y, -1); /* stick pushed up: negative Y */
	BIND(STICK_STRAFE, 0, STICK_ABS, ABS_X, 1);
	BIND(STICK_YAW, 0, STICK_ABS, ABS_RX, 1);
	BIND(STICK_PITCH, 0, STICK_ABS, ABS_RY, -1);
	BIND(STICK_CLIMB, 0, STICK_ABS, ABS_RZ, 1); /* analogue triggers ... */
	BIND(STICK_CLIMB, 1, STICK_KEY, BTN_TR2, 1); /* ... or digital ones */
	BIND(STICK_DESCEND, 0, STICK_ABS, ABS_Z, 1);
	BIND(STICK_DESCEND, 1, STICK_KEY, BTN_TL2, 1);
	BIND(STICK_SELECT_NEXT, 0, STICK_ABS, ABS_HAT0X, 1); /* the D-pad as a hat ... */
	BIND(STICK_SELECT_NEXT, 1, STICK_KEY, BTN_DPAD_RIGHT, 1); /* ... or as buttons */
	BIND(STICK_SELECT_PREV, 0, STICK_ABS, ABS_HAT0X, -1);
	BIND(STICK_SELECT_PREV, 1, STICK_KEY, BTN_DPAD_LEFT, 1);
	BIND(STICK_CHANGE_UP, 0, STICK_ABS, ABS_HAT0Y, -1); /* hat up: negative Y */
	BIND(STICK_CHANGE_UP, 1, STICK_KEY, BTN_DPAD_UP, 1);
	BIND(STICK_CHANGE_DOWN, 0, STICK_ABS, ABS_HAT0Y, 1);
	BIND(STICK_CHANGE_DOWN, 1, STICK_KEY, BTN_DPAD_DOWN, 1);
	BIND(STICK_RESET, 0, STICK_KEY, BTN_SELECT, 1);
	BIND(STICK_RESET, 1, STICK_KEY, BTN_THUMB, 1); /* a joystick's second button */
	BIND(STICK_AUTOPILOT, 0, STICK_KEY, BTN_START, 1);
	BIND(STICK_AUTOPILOT, 1, STICK_KEY, BTN_TRIGGER, 1); /* a joystick's trigger */
	BIND(STICK_PAUSE, 0, STICK_KEY, BTN_NORTH, 1);
	BIND(STICK_PRESET, 0, STICK_KEY, BTN_WEST, 1);
#undef BIND
}

int stick_map_parse(const char *s, struct stick_binding map[STICK_ROLES][STICK_BINDINGS], char *err,
		    size_t errlen)
{
	char buf[1024];
	if (!s)
		return 0;
	if (strlen(s) >= sizeof(buf)) {
		snprintf(err, errlen, "too long");
		return -1;
	}
	/* spaces are dropped: "forward = -ABS_Y, yaw = ABS_RX" */
	size_t n = 0;
	for (const char *c = s; *c; c++)
		if (*c != ' ' && *c != '\t')
			buf[n++] = *c;
	buf[n] = 0;
	char *save = NULL;
	for (char *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
		char *eq = strchr(item, '=');
		if (!eq) {
			snprintf(err, errlen, "'%s': want role=input", item);
			return -1;
		}
		*eq = 0;
		int role = -1;
		for (int r = 0; r < STICK_ROLES; r++)
			if (!strcasecmp(item, role_names[r]))
				role = r;
		if (role < 0) {
			snprintf(err, errlen, "unknown role '%s' (forward, strafe, yaw, pitch, climb, descend, select_next, "
					      "select_prev, change_up, change_down, reset, autopilot, pause, screenshot, preset, quit)",
				 item);
			return -1;
		}
		struct stick_binding b[STICK_BINDINGS];
		int nb = 0;
		char *save2 = NULL;
		for (char *t = strtok_r(eq + 1, "|", &save2); t; t = strtok_r(NULL, "|", &save2)) {
			if (nb == STICK_BINDINGS) {
				snprintf(err, errlen, "%s: at most %d inputs", item, STICK_BINDINGS);
				return -1;
			}
			char e[160];
			if (parse_binding(t, &b[nb], e, sizeof(e)) < 0) {
				snprintf(err, errlen, "%s: %s", item, e);
				return -1;
			}
			nb++;
		}
		if (!nb) {
			snprintf(err, errlen, "%s: no input (none unbinds it)", item);
			return -1;
		}
		for (int i = 0; i < STICK_BINDINGS; i++)
			map[role][i] = i < nb ? b[i] : (struct stick_binding){ .src = STICK_NONE, .sign = 1 };
	}
	return 0;
}

/* ---- a pad's state ---------------------------------------------------------- */
void stick_pad_init(struct stick_pad *pad, const struct stick_config *cfg,
		    const struct stick_binding map[STICK_ROLES][STICK_BINDINGS])
{
	memset(pad, 0, sizeof(*pad));
	pad->cfg = *cfg;
	memcpy(pad->map, map, sizeof(pad->map));
}

void stick_pad_set_abs(struct stick_pad *pad, int code, const struct stick_absinfo *ai, int value)
{
	if (code < 0 || code >= STICK_ABS_MAX)
		return;
	pad->abs[code] = *ai;
	pad->has_abs[code] = true;
	pad->absval[code] = value;
}

void stick_pad_set_key(struct stick_pad *pad, int code, bool down)
{
	if (code < 0 || code >= STICK_KEY_MAX)
		return;
	if (down)
		pad->key[code / 8] |= (uint8_t)(1u << (code % 8));
	else
		pad->key[code / 8] &= (uint8_t)~(1u << (code % 8));
}

static bool key_down(const struct stick_pad *pad, int code)
{
	return code >= 0 && code < STICK_KEY_MAX && (pad->key[code / 8] >> (code % 8) & 1);
}

/* A button role is held while any of its inputs is: a key down, or an
 * axis past half way on the binding's side. */
static bool role_held(const struct stick_pad *pad, int role)
{
	for (int i = 0; i < STICK_BINDINGS; i++) {
		const struct stick_binding *b = &pad->map[role][i];
		if (b->src == STICK_KEY && key_down(pad, b->code))
			return true;
		if (b->src == STICK_ABS && b->code < STICK_ABS_MAX && pad->has_abs[b->code] &&
		    b->sign * stick_norm_centred(pad->absval[b->code], &pad->abs[b->code]) > 0.5f)
			return true;
	}
	return false;
}

static bool repeats(int role)
{
	return role >= STICK_SELECT_NEXT && role <= STICK_CHANGE_DOWN;
}

/* Button roles after a report: a new press counts. */
static void report(struct stick_pad *pad, uint64_t now_ns)
{
	for (int r = STICK_FIRST_BUTTON; r < STICK_ROLES; r++) {
		bool h = role_held(pad, r);
		if (h && !pad->held[r]) {
			pad->presses[r]++;
			pad->held_since[r] = now_ns;
			pad->repeat_next[r] = now_ns + (uint64_t)(pad->cfg.repeat_delay_ms * 1e6);
		}
		pad->held[r] = h;
	}
}

int stick_pad_event(struct stick_pad *pad, uint64_t now_ns, int type, int code, int value)
{
	if (type == EV_SYN && code == SYN_DROPPED) {
		pad->dropping = true;
		return 1;
	}
	if (pad->dropping) { /* the kernel's buffer overran: up to the next report, events are stale */
		if (type == EV_SYN && code == SYN_REPORT)
			pad->dropping = false;
		return 0;
	}
	if (type == EV_ABS && code >= 0 && code < STICK_ABS_MAX)
		pad->absval[code] = value;
	else if (type == EV_KEY)
		stick_pad_set_key(pad, code, value != 0);
	else if (type == EV_SYN && code == SYN_REPORT)
		report(pad, now_ns);
	return 0;
}

void stick_pad_resync(struct stick_pad *pad, uint64_t now_ns)
{
	pad->dropping = false;
	report(pad, now_ns);
}

void stick_pad_settle(struct stick_pad *pad, uint64_t now_ns)
{
	stick_pad_resync(pad, now_ns);
	memset(pad->presses, 0, sizeof(pad->presses));
}

/* A stick role's value: its first bound input the device has. */
static float axis_value(const struct stick_pad *pad, int role, bool trigger, float *flat)
{
	*flat = 0.0f;
	for (int i = 0; i < STICK_BINDINGS; i++) {
		const struct stick_binding *b = &pad->map[role][i];
		if (b->src == STICK_KEY && key_down(pad, b->code))
			return trigger ? 1.0f : (float)b->sign;
		if (b->src == STICK_ABS && b->code < STICK_ABS_MAX && pad->has_abs[b->code]) {
			const struct stick_absinfo *ai = &pad->abs[b->code];
			int v = pad->absval[b->code];
			if (trigger) {
				float t = stick_norm_trigger(v, ai);
				*flat = ai->max > ai->min ? clampf((float)ai->flat / (float)(ai->max - ai->min), 0, 1) : 0;
				return b->sign < 0 ? 1.0f - t : t;
			}
			*flat = stick_flat_fraction(ai);
			return b->sign * stick_norm_centred(v, ai);
		}
	}
	return 0.0f;
}

void stick_pad_take(struct stick_pad *pad, uint64_t now_ns, struct stick_out *out)
{
	memset(out, 0, sizeof(*out));
	const struct stick_config *c = &pad->cfg;
	/* the two sticks: (strafe, forward) and (yaw, pitch) */
	static const int pairs[2][2] = { { STICK_STRAFE, STICK_FORWARD }, { STICK_YAW, STICK_PITCH } };
	for (int s = 0; s < 2; s++) {
		float fx, fy;
		float x = axis_value(pad, pairs[s][0], false, &fx), y = axis_value(pad, pairs[s][1], false, &fy);
		float dz = fmaxf(c->deadzone, fmaxf(fx, fy));
		stick_radial(x, y, dz, c->curve, &out->axis[pairs[s][0]], &out->axis[pairs[s][1]]);
	}
	for (int r = STICK_CLIMB; r <= STICK_DESCEND; r++) {
		float flat, t = axis_value(pad, r, true, &flat);
		out->axis[r] = stick_trigger(t, fmaxf(c->trigger_deadzone, flat), c->curve);
	}
	for (int r = STICK_FIRST_BUTTON; r < STICK_ROLES; r++) {
		out->presses[r] = pad->presses[r];
		pad->presses[r] = 0;
		if (!pad->held[r] || !repeats(r) || c->repeat_ms <= 0)
			continue;
		uint64_t every = (uint64_t)(c->repeat_ms * 1e6);
		/* every repeat due since the last take (a slow frame gets them
		 * all, as the encoders' detents), at most 64 */
		while (now_ns >= pad->repeat_next[r] && out->presses[r] < 64) {
			out->presses[r]++;
			pad->repeat_next[r] += every;
		}
		if (now_ns >= pad->repeat_next[r]) /* past the cap: count on from now */
			pad->repeat_next[r] = now_ns + every;
	}
}

void stick_pad_release(struct stick_pad *pad)
{
	memset(pad->key, 0, sizeof(pad->key));
	memset(pad->has_abs, 0, sizeof(pad->has_abs));
	memset(pad->held, 0, sizeof(pad->held));
	memset(pad->presses, 0, sizeof(pad->presses));
	pad->dropping = false;
}
