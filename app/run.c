/* isoterra — the frame loop (one, for every scene and destination) and the
 * program's run around it: platform, GL, renderer, controls, sinks, scene;
 * the summary at the end. */
#include "run.h"
#include "params.h"
#include "core.h"
#include "controls.h"
#include "gpu.h"
#include "kiosk.h"
#include "platform.h"
#include "render.h"
#include "scene.h"
#include "edit.h"
#include "output.h"

#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* The realtime clock's frame (--clock realtime): the tick now, or the next
 * one when this tick was drawn already (slept for: every frame a new
 * instant, the same on every board).  Its time within the period, and
 * its number there (what a %d in --out takes). */
static double realtime_frame(const struct params *p, long long *last_tick, int *number)
{
	long long tick = clock_realtime_tick(p->fps);
	if (tick <= *last_tick) {
		tick = *last_tick + 1;
		int rc = clock_sleep_until(CLOCK_REALTIME, (double)tick / p->fps);
		if (rc)
			log_warn("clock_nanosleep: %s", strerror(rc));
	}
	*last_tick = tick;
	long long period = (long long)llround(p->clock_period * p->fps);
	if (period < 1)
		period = 1;
	long long in = tick % period;
	*number = (int)in;
	return (double)in / p->fps;
}

/* The picture's size for an output of w x h: turned by the renderer's
 * turn (--rotate, unless the display turns it: odd quarter turns swap
 * them). */
static void upright_size(const struct renderer *r, int w, int h, int *pw, int *ph)
{
	bool odd = renderer_rotation(r) & 1;
	*pw = odd ? h : w;
	*ph = odd ? w : h;
}

/* The frame's part of the wall (params/wall.h) at the loop's size now. */
static int frame_view(const struct frame_loop *lp, struct wall_view *v, char *err, size_t errlen)
{
	int across = lp->across > 1 ? lp->across : 1, pw, ph;
	upright_size(lp->r, lp->w, lp->h, &pw, &ph);
	int tw = across > 1 ? lp->tile_w : pw, th = across > 1 ? lp->tile_h : ph;
	return wall_view(lp->p, tw, th, across, v, err, errlen);
}

/* The frame cap: sleeps until this frame's absolute deadline (CLOCK_MONOTONIC),
 * 1/cap after the last one's, before the frame goes to the sinks (a
 * display presents it then: the intervals the viewer sees are the cap's,
 * whatever each frame's work took); a frame more than one period late
 * starts the schedule again from now (no burst to catch up). */
static void pace(double cap, double *deadline)
{
	double now = clock_ms() / 1e3, period = 1.0 / cap;
	double next = *deadline + period;
	if (*deadline <= 0.0 || now > next + period) { /* the first frame, or late */
		*deadline = now;
		return;
	}
	*deadline = next;
	if (now >= next)
		return;
	int rc = clock_sleep_until(CLOCK_MONOTONIC, next);
	if (rc)
		log_warn("clock_nanosleep: %s", strerror(rc));
}

/* Paused on a display, the frame on screen already shows the pause: no
 * frame is drawn until an input changes something (a parameter, the pause
 * itself, quit), or a second went by (the window system's events and the
 * watchdog are served by the frames).  Polls the inputs every 20 ms. */
static bool paused_wait(struct frame_loop *lp, int f)
{
	struct params *p = lp->p;
	static struct params before; /* large: not on the stack */
	before = *p;
	for (int i = 0; i < 50; i++) {
		if (lp->watch_signals && signals_quit())
			return false;
		struct timespec d = { 0, 20 * 1000 * 1000 };
		nanosleep(&d, NULL);
		if (controls_poll(lp->ctl, p)) {
			p->count = f + 1;
			return false;
		}
		if (!controls_paused(lp->ctl) || memcmp(&before, p, sizeof(before)))
			return false;
	}
	return true;
}

/* The battery in the top-right corner (osd, osd_battery): its level as the
 * bar, its state below.  0, or -1 with err. */
