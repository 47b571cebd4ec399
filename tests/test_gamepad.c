/* isoterra — the gamepad's stick math against hand-computed values (axis
 * normalisation from absinfo, the radial dead zone and its rescale, the
 * response curve, triggers), the map (defaults, overrides, errors), the
 * pad's state fed raw events (D-pad presses counted between takes, held
 * D-pad repeats, buttons, SYN_DROPPED), and hal_gamepad_open / poll over a
 * folder with no gamepad in it (hotplug's scan path; the real devices are
 * the VM test's: tests/vm/gpio_knobs_guest.sh), and manual flights
 * steered by a pad's inputs through the autopilot's guard: never in rock. */
#include "hal.h"
#include "stick.h"
#include "params.h"
#include "world.h"
#include "density_ref.h"
#include "noise.h"
#include "tcheck.h"

#include <linux/input.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MS 1000000ull

static void test_norm(void)
{
	struct stick_absinfo b = { 0, 255, 0 }, s = { -32768, 32767, 0 }, h = { -1, 1, 0 }, bad = { 5, 5, 0 };
	CHECK_NEAR(stick_norm_centred(0, &b), -1.0, 1e-6, "0 of 0..255");
	CHECK_NEAR(stick_norm_centred(255, &b), 1.0, 1e-6, "255 of 0..255");
	CHECK_NEAR(stick_norm_centred(128, &b), 0.5 / 127.5, 1e-6, "128 of 0..255: 0.00392");
	CHECK_NEAR(stick_norm_centred(64, &b), -63.5 / 127.5, 1e-6, "64 of 0..255: -0.498");
	CHECK_NEAR(stick_norm_centred(300, &b), 1.0, 1e-6, "past max: clamped");
	CHECK_NEAR(stick_norm_centred(-32768, &s), -1.0, 1e-6, "s16 min");
	CHECK_NEAR(stick_norm_centred(16384, &s), 16384.5 / 32767.5, 1e-6, "s16 half: 0.50002");
	CHECK_NEAR(stick_norm_centred(-1, &h), -1.0, 1e-6, "hat -1");
	CHECK_NEAR(stick_norm_centred(0, &h), 0.0, 1e-6, "hat 0");
	CHECK(stick_norm_centred(5, &bad) == 0.0f && stick_norm_trigger(5, &bad) == 0.0f, "min >= max: 0");
	struct stick_absinfo t = { 0, 1023, 0 };
	CHECK_NEAR(stick_norm_trigger(0, &t), 0.0, 1e-6, "trigger at rest");
	CHECK_NEAR(stick_norm_trigger(512, &t), 512.0 / 1023.0, 1e-6, "trigger 512 of 0..1023: 0.5005");
	CHECK_NEAR(stick_norm_trigger(2000, &t), 1.0, 1e-6, "trigger clamped");
	struct stick_absinfo f = { 0, 255, 15 }, f0 = { -32768, 32767, 4096 };
	CHECK_NEAR(stick_flat_fraction(&f), 15.0 / 127.5, 1e-6, "flat 15 of 0..255: 0.1176");
	CHECK_NEAR(stick_flat_fraction(&f0), 4096.0 / 32767.5, 1e-6, "flat 4096 of s16: 0.125");
}

