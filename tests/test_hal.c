/* isoterra — the knob mapping (parameter steps, clamping, snapping, enums,
 * booleans), the development keys' byte decoding, the pause clock, the OSD
 * (drawn where it should be, text visible, nothing outside its box) and
 * the configuration errors of the controls (app/controls.c over hal/). */
#include "app.h"
#include "controls.h"
#include "hal_config.h"
#include "hal.h"
#include "osd.h"
#include "font.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <linux/input.h>
#include <math.h>
#include <string.h>

static void test_knobs(void)
{
	struct knobs k;
	char err[256];
	CHECK(knobs_init(&k, "", err, sizeof(err)) == 0 && k.count > 10, "every live parameter (%d)", k.count);
	for (int i = 0; i < k.count; i++)
		CHECK(k.list[i]->flags & P_LIVE, "%s is live", k.list[i]->name);
	CHECK(knobs_init(&k, "nope", err, sizeof(err)) < 0 && strstr(err, "nope"), "unknown name refused: %s", err);
	CHECK(knobs_init(&k, "out", err, sizeof(err)) < 0 && strstr(err, "text"), "text parameter refused: %s", err);
	CHECK(knobs_init(&k, "ambient,octaves,fractal,flat_spot,iso", err, sizeof(err)) == 0 && k.count == 5, "list");
	CHECK_NEAR(knob_step(params_find("ambient")), 0.01, 1e-12, "ambient step");
	CHECK_NEAR(knob_step(params_find("cam_yaw")), 1.0, 1e-12, "cam_yaw step");
	CHECK_NEAR(knob_step(params_find("iso")), 1.0, 1e-12, "iso step (zero default)");
	CHECK_NEAR(knob_step(params_find("noise_freq")), 0.001, 1e-12, "noise_freq step");
	CHECK(knob_step(params_find("octaves")) == 1, "int step");
	struct params p;
	params_defaults(&p);
	k.sel = 0;
	p.ambient = 0.28f;
	CHECK(knob_change(&k, &p, 3), "ambient +3");
	CHECK_NEAR(p.ambient, 0.31, 1e-6, "ambient after +3");
	knob_change(&k, &p, -100);
	CHECK(p.ambient == 0.0f, "clamped at 0 (%g)", p.ambient);
	CHECK(!knob_change(&k, &p, -1), "no change at the limit");
	k.sel = 1; /* octaves 9 */
	knob_change(&k, &p, 20);
	CHECK(p.octaves == 16, "octaves clamped to 16 (%d)", p.octaves);
	k.sel = 2; /* fractal enum wraps */
	int nf = FRACTAL_COUNT;
	knob_change(&k, &p, -1);
	CHECK(p.fractal == nf - 1, "enum wraps backwards (%d)", p.fractal);
	k.sel = 3;
	knob_change(&k, &p, 1);
	CHECK(p.flat_spot, "bool toggles");
	knob_change(&k, &p, 2);
	CHECK(p.flat_spot, "two detents: back where it was");
}

static void test_keys(void)
{
	struct hal_input in;
	memset(&in, 0, sizeof(in));
	int esc = 0;
	const unsigned char keys[] = "\x1b[A\x1b[A\x1b[B\x1b[C]][-+psnrq";
	hal_keys_feed_tty(keys, sizeof(keys) - 1, &esc, &in);
	CHECK(in.change == 1 + -1 + 1, "change %d", in.change);
	CHECK(in.select == 1 + 2 - 1, "select %d", in.select);
	CHECK(in.actions[HAL_PAUSE] == 1 && in.actions[HAL_SCREENSHOT] == 1 && in.actions[HAL_PRESET] == 1 &&
		      in.actions[HAL_RESET] == 1 && in.actions[HAL_QUIT] == 1,
	      "actions");
	/* an escape sequence split across reads */
	memset(&in, 0, sizeof(in));
	hal_keys_feed_tty((const unsigned char *)"\x1b", 1, &esc, &in);
	hal_keys_feed_tty((const unsigned char *)"[", 1, &esc, &in);
	hal_keys_feed_tty((const unsigned char *)"D", 1, &esc, &in);
	CHECK(in.select == -1 && in.actions[HAL_QUIT] == 0, "split arrow (%d)", in.select);
	/* manual camera keys: forward twice, a turn each way, up, pitch down */
	memset(&in, 0, sizeof(in));
	hal_keys_feed_tty((const unsigned char *)"iijluh", 6, &esc, &in);
	CHECK(in.fly[0] == 2 && in.fly[1] == 0 && in.fly[2] == 1 && in.fly[3] == 0 && in.fly[4] == -1 &&
		      in.change == 0 && in.select == 0,
	      "flight keys (%d %d %d %d %d)", in.fly[0], in.fly[1], in.fly[2], in.fly[3], in.fly[4]);
}

/* The evdev reader: whole events decoded, a short read refused, a file that
 * is not an evdev node (it would read zeros forever) refused at open. */