static int battery_osd(struct frame_loop *lp, char *err, size_t errlen)
{
	const struct battery *b = power_battery(lp->power);
	if (!b->present || !lp->p->osd || !lp->p->osd_battery)
		return 0;
	if (!lp->battery_osd && !(lp->battery_osd = osd_create(err, errlen)))
		return -1;
	char title[OSD_COLS + 1], value[OSD_COLS + 1];
	snprintf(title, sizeof(title), "battery %d%%", b->percent);
	snprintf(value, sizeof(value), "%s", power_low(lp->power) ? "low power" : b->charging ? "charging" : "");
	unsigned fbo;
	int w, h;
	renderer_target(lp->r, &fbo, &w, &h);
	if (osd_draw_right(lp->battery_osd, fbo, w, h, title, value, (float)b->percent / 100.0f, lp->p->osd_scale,
			   1.0f) < 0) {
		snprintf(err, errlen, "drawing the battery's OSD failed");
		return -1;
	}
	return 0;
}

int frame_loop_run(struct frame_loop *lp, char *err, size_t errlen)
{
	struct params *p = lp->p;
	double start = clock_ms() / 1e3;
	struct pause_clock frame_clock = { 0 }, wall_clock = { 0 };
	long long last_tick = LLONG_MIN;
	double deadline = 0.0;
	bool shown_paused = false;
	double last_work_ms = -1.0; /* the frame before's work (scene_frame) */
	unsigned presets_seen = 0;  /* the preset button's presses seen ... */
	double preset_flight = 0.0; /* ... and the clock when the last one was */
	lp->frames = 0;
	err[0] = 0;
	for (int f = 0; p->count == 0 || f < p->count; f++) {
		if (lp->watch_signals && signals_quit())
			break;
		/* paused on a display: idle, nothing rendered, until an input
		 * arrives; once a second the picture shown is handed to the sinks
		 * again (the display sees signals, window events and the
		 * watchdog's ping there) */
		bool idle = lp->live && shown_paused && controls_paused(lp->ctl) && paused_wait(lp, f);
		double work_t0 = clock_ms(), capped_ms = 0.0;
		/* the frame cap in force: max_fps, lowered by the low-power profile */
		bool low = power_update(lp->power, p, clock_ms() / 1e3);
		double cap = p->max_fps;
		if (low && (cap <= 0 || cap > p->low_power_fps))
			cap = p->low_power_fps;
		if (controls_poll(lp->ctl, p)) /* quit: this frame is the last */
			p->count = f + 1;
		struct scene_timing tm = { 0, 0 };
		char msg[512]; /* a saved shader file rebuilt; a broken one reported, the last good kept */
		if (shader_watch_poll(lp->shaders, msg, sizeof(msg)) < 0) {
			log_error("%s", msg);
			controls_notice(lp->ctl, p, "shader error", msg);
		}
		/* the animation clocks: the realtime one (every board the same
		 * instant, no pause), or frame time and the live world's wall
		 * clock, stopped while the controls pause */
		int number = f;
		float frame_time;
		double clock_time, show_time;
		if (wall_clock_realtime(p, err, errlen) > 0) {
			clock_time = show_time = realtime_frame(p, &last_tick, &number);
			frame_time = (float)clock_time;
		} else {
			bool paused = controls_paused(lp->ctl);
			frame_time = pause_clock_time(&frame_clock, (float)f / p->fps, paused);
			double ct = lp->live ? clock_ms() / 1e3 - start : (double)f / p->fps;
			clock_time = ct - (double)((float)ct - pause_clock_time(&wall_clock, (float)ct, paused));
			show_time = ct;
		}
		if (controls_presets_applied(lp->ctl) != presets_seen) { /* its flight from its own spawn */
			presets_seen = controls_presets_applied(lp->ctl);
			preset_flight = clock_time;
		}
		bool last = p->count > 0 && f == p->count - 1;
		if (!idle) {
			kiosk_frame_begin(lp->kiosk, p, lp->r, show_time);
			/* the flight starts again with a show (as it begins, above)
			 * or a preset from the controls */
			double flight_start = kiosk_show_start(lp->kiosk);
			if (preset_flight > flight_start)
				flight_start = preset_flight;
			struct wall_view view;
			if (frame_view(lp, &view, err, errlen) < 0)
				return -1;
			int pw, ph; /* the upright picture (--rotate turns it onto the output) */
			upright_size(lp->r, lp->w, lp->h, &pw, &ph);
			struct scene_frame sf = { .index = f, .last = last, .live = lp->live, .r = lp->r, .w = pw,
						  .h = ph, .view = &view, .frame_time = frame_time, .clock_time = clock_time,
						  .flight_start = flight_start,
						  .refresh_hz = lp->refresh_hz, .cap_fps = cap,
						  .min_quality = low ? p->low_power_quality : 0, .timing = lp->timing ? &tm : NULL,
						  .last_work_ms = last_work_ms };
			controls_flight(lp->ctl, sf.move, sf.turn);
			if (lp->scene->ops->frame(lp->scene, p, &sf, err, errlen) < 0 ||
			    kiosk_frame_end(lp->kiosk, lp->r, err, errlen) < 0 ||
			    controls_frame(lp->ctl, lp->r, p, err, errlen) < 0 || battery_osd(lp, err, errlen) < 0)
				return -1;
		}
		struct sink_frame fr = { .r = lp->r, .w = lp->w, .h = lp->h, .index = f, .number = number,
					 .count = p->count,
					 .last = last, .update_ms = tm.update_ms,
					 .draw_ms = tm.draw_ms, .screenshot = controls_take_screenshot(lp->ctl),
					 .battery_percent = -1, .low_power = low, .cap_fps = cap };
		const struct battery *bat = power_battery(lp->power);
		if (bat->present) {
			fr.battery_percent = bat->percent;
			snprintf(fr.battery_status, sizeof(fr.battery_status), "%s", bat->status);
		}
		if (lp->scene->ops->status)
			lp->scene->ops->status(lp->scene, fr.status, sizeof(fr.status));
		if (cap > 0) { /* frames handed to the display (the sinks) at the cap's pace */
			double t = clock_ms();
			pace(cap, &deadline);
			capped_ms = clock_ms() - t;
		}
		int q = sinks_frame(lp->sinks, &fr, err, errlen);
		/* the frame's work: its time less the cap's sleep and the
		 * display's waits (an idle frame's is not a frame time) */
		last_work_ms = idle ? -1.0 : clock_ms() - work_t0 - capped_ms - fr.wait_ms;
		lp->r = fr.r; /* a display's resize */
		lp->w = fr.w;
		lp->h = fr.h;
		if (q < 0)
			return -1;
		lp->frames = f + 1;
		shown_paused = controls_paused(lp->ctl);
		notify_frame(lp->notify);
		if (q > 0)
			break;
	}
	return 0;
}