static void test_radial(void)
{
	float x, y;
	stick_radial(0.1f, 0.1f, 0.2f, 1.0f, &x, &y);
	CHECK(x == 0.0f && y == 0.0f, "|0.141| inside the dead zone 0.2: (%g, %g)", x, y);
	stick_radial(0.3f, 0.4f, 0.2f, 1.0f, &x, &y); /* |v| 0.5 -> (0.5-0.2)/0.8 = 0.375 */
	CHECK_NEAR(x, 0.225, 1e-6, "linear: x = 0.6 * 0.375");
	CHECK_NEAR(y, 0.300, 1e-6, "linear: y = 0.8 * 0.375");
	stick_radial(0.3f, 0.4f, 0.2f, 2.0f, &x, &y); /* 0.375^2 = 0.140625 */
	CHECK_NEAR(x, 0.084375, 1e-6, "curve 2: x = 0.6 * 0.140625");
	CHECK_NEAR(y, 0.1125, 1e-6, "curve 2: y = 0.8 * 0.140625");
	stick_radial(0.6f, 0.8f, 0.2f, 2.0f, &x, &y);
	CHECK_NEAR(x, 0.6, 1e-6, "full deflection: 1 (x)");
	CHECK_NEAR(y, 0.8, 1e-6, "full deflection: 1 (y)");
	stick_radial(1.0f, 1.0f, 0.2f, 1.0f, &x, &y); /* a square gate's corner: clamped to the circle */
	CHECK_NEAR(x, sqrt(0.5), 1e-6, "corner clamped (x)");
	CHECK_NEAR(y, sqrt(0.5), 1e-6, "corner clamped (y)");
	stick_radial(0.0f, -0.21f, 0.2f, 1.0f, &x, &y); /* just past: small, not a jump to 0.21 */
	CHECK_NEAR(y, -0.0125, 1e-6, "rescaled from the dead zone's edge: -0.01/0.8");
	CHECK(x == 0.0f, "one axis: the other stays 0");
	stick_radial(0.0f, 0.0f, 0.0f, 3.0f, &x, &y);
	CHECK(x == 0.0f && y == 0.0f, "rest, no dead zone");
	stick_radial(0.5f, 0.0f, 0.0f, 3.0f, &x, &y);
	CHECK_NEAR(x, 0.125, 1e-6, "curve 3, no dead zone: 0.5^3");
	CHECK_NEAR(stick_trigger(0.55f, 0.1f, 2.0f), 0.25, 1e-6, "trigger: ((0.55-0.1)/0.9)^2");
	CHECK(stick_trigger(0.05f, 0.1f, 2.0f) == 0.0f, "trigger inside its dead zone");
	CHECK_NEAR(stick_trigger(1.0f, 0.1f, 2.0f), 1.0, 1e-6, "trigger full");
}

static void test_map(void)
{
	struct stick_binding m[STICK_ROLES][STICK_BINDINGS];
	char err[256], b[32];
	stick_map_default(m);
	CHECK(!strcmp(stick_binding_name(&m[STICK_FORWARD][0], b, sizeof(b)), "-ABS_Y"), "forward: %s", b);
	CHECK(!strcmp(stick_binding_name(&m[STICK_PITCH][0], b, sizeof(b)), "-ABS_RY"), "pitch: %s", b);
	CHECK(!strcmp(stick_binding_name(&m[STICK_CLIMB][1], b, sizeof(b)), "BTN_TR2"), "climb's second: %s", b);
	CHECK(!strcmp(stick_binding_name(&m[STICK_AUTOPILOT][0], b, sizeof(b)), "BTN_START"), "autopilot: %s", b);
	CHECK(!strcmp(stick_binding_name(&m[STICK_QUIT][0], b, sizeof(b)), "none"), "quit unbound: %s", b);
	CHECK(stick_map_parse("climb=ABS_GAS, descend = abs_brake ,pitch=ABS_RY,reset=BTN_EAST|none,quit=key:0x13c",
			      m, err, sizeof(err)) == 0, "a map: %s", err);
	CHECK(m[STICK_CLIMB][0].src == STICK_ABS && m[STICK_CLIMB][0].code == ABS_GAS &&
		      m[STICK_CLIMB][1].src == STICK_NONE, "climb = ABS_GAS only");
	CHECK(m[STICK_DESCEND][0].code == ABS_BRAKE, "names in any case, spaces dropped");
	CHECK(m[STICK_PITCH][0].sign == 1, "pitch inverted (ABS_RY without -)");
	CHECK(m[STICK_RESET][0].code == BTN_EAST && m[STICK_RESET][1].src == STICK_NONE, "two inputs, one none");
	CHECK(m[STICK_QUIT][0].src == STICK_KEY && m[STICK_QUIT][0].code == BTN_MODE, "key:0x13c is BTN_MODE");
	CHECK(m[STICK_FORWARD][0].code == ABS_Y && m[STICK_FORWARD][0].sign == -1, "roles not named keep their defaults");
	struct stick_binding k = { STICK_KEY, 700, 1 };
	CHECK(!strcmp(stick_binding_name(&k, b, sizeof(b)), "key:700"), "an unnamed code: %s", b);
	static const struct {
		const char *map, *want;
	} bad[] = {
		{ "bogus=ABS_X", "unknown role 'bogus'" },
		{ "yaw", "want role=input" },
		{ "yaw=ABS_NOPE", "no input name" },
		{ "yaw=abs:64", "0..63" },
		{ "yaw=ABS_X|ABS_Y|ABS_Z", "at most 2" },
		{ "yaw=", "no input" },
	};
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		err[0] = 0;
		CHECK(stick_map_parse(bad[i].map, m, err, sizeof(err)) < 0 && strstr(err, bad[i].want), "'%s' refused: %s",
		      bad[i].map, err);
	}
	CHECK(stick_map_parse("", m, err, sizeof(err)) == 0 && stick_map_parse(NULL, m, err, sizeof(err)) == 0,
	      "empty map: the defaults");
}