static void test_evdev(void)
{
	struct input_event ev[4];
	memset(ev, 0, sizeof(ev));
	ev[0].type = EV_KEY, ev[0].code = KEY_UP, ev[0].value = 1;     /* press */
	ev[1].type = EV_KEY, ev[1].code = KEY_UP, ev[1].value = 2;     /* auto-repeat */
	ev[2].type = EV_KEY, ev[2].code = KEY_UP, ev[2].value = 0;     /* release: nothing */
	ev[3].type = EV_KEY, ev[3].code = KEY_Q, ev[3].value = 1;
	struct hal_input in;
	memset(&in, 0, sizeof(in));
	CHECK(hal_keys_feed_evdev(ev, sizeof(ev), &in) == 4, "four events");
	CHECK(in.change == 2 && in.actions[HAL_QUIT] == 1, "up twice, quit (%d %d)", in.change, in.actions[HAL_QUIT]);
	memset(&in, 0, sizeof(in));
	CHECK(hal_keys_feed_evdev(ev, sizeof(ev) - 1, &in) == -1 && in.change == 0 && in.actions[HAL_QUIT] == 0,
	      "a short read is refused, nothing decoded");
	char err[256];
	struct hal_keys_config kc = {.mode = HAL_KEYS_EVDEV, .evdev = "/dev/zero"};
	struct hal_keys *k = hal_keys_open(&kc, err, sizeof(err));
	CHECK(!k && strstr(err, "/dev/zero") && strstr(err, "not an evdev"), "/dev/zero refused: %s", err);
	hal_keys_close(k);
}

static void test_osd(void)
{
	char err[512];
	struct osd *o = osd_create(err, sizeof(err));
	CHECK(o != NULL, "osd: %s", err);
	if (!o)
		return;
	enum { W = 200, H = 100 };
	GLuint tex, fbo;
	glGenTextures(1, &tex);
	glBindTexture(GL_TEXTURE_2D, tex);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, W, H);
	glGenFramebuffers(1, &fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
	glClearColor(0.0f, 1.0f, 0.0f, 1.0f);
	glClear(GL_COLOR_BUFFER_BIT);
	CHECK(osd_draw(o, fbo, W, H, "I", "0.5", 0.5f, 1, 1.0f) == 0, "draw");
	static uint8_t pix[H][W][4];
	glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, pix);
	/* box: x 2.., y 2.. from the top; cols = 3 -> (3*6+8) = 26 px wide */
	int inside_dark = 0, outside_green = 0, outside = 0, bright = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			const uint8_t *c = pix[H - 1 - y][x]; /* y from the top */
			bool in = x >= 2 && x < 2 + 26 && y >= 2 && y < 2 + 30;
			if (!in) {
				outside++;
				outside_green += c[0] == 0 && c[1] == 255 && c[2] == 0;
			} else {
				inside_dark += c[1] < 128;
				bright += c[0] > 200 && c[1] > 200 && c[2] > 200;
			}
		}
	CHECK(outside_green == outside, "nothing drawn outside the box (%d of %d untouched)", outside_green, outside);
	CHECK(inside_dark > 500, "the box is dark (%d)", inside_dark);
	CHECK(bright >= 15, "white value text drawn (%d pixels)", bright);
	/* the "I" glyph: its stem (column 2 of the glyph) is lit in the title row */
	const uint8_t *g = font_glyph('I');
	int lit = 0;
	for (int gy = 0; gy < 7; gy++) {
		const uint8_t *c = pix[H - 1 - (2 + 3 + gy)][2 + 4 + 2];
		lit += (g[gy] >> 2 & 1) && c[0] > 200 && c[1] > 150;
	}
	CHECK(lit == 7, "glyph 'I' stem lit in 7 rows (%d)", lit);
	CHECK(font_glyph(200) == font_glyph('?') && font_glyph(' ')[3] == 0, "font lookups");
	glDeleteFramebuffers(1, &fbo);
	glDeleteTextures(1, &tex);
	osd_destroy(o);
}