int render_to_image(const struct params *p_in, struct image *img, char *err, size_t errlen)
{
	struct params p = *p_in;
	int w, h;
	memset(img, 0, sizeof(*img));
	if (cli_parse_size(p.size, &w, &h) < 0) {
		snprintf(err, errlen, "--size '%s' is not WxH", p.size);
		return -1;
	}
	if (p.count < 1) {
		snprintf(err, errlen, "render_to_image: count must be at least 1");
		return -1;
	}
	if (heightmap_fit_file(&p, err, errlen) < 0)
		return -1;
	struct scene *scene = scene_create(&p, err, errlen);
	if (!scene)
		return -1;
	struct renderer *r = renderer_create_turned(w, h, (int)p.rotate, p.antialias, err, errlen);
	struct sink_set sinks = { .n = 0 };
	int rc = -1;
	if (r && sinks_add(&sinks, sink_memory_open(img, err, errlen)) == 0) {
		struct frame_loop lp = { .p = &p, .scene = scene, .sinks = &sinks, .r = r, .w = w, .h = h };
		rc = frame_loop_run(&lp, err, errlen);
		r = lp.r;
		if (rc < 0 && !err[0])
			snprintf(err, errlen, "rendering failed (see the log)");
		struct sink_end end = { .ok = rc == 0, .frames = lp.frames, .scene = scene, .r = r };
		char e[512];
		if (sinks_finish(&sinks, &end, e, sizeof(e)) < 0 && rc == 0) {
			snprintf(err, errlen, "%s", e);
			rc = -1;
		}
	}
	sinks_destroy(&sinks);
	renderer_destroy(r);
	scene_destroy(scene);
	if (rc < 0)
		image_free(img);
	return rc;
}