/* A pad like the kernel's xpad: s16 sticks with a flat, 0..255 triggers, a hat. */
static void xpad(struct stick_pad *p, const struct stick_config *c, const char *map)
{
	struct stick_binding m[STICK_ROLES][STICK_BINDINGS];
	char err[256];
	stick_map_default(m);
	if (map && stick_map_parse(map, m, err, sizeof(err)) < 0)
		fprintf(stderr, "map: %s\n", err);
	stick_pad_init(p, c, m);
	struct stick_absinfo s = { -32768, 32767, 128 }, t = { 0, 255, 0 }, h = { -1, 1, 0 };
	stick_pad_set_abs(p, ABS_X, &s, 0);
	stick_pad_set_abs(p, ABS_Y, &s, 0);
	stick_pad_set_abs(p, ABS_RX, &s, 0);
	stick_pad_set_abs(p, ABS_RY, &s, 0);
	stick_pad_set_abs(p, ABS_Z, &t, 0);
	stick_pad_set_abs(p, ABS_RZ, &t, 0);
	stick_pad_set_abs(p, ABS_HAT0X, &h, 0);
	stick_pad_set_abs(p, ABS_HAT0Y, &h, 0);
	stick_pad_settle(p, 0);
}

static void ev(struct stick_pad *p, uint64_t t, int type, int code, int value)
{
	stick_pad_event(p, t, type, code, value);
	stick_pad_event(p, t, EV_SYN, SYN_REPORT, 0);
}