static void test_open(void)
{
	struct params p;
	char err[512];
	params_defaults(&p);
	/* nothing configured: a no-op object, time passes through */
	struct controls *h = controls_create(&p, err, sizeof(err));
	CHECK(h != NULL, "open: %s", err);
	CHECK(!controls_paused(h), "not paused");
	/* the loop's pause clock: frozen from the first paused frame, going
	 * on from there after, the paused time taken out */
	struct pause_clock pc = { 0 };
	const float in_t[] = { 1, 2, 3, 4, 5 }, want[] = { 1, 1, 1, 2, 3 };
	const bool paused[] = { false, true, true, false, false };
	for (int i = 0; i < 5; i++) {
		float got = pause_clock_time(&pc, in_t[i], paused[i]);
		CHECK(got == want[i], "pause clock at %g (%s): %g, want %g", (double)in_t[i],
		      paused[i] ? "paused" : "running", (double)got, (double)want[i]);
	}
	CHECK(controls_poll(h, &p) == 0, "no quit");
	controls_destroy(h);
	struct {
		const char *key, *value, *msg;
	} bad[] = {
		{ "enc1_a", "3", "enc1_a and enc1_b" },
		{ "button1_line", "2", "no gpiochip" },
		{ "knob_params", "size", "text" },
	};
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		params_defaults(&p);
		CHECK(params_set(&p, bad[i].key, bad[i].value, err, sizeof(err)) == 0, "set %s", bad[i].key);
		err[0] = 0;
		h = controls_create(&p, err, sizeof(err));
		CHECK(h == NULL && strstr(err, bad[i].msg), "%s=%s refused with '%s': got '%s'", bad[i].key, bad[i].value,
		      bad[i].msg, err);
		controls_destroy(h);
	}
	params_defaults(&p);
	params_set(&p, "gpio_chip", "gpiochip0", err, sizeof(err));
	params_set(&p, "enc1_a", "1", err, sizeof(err));
	params_set(&p, "enc1_b", "1", err, sizeof(err));
	h = controls_create(&p, err, sizeof(err));
	CHECK(h == NULL && strstr(err, "twice"), "a line used twice: %s", err);
	controls_destroy(h);
}

/* hal's configuration from the parameters: names, numbers and choices
 * arrive as hal's own values */
static void test_config(void)
{
	struct params p;
	char err[512];
	params_defaults(&p);
	const char *set[] = { "gpio_chip=knobs", "enc1_a=3", "enc1_b=4", "enc1_sw=5", "enc1_bias=pull_down",
			      "enc1_sw_action=quit", "enc2_chip=other", "enc2_steps_per_detent=2", "button3_line=7",
			      "button3_action=prev", "button_bias=disable", "keyboard=evdev",
			      "keyboard_evdev=/dev/input/event9", "v4l2=/dev/video7", "v4l2_format=NV12",
			      "v4l2_matrix=bt709", "v4l2_io=write", "v4l2_fps=25" };
	for (size_t i = 0; i < sizeof(set) / sizeof(set[0]); i++) {
		char name[64];
		const char *eq = strchr(set[i], '=');
		snprintf(name, sizeof(name), "%.*s", (int)(eq - set[i]), set[i]);
		CHECK(params_set(&p, name, eq + 1, err, sizeof(err)) == 0, "%s: %s", set[i], err);
	}
	struct hal_gpio_config g;
	CHECK(hal_config_gpio(&p, &g, err, sizeof(err)) == 0, "gpio config: %s", err);
	CHECK(!strcmp(g.chip, "knobs") && !strcmp(g.enc[1].chip, "other") && !g.enc[0].chip[0], "chips");
	CHECK(g.enc[0].a == 3 && g.enc[0].b == 4 && g.enc[0].sw == 5 && g.enc[1].a == HAL_NO_LINE, "lines");
	CHECK(g.enc[0].bias == HAL_BIAS_PULL_DOWN && g.enc[1].bias == HAL_BIAS_AS_IS && g.button_bias == HAL_BIAS_DISABLE,
	      "bias");
	CHECK(g.enc[0].sw_action == HAL_QUIT && g.enc[1].sw_action == HAL_RESET, "switch actions");
	CHECK(g.enc[0].turn == HAL_TURN_SELECT && g.enc[1].turn == HAL_TURN_CHANGE, "encoder 1 selects, 2 changes");
	CHECK(g.enc[1].steps_per_detent == 2 && g.enc[0].steps_per_detent == 4, "steps per detent");
	CHECK(g.button[2].line == 7 && g.button[2].action == HAL_PREV && g.button[0].action == HAL_PRESET &&
		      g.button[1].action == HAL_SCREENSHOT && g.button[3].action == HAL_QUIT,
	      "buttons");
	struct hal_keys_config k;
	hal_config_keys(&p, &k);
	CHECK(k.mode == HAL_KEYS_EVDEV && !strcmp(k.evdev, "/dev/input/event9"), "keys");
	struct hal_v4l2_config v;
	hal_config_v4l2(&p, 64, 48, &v);
	CHECK(!strcmp(v.device, "/dev/video7") && v.format == CF_NV12 && v.matrix == CM_BT709 &&
		      v.io == HAL_V4L2_IO_WRITE && v.fps == 25 && v.width == 64 && v.height == 48,
	      "v4l2");
	params_defaults(&p);
	hal_config_v4l2(&p, 64, 48, &v);
	CHECK(v.format == -1 && v.matrix == CM_BT601 && v.io == HAL_V4L2_IO_AUTO, "v4l2 defaults: the first format");
	CHECK(v.gpu.compile && v.gpu.log.fn && v.log.fn, "seams filled");
}

int main(void)
{
	test_config();
	test_knobs();
	test_keys();
	test_evdev();
	struct platform *plat = fixture_open();
	test_osd();
	test_open();
	platform_close(plat);
	return tc_done("hal");
}