/* ---- the program's run --------------------------------------------------- */
struct run {
	struct params p;
	struct platform *plat;
	struct renderer *r;
	int w, h;
	struct controls *ctl;
	struct sink *display;  /* opened with the platform, then the last sink */
	struct sink_set sinks;
	struct scene *scene;
	struct shader_watch *shaders;
	struct kiosk *kiosk;
	struct power *power;
	int argc;
	char **argv;
};

/* Platform, GL and the renderer, at the window's / mode's size on a
 * display.  0, or the exit code with err. */
static int open_gpu(struct run *rn, char *err, size_t errlen)
{
	const struct params *p = &rn->p;
	struct platform_options po = { .name = p->platform, .width = rn->w, .height = rn->h, .debug = p->verbose,
		.fullscreen = p->fullscreen, .hide_cursor = p->hide_cursor, .x11_present = p->x11_present, .drm_device = p->drm_device,
		.mode = p->mode, .kms_legacy = p->kms_legacy, .device = p->device, .rotate = (int)p->rotate };
	sink_display_outputs(p, &po); /* --outputs: the connectors and their layout */
	rn->plat = platform_open(&po, err, errlen);
	if (!rn->plat)
		return 1;
	if (!rn->plat->headless && !(rn->display = sink_display_open(rn->plat, p, err, errlen)))
		return 1;
	if (rn->plat->headless && p->count == 0) {
		snprintf(err, errlen, "--count 0 (until closed) needs a display platform (gbm, wayland, x11), not '%s'",
			 rn->plat->backend->name);
		return 1;
	}
	if (!rn->plat->headless) {
		rn->w = rn->plat->width;
		rn->h = rn->plat->height;
	}
	struct gpu_caps caps;
	if (gpu_init(&caps, p->verbose, err, errlen) < 0)
		return 1;
	log_debug("platform %s on %s", rn->plat->backend->name, rn->plat->device_desc);
	/* the turn the display does not do itself (gbm: the plane's rotation) */
	int turn = rn->plat->rotated ? 0 : (int)p->rotate;
	rn->r = renderer_create_turned(rn->w, rn->h, turn, p->antialias, err, errlen);
	return rn->r ? 0 : 1;
}