static void test_pad(void)
{
	struct stick_config c = { .deadzone = 0.15f, .trigger_deadzone = 0.05f, .curve = 2.0f,
				  .repeat_delay_ms = 400, .repeat_ms = 150 };
	struct stick_pad p;
	struct stick_out o;
	xpad(&p, &c, NULL);
	stick_pad_take(&p, 0, &o);
	for (int i = 0; i <= STICK_DESCEND; i++)
		CHECK(o.axis[i] == 0.0f, "at rest: axis %d is 0", i);
	/* left stick fully up: forward 1; a little right: inside nothing */
	stick_pad_event(&p, 1, EV_ABS, ABS_Y, -32768);
	ev(&p, 1, EV_ABS, ABS_X, 2000);
	stick_pad_take(&p, 2, &o);
	/* x = 2000.5/32767.5 = 0.061052, y = 1 (forward), |v| = 1.001862 -> 1 */
	double m = sqrt(1.0 + 0.061052 * 0.061052);
	CHECK_NEAR(o.axis[STICK_FORWARD], 1.0 / m, 1e-5, "forward: the direction kept at full deflection");
	CHECK_NEAR(o.axis[STICK_STRAFE], 0.061052 / m, 1e-5, "strafe: the small part of the direction");
	/* the right stick half right: yaw ((0.50002-0.15)/0.85)^2 = 0.169563 */
	ev(&p, 3, EV_ABS, ABS_RX, 16384);
	stick_pad_take(&p, 4, &o);
	CHECK_NEAR(o.axis[STICK_YAW], pow((16384.5 / 32767.5 - 0.15) / 0.85, 2), 1e-5, "yaw, dead zone and curve");
	CHECK_NEAR(o.axis[STICK_PITCH], 0.0, 1e-4, "pitch ~0 (s16 rests half a unit off the middle)");
	/* triggers: RZ full climbs, Z half descends ((128/255-0.05)/0.95)^2 */
	stick_pad_event(&p, 5, EV_ABS, ABS_RZ, 255);
	ev(&p, 5, EV_ABS, ABS_Z, 128);
	stick_pad_take(&p, 6, &o);
	CHECK_NEAR(o.axis[STICK_CLIMB], 1.0, 1e-6, "climb");
	CHECK_NEAR(o.axis[STICK_DESCEND], pow((128.0 / 255.0 - 0.05) / 0.95, 2), 1e-5, "descend: 0.2264");
	/* the D-pad: two presses right and one left between takes all count */
	ev(&p, 10, EV_ABS, ABS_HAT0X, 1);
	ev(&p, 11, EV_ABS, ABS_HAT0X, 0);
	ev(&p, 12, EV_ABS, ABS_HAT0X, 1);
	ev(&p, 13, EV_ABS, ABS_HAT0X, -1);
	ev(&p, 14, EV_ABS, ABS_HAT0X, 0);
	stick_pad_take(&p, 20, &o);
	CHECK(o.presses[STICK_SELECT_NEXT] == 2 && o.presses[STICK_SELECT_PREV] == 1, "hat: next %d, prev %d",
	      o.presses[STICK_SELECT_NEXT], o.presses[STICK_SELECT_PREV]);
	stick_pad_take(&p, 21, &o);
	CHECK(o.presses[STICK_SELECT_NEXT] == 0, "counted once");
	/* a press and release within one report: no change of state seen, no press */
	stick_pad_event(&p, 30, EV_KEY, BTN_START, 1);
	stick_pad_event(&p, 30, EV_KEY, BTN_START, 0);
	stick_pad_event(&p, 30, EV_SYN, SYN_REPORT, 0);
	ev(&p, 31, EV_KEY, BTN_START, 1);
	ev(&p, 32, EV_KEY, BTN_START, 0);
	ev(&p, 33, EV_KEY, BTN_SELECT, 1);
	stick_pad_take(&p, 40, &o);
	CHECK(o.presses[STICK_AUTOPILOT] == 1 && o.presses[STICK_RESET] == 1, "start %d (autopilot), select %d (reset)",
	      o.presses[STICK_AUTOPILOT], o.presses[STICK_RESET]);
	ev(&p, 41, EV_KEY, BTN_SELECT, 0);
	/* held D-pad up: one press, repeats from 400 ms every 150 ms */
	uint64_t t0 = 1000 * MS;
	ev(&p, t0, EV_ABS, ABS_HAT0Y, -1);
	stick_pad_take(&p, t0 + 300 * MS, &o);
	CHECK(o.presses[STICK_CHANGE_UP] == 1, "held 300 ms: the press (%d)", o.presses[STICK_CHANGE_UP]);
	stick_pad_take(&p, t0 + 500 * MS, &o);
	CHECK(o.presses[STICK_CHANGE_UP] == 1, "at 500 ms: one repeat (400) (%d)", o.presses[STICK_CHANGE_UP]);
	stick_pad_take(&p, t0 + 1000 * MS, &o);
	CHECK(o.presses[STICK_CHANGE_UP] == 4, "at 1000 ms: 550, 700, 850, 1000 (%d)", o.presses[STICK_CHANGE_UP]);
	ev(&p, t0 + 1010 * MS, EV_ABS, ABS_HAT0Y, 0);
	stick_pad_take(&p, t0 + 3000 * MS, &o);
	CHECK(o.presses[STICK_CHANGE_UP] == 0, "released: no more (%d)", o.presses[STICK_CHANGE_UP]);
	/* select's repeat is the D-pad's only: a held button counts once */
	ev(&p, t0 + 3000 * MS, EV_KEY, BTN_SELECT, 1);
	stick_pad_take(&p, t0 + 9000 * MS, &o);
	CHECK(o.presses[STICK_RESET] == 1, "a held button: one press (%d)", o.presses[STICK_RESET]);
	ev(&p, t0 + 9000 * MS, EV_KEY, BTN_SELECT, 0);
	/* SYN_DROPPED: events to the next report are stale; the state read again */
	CHECK(stick_pad_event(&p, 50, EV_SYN, SYN_DROPPED, 0) == 1, "SYN_DROPPED asks for a resync");
	ev(&p, 51, EV_KEY, BTN_NORTH, 1); /* stale: dropped with its report */
	stick_pad_take(&p, 52, &o);
	CHECK(o.presses[STICK_PAUSE] == 0, "events after SYN_DROPPED ignored up to the report");
	CHECK(stick_pad_event(&p, 53, EV_SYN, SYN_DROPPED, 0) == 1, "dropped again");
	stick_pad_set_key(&p, BTN_NORTH, true); /* EVIOCGKEY says: down */
	stick_pad_resync(&p, 54);
	stick_pad_take(&p, 55, &o);
	CHECK(o.presses[STICK_PAUSE] == 1, "resync: the press seen in the state counts");
	/* a button down when the device opens is no press */
	stick_pad_settle(&p, 56);
	stick_pad_release(&p);
	stick_pad_take(&p, 57, &o);
	CHECK(o.axis[STICK_FORWARD] == 0.0f && o.axis[STICK_CLIMB] == 0.0f, "released: at rest");
	/* digital triggers and a D-pad of buttons (no Z/RZ, no hat) */
	struct stick_binding map[STICK_ROLES][STICK_BINDINGS];
	stick_map_default(map);
	stick_pad_init(&p, &c, map);
	struct stick_absinfo s = { -128, 127, 0 };
	stick_pad_set_abs(&p, ABS_X, &s, 0);
	stick_pad_set_abs(&p, ABS_Y, &s, 0);
	stick_pad_settle(&p, 0);
	ev(&p, 1, EV_KEY, BTN_TR2, 1);
	ev(&p, 2, EV_KEY, BTN_DPAD_DOWN, 1);
	ev(&p, 3, EV_KEY, BTN_DPAD_DOWN, 0);
	stick_pad_take(&p, 4, &o);
	CHECK(o.axis[STICK_CLIMB] == 1.0f && o.presses[STICK_CHANGE_DOWN] == 1, "BTN_TR2 climbs (%g), BTN_DPAD_DOWN (%d)",
	      o.axis[STICK_CLIMB], o.presses[STICK_CHANGE_DOWN]);
	/* the device's flat over a smaller configured dead zone */
	c.deadzone = 0.0f;
	xpad(&p, &c, "forward=ABS_Y");
	ev(&p, 1, EV_ABS, ABS_Y, 100); /* 0.00307 of s16: inside flat 128 (0.0039) */
	stick_pad_take(&p, 2, &o);
	CHECK(o.axis[STICK_FORWARD] == 0.0f, "inside the device's flat: 0 (%g)", o.axis[STICK_FORWARD]);
	ev(&p, 3, EV_ABS, ABS_Y, 32767);
	stick_pad_take(&p, 4, &o);
	CHECK_NEAR(o.axis[STICK_FORWARD], 1.0, 1e-6, "forward=ABS_Y: stick down flies forward");
}

