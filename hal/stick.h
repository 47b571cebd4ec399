/* isoterra — a gamepad's state and its stick math (stick.c), pure C: no
 * device, no clock of its own, so that it is unit-tested on the host
 * (tests/test_gamepad.c).  hal/gamepad.c feeds it the events it reads
 * from an evdev node and asks it, once a frame, what they mean.
 *
 * Axes are normalised from the device's absinfo: a stick or a hat to
 * -1..1 around the middle of [min, max], a trigger to 0..1 from min to
 * max.  A stick's two axes share a radial dead zone (the larger of the
 * configured one and the axes' own flat, as a fraction of their half
 * range), rescaled so the output starts at 0 at its edge and reaches 1 at
 * full deflection, then a response curve |r|^curve.  A trigger has its
 * own dead zone, rescaled the same way, and the same curve.
 *
 * Roles (forward, yaw, select_next, reset, ...) are bound to at most
 * STICK_BINDINGS inputs each: an axis (ABS_*, its sign flips it) or a key
 * (BTN_* / KEY_*).  The defaults follow the kernel's gamepad layout
 * (Documentation/input/gamepad.rst); the map string overrides them. */
#ifndef ISOTERRA_STICK_H
#define ISOTERRA_STICK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum stick_role {
	/* sticks: -1..1 */
	STICK_FORWARD, STICK_STRAFE, STICK_YAW, STICK_PITCH,
	/* triggers: 0..1 */
	STICK_CLIMB, STICK_DESCEND,
	/* buttons: presses counted */
	STICK_SELECT_NEXT, STICK_SELECT_PREV, STICK_CHANGE_UP, STICK_CHANGE_DOWN,
	STICK_RESET, STICK_AUTOPILOT, STICK_PAUSE, STICK_SCREENSHOT, STICK_PRESET, STICK_QUIT,
	STICK_ROLES
};
#define STICK_FIRST_BUTTON STICK_SELECT_NEXT
#define STICK_BINDINGS 2
#define STICK_ABS_MAX 0x40  /* ABS_CNT */
#define STICK_KEY_MAX 0x300 /* KEY_CNT */

/* The role's name in a map ("forward", "select_next", ...). */
const char *stick_role_name(enum stick_role r);

enum stick_src { STICK_NONE, STICK_ABS, STICK_KEY };
struct stick_binding {
	enum stick_src src;
	int code;  /* ABS_* or KEY_* / BTN_* */
	int sign;  /* +1 or -1: an axis read the other way (a stick's Y) */
};

/* ---- the math -------------------------------------------------------------- */
struct stick_absinfo {
	int min, max, flat;
};
/* v on [min, max] to -1..1 around the middle (clamped; 0 when min >= max). */
float stick_norm_centred(int v, const struct stick_absinfo *ai);
/* v on [min, max] to 0..1 (clamped; 0 when min >= max). */
float stick_norm_trigger(int v, const struct stick_absinfo *ai);
/* The flat as a fraction of the half range (the radial dead zone's floor). */
float stick_flat_fraction(const struct stick_absinfo *ai);
/* A stick's two axes (-1..1 each) through a radial dead zone dz (0..<1)
 * rescaled to start at 0, and the curve exponent (>= 1) on the magnitude,
 * clamped to the unit circle; the direction is kept. */
void stick_radial(float x, float y, float dz, float curve, float *ox, float *oy);
/* A trigger (0..1) through its dead zone, rescaled, and the curve. */
float stick_trigger(float t, float dz, float curve);

/* ---- the map ---------------------------------------------------------------- */
/* The default bindings (both slots of every role). */
void stick_map_default(struct stick_binding map[STICK_ROLES][STICK_BINDINGS]);
/* Applies "role=binding[|binding],..." over map: a binding is none, an
 * input name (ABS_RZ, BTN_START, KEY_SPACE, ...), abs:N or key:N, with a
 * leading - for an axis read the other way.  A role named replaces both of
 * its slots.  0, or -1 with err (the map left partly applied). */
int stick_map_parse(const char *s, struct stick_binding map[STICK_ROLES][STICK_BINDINGS], char *err,
		    size_t errlen);
/* The binding written back ("-ABS_Y", "key:700"): buf. */
const char *stick_binding_name(const struct stick_binding *b, char *buf, size_t len);

/* ---- a pad's state ---------------------------------------------------------- */
struct stick_config {
	float deadzone;         /* sticks: radial, 0..0.9 */
	float trigger_deadzone; /* triggers */
	float curve;            /* exponent >= 1 */
	double repeat_delay_ms; /* a held D-pad role repeats after this ... */
	double repeat_ms;       /* ... every so many ms (0 = no repeat) */
};

struct stick_pad {
	struct stick_config cfg;
	struct stick_binding map[STICK_ROLES][STICK_BINDINGS];
	struct stick_absinfo abs[STICK_ABS_MAX];
	bool has_abs[STICK_ABS_MAX];
	int absval[STICK_ABS_MAX];
	uint8_t key[STICK_KEY_MAX / 8];
	bool held[STICK_ROLES];      /* button roles after the last report */
	int presses[STICK_ROLES];    /* since the last stick_pad_take */
	uint64_t held_since[STICK_ROLES], repeat_next[STICK_ROLES];
	bool dropping;               /* after SYN_DROPPED: events ignored until SYN_REPORT */
};

/* What the pad asks for since the last take. */
struct stick_out {
	float axis[STICK_DESCEND + 1]; /* forward, strafe, yaw, pitch (-1..1); climb, descend (0..1) */
	int presses[STICK_ROLES];      /* button roles: presses, held D-pad repeats included */
};

/* A pad with these bindings, everything at rest (no axis known yet). */
void stick_pad_init(struct stick_pad *pad, const struct stick_config *cfg,
		    const struct stick_binding map[STICK_ROLES][STICK_BINDINGS]);
/* The device has axis code with this range, now at value (its EVIOCGABS). */
void stick_pad_set_abs(struct stick_pad *pad, int code, const struct stick_absinfo *ai, int value);
/* One evdev event (type, code, value as in struct input_event) at now_ns.
 * Button roles are evaluated at each SYN_REPORT, so a press released
 * before the next take still counts.  Returns 1 on SYN_DROPPED: the
 * caller reads the device's state again (stick_pad_set_abs,
 * stick_pad_set_key) and calls stick_pad_resync; else 0. */
int stick_pad_event(struct stick_pad *pad, uint64_t now_ns, int type, int code, int value);
void stick_pad_set_key(struct stick_pad *pad, int code, bool down);
/* After a resync: roles re-evaluated (a press seen as its new state). */
void stick_pad_resync(struct stick_pad *pad, uint64_t now_ns);
/* After opening a device: roles held as the inputs are, nothing counted
 * (a button down at the start is no press). */
void stick_pad_settle(struct stick_pad *pad, uint64_t now_ns);
/* The axes now and the presses since the last take (held D-pad roles
 * repeated up to now_ns); the counts start again. */
void stick_pad_take(struct stick_pad *pad, uint64_t now_ns, struct stick_out *out);
/* Everything released (the device went away). */
void stick_pad_release(struct stick_pad *pad);

#endif