/* Everything the frame loop needs.  0, or the exit code with err. */
static int open_run(struct run *rn, bool signals_ok, char *err, size_t errlen)
{
	int rc = open_gpu(rn, err, errlen);
	if (rc)
		return rc;
	if (!signals_ok && !rn->plat->headless)
		log_warn("cannot install the SIGINT/SIGTERM handlers; the display is not restored on those");
	rn->ctl = controls_create(&rn->p, err, errlen);
	if (!rn->ctl)
		return 2;
	rc = sinks_open(&rn->sinks, &rn->p, rn->w, rn->h, err, errlen);
	if (rc)
		return rc;
	if (rn->p.results[0] || (rn->plat->headless && rn->p.fps_report > 0)) {
		struct sink *rs = sink_results_open(&rn->p, rn->plat->headless, err, errlen);
		if (!rs)
			return 2;
		if (sinks_add(&rn->sinks, rs) < 0) {
			rs->ops->destroy(rs);
			snprintf(err, errlen, "too many outputs");
			return 2;
		}
	}
	if (rn->display) {
		sinks_add(&rn->sinks, rn->display); /* last: a resize re-creates the renderer */
		rn->display = NULL;
	}
	if (!(rn->power = power_create(&rn->p, !rn->plat->headless))) {
		snprintf(err, errlen, "out of memory");
		return 2;
	}
	rn->kiosk = kiosk_create(&rn->p, rn->argc, rn->argv, err, errlen);
	if (!rn->kiosk)
		return 2;
	if (heightmap_fit_file(&rn->p, err, errlen) < 0) /* a georeferenced map: the volume on it */
		return 1;
	rn->scene = scene_create(&rn->p, err, errlen);
	return rn->scene ? 0 : 1;
}

/* "N frame(s) WxH, <the scene's line> -> where the frames went" */
static void summary(struct run *rn, int frames)
{
	char line[512], warn[512];
	if (rn->scene->ops->report(rn->scene, &rn->p, line, sizeof(line), warn, sizeof(warn)) < 0)
		return;
	if (warn[0])
		log_warn("%s", warn);
	const char *dest = sinks_dest(&rn->sinks);
	if (!dest)
		dest = rn->p.count == 0 ? "(display only: no image)" : "(stopped before the last frame: no image)";
	log_info("%d frame(s) %dx%d, %s -> %s", frames, rn->w, rn->h, line, dest);
}

/* Every file the run will write, checked before any work (names, their
 * directories): 0, or the exit code with err.  Screenshots, taken on
 * request while the run goes on, only where keys or GPIO controls can ask
 * for one, and a warning: a kiosk whose working directory is read-only
 * still starts. */
static int check_outputs(const struct params *p, char *err, size_t errlen)
{
	enum cli_out_kind kind;
	if (cli_parse_out(p->out, &kind, err, errlen) < 0)
		return 2;
	int last = p->count > 0 ? p->count - 1 : INT_MAX;
	/* a display run until closed (--count 0) writes no single PNG */
	bool writes_out = strcmp(p->out, "-") && !(p->count == 0 && kind == CLI_OUT_PNG);
	if (writes_out && cli_check_dest("out", p->out, kind == CLI_OUT_PNG_SEQUENCE ? last : 0, err, errlen) < 0)
		return 1;
	if (p->export_mesh[0] && cli_check_dest("export_mesh", p->export_mesh, 0, err, errlen) < 0)
		return 1;
	if (p->results[0] && strcmp(p->results, "-") && cli_check_dest("results", p->results, 0, err, errlen) < 0)
		return 1;
	bool keys = p->keyboard == KEYBOARD_TTY || p->keyboard == KEYBOARD_EVDEV ||
		    (p->keyboard == KEYBOARD_AUTO && isatty(0));
	bool shots = keys || p->gpio_chip[0] || p->enc1_chip[0] || p->enc2_chip[0] || p->button_chip[0];
	if (shots && cli_check_dest("screenshot", p->screenshot, INT_MAX, err, errlen) < 0)
		log_warn("%s: screenshots will not be written", err);
	err[0] = 0;
	return 0;
}

/* The frames, the summary, the sinks finished (their files committed only
 * when every frame was done).  The exit code: 0, 1 an error, 128 + the
 * signal that stopped a run before its last frame. */