static void logged(void *user, enum hal_level level, const char *msg)
{
	(void)level;
	snprintf(user, 512, "%s", msg);
}

/* No device here: the folder's scan and inotify path, and the refusals. */
static void test_open(void)
{
	char err[256], last[512] = "";
	struct hal_gamepad_config cfg = { .enabled = false, .deadzone = 0.15f, .curve = 2.0f, .retry_s = 0.1,
					  .log = { logged, last } };
	CHECK(!hal_gamepad_open(&cfg, err, sizeof(err)) && !err[0], "off: NULL, no error");
	cfg.enabled = true;
	cfg.map = "yaw=ABS_NOPE";
	CHECK(!hal_gamepad_open(&cfg, err, sizeof(err)) && strstr(err, "gamepad_map: yaw: 'ABS_NOPE'"), "bad map: %s", err);
	cfg.map = "";
	char dir[] = "/tmp/isoterra-pad-XXXXXX";
	if (!mkdtemp(dir)) {
		CHECK(0, "mkdtemp");
		return;
	}
	cfg.dir = dir;
	struct hal_gamepad *g = hal_gamepad_open(&cfg, err, sizeof(err));
	CHECK(g && !err[0] && strstr(last, "none in") && !hal_gamepad_device(g)[0], "no gamepad yet: %s", last);
	/* a node appears that is no input device: scanned (inotify), refused */
	char path[64];
	snprintf(path, sizeof(path), "%s/event3", dir);
	FILE *f = fopen(path, "w");
	if (f)
		fclose(f);
	struct hal_input in;
	memset(&in, 0, sizeof(in));
	last[0] = 0;
	hal_gamepad_poll(g, hal_now_ns(), &in);
	CHECK(!hal_gamepad_device(g)[0] && !last[0] && in.select == 0 && in.stick[HAL_FLY_FORWARD] == 0.0f,
	      "a file named event3 is no gamepad (nothing said: %s)", last);
	hal_gamepad_close(g);
	/* a named node that is missing: said once, waited for */
	cfg.device = path;
	unlink(path);
	g = hal_gamepad_open(&cfg, err, sizeof(err));
	CHECK(g && strstr(last, "cannot open") && strstr(last, "waiting"), "a missing node: %s", last);
	last[0] = 0;
	hal_gamepad_poll(g, hal_now_ns() + 1000 * MS, &in);
	CHECK(!last[0], "not said again: %s", last);
	hal_gamepad_close(g);
	cfg.device = "/dev/null";
	CHECK(!hal_gamepad_open(&cfg, err, sizeof(err)) && strstr(err, "gamepad_device /dev/null is not an evdev"),
	      "a named node of another kind: %s", err);
	hal_gamepad_close(NULL);
	rmdir(dir);
}