static int run_frames(struct run *rn)
{
	struct params *p = &rn->p;
	char err[1024];
	if (p->scene == SCENE_WORLD && p->camera == CAMERA_MANUAL)
		log_info("manual camera: i/k forward/back, j/l turn, u/o up/down, y/h pitch (keyboard: %s%s)",
			 p->keyboard == KEYBOARD_OFF ? "off" : "terminal or evdev",
			 p->gamepad == GAMEPAD_AUTO ? "; gamepad: sticks" : p->keyboard == KEYBOARD_OFF ? "!" : "");
	struct frame_loop lp = { .p = p, .scene = rn->scene, .ctl = rn->ctl, .sinks = &rn->sinks, .r = rn->r,
				 .shaders = rn->shaders,
				 .w = rn->w, .h = rn->h, .live = !rn->plat->headless,
				 .watch_signals = rn->plat->headless, .refresh_hz = rn->plat->refresh_hz,
				 .timing = p->results[0] != 0, .notify = notify_open(), .kiosk = rn->kiosk,
				 .power = rn->power };
	sink_display_tiles(rn->plat, &lp.tile_w, &lp.tile_h, &lp.across); /* --outputs along a wall's row */
	int rc = frame_loop_run(&lp, err, sizeof(err)) < 0 ? 1 : 0;
	osd_destroy(lp.battery_osd);
	notify_close(lp.notify); /* STOPPING=1 */
	rn->r = lp.r;
	rn->w = lp.w;
	rn->h = lp.h;
	if (rc && err[0])
		log_error("%s", err);
	int sig = signals_quit();
	if (rc == 0 && sig && p->count > 0 && lp.frames < p->count) {
		log_error("stopped by %s after %d of %d frames: no file written", sig == SIGINT ? "SIGINT" : "SIGTERM",
			  lp.frames, p->count);
		rc = 128 + sig;
	}
	if (rc == 0)
		summary(rn, lp.frames);
	struct sink_end end = { .ok = rc == 0, .frames = lp.frames, .scene = rn->scene, .r = rn->r };
	if (sinks_finish(&rn->sinks, &end, err, sizeof(err)) < 0 && rc == 0) {
		log_error("%s", err);
		rc = 1;
	}
	if (sig && rc == 0 && rn->plat->headless)
		log_info("stopped by signal");
	return rc;
}

/* In order: what needs GL, the platform (which restores a display), the
 * sinks' final reports, the signal handlers. */
static void close_run(struct run *rn)
{
	scene_destroy(rn->scene);
	kiosk_destroy(rn->kiosk);
	power_destroy(rn->power);
	controls_destroy(rn->ctl);
	renderer_destroy(rn->r);
	shader_watch_close(rn->shaders);
	platform_close(rn->plat);
	sinks_destroy(&rn->sinks);
	if (rn->display)
		rn->display->ops->destroy(rn->display);
	signals_restore();
}

int run_program(const struct params *p_in)
{
	return run_program_args(p_in, 0, NULL);
}

int run_program_args(const struct params *p_in, int argc, char **argv)
{
	struct run rn;
	memset(&rn, 0, sizeof(rn));
	rn.p = *p_in;
	rn.argc = argc;
	rn.argv = argv;
	char err[1024];
	if (cli_parse_size(rn.p.size, &rn.w, &rn.h) < 0) {
		log_error("--size '%s' is not WxH", rn.p.size);
		return 2;
	}
	log_set_level(rn.p.verbose ? LOG_DEBUG : LOG_INFO);
	shader_set_dir(rn.p.shader_dir);
	gpu_program_cache_config(rn.p.program_cache, NULL);
	int rc = check_outputs(&rn.p, err, sizeof(err));
	if (rc) {
		log_error("%s", err);
		return rc;
	}
	if (rn.p.shader_dir[0] && !(rn.shaders = shader_watch_open(rn.p.shader_dir, err, sizeof(err)))) {
		log_error("%s", err);
		return 2;
	}
	bool signals_ok = signals_install() == 0;
	rc = open_run(&rn, signals_ok, err, sizeof(err));
	if (rc) {
		log_error("%s", err);
		struct sink_end end = { .ok = false };
		sinks_finish(&rn.sinks, &end, err, sizeof(err));
	} else {
		rc = run_frames(&rn);
	}
	close_run(&rn);
	return rc;
}