/* A pad pushed around for 24 s (30 polls a second, as frames): dives
 * (forward and the descend trigger), turns, pitches down into the ground,
 * strafes; what controls.c does with its output (forward, right, up =
 * climb - descend; yaw, pitch) steers the autopilot, which must keep the
 * camera out of rock at every simulation step. */
/* One 1/60 s step of the flight to time t: the least air and the path so
 * far (prev: where it was). */
static void guard_step(struct autopilot *ap, double t, const struct params *p, const struct noise_set *ns,
		       float prev[3], float *least, float *path)
{
	autopilot_advance(ap, t);
	*least = fminf(*least, -density_ref(p, ns, NULL, ap->pos[0], ap->pos[1], ap->pos[2]));
	float d[3] = { ap->pos[0] - prev[0], ap->pos[1] - prev[1], ap->pos[2] - prev[2] };
	*path += sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
	memcpy(prev, ap->pos, sizeof(ap->pos));
}

static void test_guard(void)
{
	static const char *const names[] = { "default", "alien", "caves", "canyon", "planet" };
	static const struct {
		int code, value;
	} phases[][3] = {
		{ { ABS_Y, -32768 }, { ABS_Z, 255 }, { ABS_RX, 0 } },      /* forward and down */
		{ { ABS_Y, -32768 }, { ABS_Z, 0 }, { ABS_RX, 20000 } },    /* forward, turning right */
		{ { ABS_Y, -32768 }, { ABS_RY, 32767 }, { ABS_RX, 0 } },   /* pitched down, forward */
		{ { ABS_X, 32767 }, { ABS_Y, 0 }, { ABS_Z, 255 } },        /* strafing right, down */
	};
	struct stick_config c = { .deadzone = 0.15f, .trigger_deadzone = 0.05f, .curve = 2.0f };
	for (size_t n = 0; n < sizeof(names) / sizeof(names[0]); n++) {
		struct params p;
		char err[256];
		params_defaults(&p);
		if (params_apply_preset(&p, names[n], err, sizeof(err)) < 0) {
			CHECK(0, "%s", err);
			continue;
		}
		p.fly_speed = 12.0f;
		struct noise_set ns;
		noise_set_init(&ns, p.seed);
		struct autopilot ap;
		if (autopilot_init(&ap, &p, NULL) < 0) {
			CHECK(0, "%s: autopilot_init", names[n]);
			continue;
		}
		struct stick_pad pad;
		xpad(&pad, &c, NULL);
		float least = 1e30f, path = 0.0f, prev[3];
		memcpy(prev, ap.pos, sizeof(prev));
		int frames = 0;
		for (size_t ph = 0; ph < sizeof(phases) / sizeof(phases[0]); ph++) {
			for (int k = 0; k < 3; k++)
				stick_pad_event(&pad, 0, EV_ABS, phases[ph][k].code, phases[ph][k].value);
			stick_pad_event(&pad, 0, EV_SYN, SYN_REPORT, 0);
			for (int f = 0; f < 6 * 30; f++, frames++) {
				struct stick_out o;
				stick_pad_take(&pad, 0, &o);
				float move[3] = { o.axis[STICK_FORWARD], o.axis[STICK_STRAFE],
						  o.axis[STICK_CLIMB] - o.axis[STICK_DESCEND] };
				float turn[2] = { o.axis[STICK_YAW], o.axis[STICK_PITCH] };
				autopilot_steer(&ap, move, turn);
				for (int s = 1; s <= 2; s++) /* each 1/60 s step */
					guard_step(&ap, frames / 30.0 + s / 60.0, &p, &ns, prev, &least, &path);
			}
		}
		printf("guard: %-8s least air %.2f, %.0f units flown\n", names[n], (double)least, (double)path);
		CHECK(least > 0.0f, "%s: never in rock (least air %g)", names[n], (double)least);
		CHECK(path > 30.0f, "%s: it flew (%.1f units in 24 s)", names[n], (double)path);
		/* start again: the autopilot flies on by itself (not the last
		 * stick input held), still out of the rock */
		autopilot_resume(&ap);
		CHECK(!ap.manual, "%s: resumed: not manual", names[n]);
		float auto_path = 0.0f, auto_least = 1e30f;
		for (int s = 1; s <= 10 * 60; s++)
			guard_step(&ap, frames / 30.0 + s / 60.0, &p, &ns, prev, &auto_least, &auto_path);
		printf("resume: %-8s least air %.2f, %.0f units in 10 s\n", names[n], (double)auto_least, (double)auto_path);
		CHECK(auto_least > 0.0f, "%s: the resumed autopilot never in rock (least air %g)", names[n],
		      (double)auto_least);
		CHECK(auto_path > 0.5f * p.fly_speed * 10.0f, "%s: the resumed autopilot flies (%.1f units in 10 s at %g/s)",
		      names[n], (double)auto_path, (double)p.fly_speed);
		autopilot_free(&ap);
	}
}

int main(void)
{
	test_norm();
	test_radial();
	test_map();
	test_pad();
	test_open();
	test_guard();
	return tc_done("gamepad");
}
