/* isoterra — the main job: headless frames of the terrain to PNG. */
#include "render.h"
#include "controls.h"
#include "cli.h"
#include "gpu.h"
#include "clock.h"
#include "log.h"
#include "ply.h"
#include "platform.h"
#include "display.h" /* issue 4: display platforms */

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "v4l2_out.h"
#include "world.h"
#include "y4m.h"

static volatile sig_atomic_t quit_requested;

static void on_signal(int sig)
{
	(void)sig;
	quit_requested = 1;
}

/* SIGINT/SIGTERM end the frame loop cleanly (files closed, devices
 * restored); a second signal kills as usual. */
static void install_signal_handlers(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_signal;
	sa.sa_flags = SA_RESETHAND;
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
}

/* "frame%04d.png" style names: the out parameter may hold one %d. */
static int frame_name(const char *pattern, int frame, char *buf, size_t len)
{
	const char *pc = strchr(pattern, '%');
	if (!pc) {
		snprintf(buf, len, "%s", pattern);
		return 0;
	}
	/* allow %d, %0Nd only */
	const char *q = pc + 1;
	while (*q >= '0' && *q <= '9')
		q++;
	if (*q != 'd' || strchr(q + 1, '%'))
		return -1;
	char fmt[32];
	snprintf(fmt, sizeof(fmt), "%%.%ds%%%.*s%%s", (int)(pc - pattern), (int)(q - pc), pc + 1);
	snprintf(buf, len, fmt, pattern, frame, q + 1);
	return 1;
}

/* Where frames go: PNG (one file, or one per frame with %d), or Y4M. */
struct frame_sink {
	const char *pattern;
	int per_frame;
	bool y4m;
	struct y4m y;
	int count;
	bool progress;
};

static bool ends_with(const char *s, const char *suf)
{
	size_t n = strlen(s), m = strlen(suf);
	return n >= m && !strcmp(s + n - m, suf);
}

static int sink_open(struct frame_sink *fs, const struct params *p, int w, int h)
{
	char err[512];
	char name[PARAM_STR_MAX + 32];
	memset(fs, 0, sizeof(*fs));
	fs->pattern = p->out;
	fs->count = p->count;
	fs->y4m = !strcmp(p->out, "-") || ends_with(p->out, ".y4m");
	fs->progress = p->count > 1 && isatty(2);
	if (fs->y4m) {
		if (y4m_open(&fs->y, p->out, w, h, (int)lroundf(p->fps), err, sizeof(err)) < 0) {
			log_error("%s", err);
			return -1;
		}
		return 0;
	}
	fs->per_frame = frame_name(p->out, 0, name, sizeof(name));
	if (fs->per_frame < 0) {
		log_error("--out '%s': only one %%d (or %%0Nd) is allowed in the file name", p->out);
		return -1;
	}
	return 0;
}

static bool sink_wants(const struct frame_sink *fs, int f)
{
	return fs->y4m || fs->per_frame || f == fs->count - 1;
}

static int sink_write(struct frame_sink *fs, struct renderer *r, int f)
{
	if (!sink_wants(fs, f))
		return 0;
	struct image img = { 0 };
	char err[512], name[PARAM_STR_MAX + 32];
	if (renderer_read(r, &img) < 0) {
		log_error("reading the frame back failed");
		return -1;
	}
	int rc;
	if (fs->y4m) {
		rc = y4m_write(&fs->y, &img);
		if (rc < 0)
			log_error("writing frame %d to '%s' failed", f, fs->pattern);
	} else {
		frame_name(fs->pattern, f, name, sizeof(name));
		rc = image_write_png(&img, name, err, sizeof(err));
		if (rc < 0)
			log_error("%s", err);
	}
	image_free(&img);
	if (fs->progress) {
		int width = 40, done = (f + 1) * width / fs->count;
		fprintf(stderr, "\r[%.*s%*s] %d/%d", done, "########################################", width - done, "",
			f + 1, fs->count);
		if (f + 1 == fs->count)
			fputc('\n', stderr);
	}
	return rc;
}

static int sink_close(struct frame_sink *fs)
{
	if (fs->y4m && y4m_close(&fs->y) < 0) {
		log_error("closing '%s' failed", fs->pattern);
		return -1;
	}
	return 0;
}

/* Where a finished frame goes: the sink and, on a display platform
 * (issue 4), the window or the KMS scanout.  On a resize the renderer is
 * re-created at the new size (w, h follow). */
struct frame_out {
	struct frame_sink *fs;
	struct platform *plat;
	struct display_loop *disp;
	struct renderer *r;
	int w, h;
	int frames; /* frames finished */
	struct controls *ctl;  /* knobs, keys, OSD, screenshots */
	struct v4l2_out *v4l2; /* V4L2 output */
};

static bool frame_more(const struct params *p, int f)
{
	return (p->count == 0 || f < p->count) && !quit_requested;
}

/* 0: go on, 1: stop (window closed, SIGINT/SIGTERM), -1: error (logged) */
static int frame_done(struct frame_out *o, int f)
{
	if (sink_write(o->fs, o->r, f) < 0)
		return -1;
	o->frames = f + 1;
	if (o->plat->headless)
		return 0;
	return display_frame(o->disp, o->plat, &o->r, &o->w, &o->h);
}

static const char *frame_dest(const struct frame_out *o, const struct params *p)
{
	if (o->fs->y4m || o->fs->per_frame || o->frames == p->count)
		return p->out;
	return p->count == 0 ? "(display only: no image)" : "(stopped before the last frame: no image)";
}

/* OSD and screenshot (the controls), then the V4L2 output. */
static int frame_overlays(struct frame_out *o, const struct params *p)
{
	char err[512];
	if (controls_frame(o->ctl, o->r, p, err, sizeof(err)) < 0) {
		if (err[0])
			log_error("%s", err);
		return -1;
	}
	unsigned fbo;
	int w, h;
	renderer_target(o->r, &fbo, &w, &h);
	return v4l2_out_frame(o->v4l2, fbo, w, h);
}

static int run_volume(struct params *p, struct frame_out *o)
{
	char err[512] = "";
	struct grid g;
	grid_from_params(&g, p);
	struct pipeline *pl = pipeline_create(&g, p, err, sizeof(err));
	if (!pl) {
		log_error("%s", err);
		return 1;
	}
	int rc = 1;
	struct pipeline_draw d;
	struct camera cam;
	float t0 = p->time;
	for (int f = 0; frame_more(p, f); f++) {
		if (controls_poll(o->ctl, p)) /* issue 5: inputs -> parameters; quit: this frame is the last */
			o->fs->count = p->count = f + 1;
		float t = controls_time(o->ctl, (float)f / p->fps);
		p->time = t0 + t;
		if (pipeline_run(pl, p) < 0)
			goto out;
		pipeline_draw_info(pl, &d);
		camera_orbit(&cam, p, &g, t, (float)o->w / (float)o->h);
		if (renderer_draw(o->r, &d, &cam, p) < 0 || frame_overlays(o, p) < 0)
			goto out;
		int q = frame_done(o, f);
		if (q < 0)
			goto out;
		if (q > 0)
			break;
	}
	struct extract_stats st;
	if (pipeline_read_stats(pl, &st) == 0) {
		if (st.overflow)
			log_warn("mesh capacity exceeded: the field needs %llu triangles / %llu vertices, capacity %u / %u; "
				 "output clamped (raise --max-triangles / --max-vertices)",
				 (unsigned long long)st.triangles_needed, (unsigned long long)st.vertices_needed,
				 st.triangle_capacity, st.vertex_capacity);
		log_info("%d frame(s) %dx%d, grid %d^3: %u triangles, %u vertices -> %s", o->frames, o->w, o->h,
			 p->grid, st.triangles, st.vertices, frame_dest(o, p));
	}
	if (p->export_mesh[0]) {
		struct mesh m;
		if (pipeline_read_mesh(pl, &m) < 0) {
			log_error("reading the mesh back failed");
			goto out;
		}
		int wr = ply_write(&m, p->export_mesh, err, sizeof(err));
		mesh_free(&m);
		if (wr < 0) {
			log_error("%s", err);
			goto out;
		}
	}
	rc = 0;
out:
	pipeline_destroy(pl);
	return rc;
}

static int run_world(struct params *p, struct frame_out *o)
{
	char err[512] = "";
	if (p->export_mesh[0])
		log_warn("--export-mesh exports the volume scene's mesh; ignored with --scene world");
	struct world *wd = world_create(p, err, sizeof(err));
	if (!wd) {
		log_error("%s", err);
		return 1;
	}
	struct autopilot ap;
	if (autopilot_init(&ap, p) < 0) {
		world_destroy(wd);
		log_error("out of memory");
		return 1;
	}
	int rc = 1;
	struct camera cam;
	float t0 = p->time;
	float far = p->view_distance * 1.2f;
	/* Offline (headless: PNG, Y4M, tests) every frame is complete and
	 * reproducible: time is frame / fps and each frame waits for its
	 * blocks.  On a display the world runs live: wall-clock time, and
	 * blocks stream in under the generation budget. */
	bool live = !o->plat->headless;
	double start = clock_ms() / 1e3;
	if (p->camera == CAMERA_MANUAL)
		log_info("manual camera: i/k forward/back, j/l turn, u/o up/down, y/h pitch (keyboard: %s)",
			 p->keyboard == KEYBOARD_OFF ? "off!" : "terminal or evdev");
	for (int f = 0; frame_more(p, f); f++) {
		if (controls_poll(o->ctl, p)) /* issue 5: inputs -> parameters; quit: this frame is the last */
			o->fs->count = p->count = f + 1;
		double t = live ? clock_ms() / 1e3 - start : (double)f / p->fps;
		t -= (double)((float)t - controls_time(o->ctl, (float)t)); /* paused time */
		p->time = t0; /* the world does not scroll: the camera moves */
		if (p->camera == CAMERA_MANUAL) { /* manual: the keys steer, rock still stops */
			float move[3], turn[2];
			controls_flight(o->ctl, move, turn);
			autopilot_steer(&ap, move, turn);
		}
		autopilot_advance(&ap, t);
		autopilot_camera(&ap, &cam, p->fov, (float)o->w / (float)o->h, far);
		int urc = f == 0 ? world_fill(wd, p, &cam, t) : world_update(wd, p, &cam, t, !live);
		if (urc < 0 || world_draw(wd, o->r, &cam, p, t) < 0 || frame_overlays(o, p) < 0)
			goto out;
		int q = frame_done(o, f);
		if (q < 0)
			goto out;
		if (q > 0)
			break;
	}
	struct world_stats st;
	world_get_stats(wd, &st);
	log_info("%d frame(s) %dx%d, world: %llu blocks generated (%llu empty, never regenerated), %d drawn, "
		 "%llu evicted%s -> %s",
		 o->frames, o->w, o->h, (unsigned long long)st.generated, (unsigned long long)st.empty_found, st.drawn,
		 (unsigned long long)st.evicted, st.overflowed ? ", some blocks over capacity (raise --block-tris)" : "",
		 frame_dest(o, p));
	rc = 0;
out:
	autopilot_free(&ap);
	world_destroy(wd);
	return rc;
}

int run_headless(const struct params *p_in)
{
	struct params p = *p_in;
	char err[512] = "";
	int w, h;
	if (cli_parse_size(p.size, &w, &h) < 0) {
		log_error("--size '%s' is not WxH", p.size);
		return 2;
	}
	log_set_level(p.verbose ? LOG_DEBUG : LOG_INFO);
	shader_set_dir(p.shader_dir);
	install_signal_handlers();

	struct frame_sink fs;
	char name[PARAM_STR_MAX + 32];
	if (frame_name(p.out, 0, name, sizeof(name)) < 0) {
		log_error("--out '%s': only one %%d (or %%0Nd) is allowed in the file name", p.out);
		return 2;
	}
	struct platform_options po = { .name = p.platform, .width = w, .height = h, .debug = p.verbose,
		.fullscreen = p.fullscreen, .hide_cursor = p.hide_cursor, .drm_device = p.drm_device,
		.mode = p.mode, .kms_legacy = p.kms_legacy };
	struct platform *plat = platform_open(&po, err, sizeof(err));
	if (!plat) {
		log_error("%s", err);
		return 1;
	}
	int rc = 1;
	struct renderer *r = NULL;
	struct controls *ctl = NULL; /* knobs, keys, OSD, screenshots */
	struct v4l2_out *v4l2 = NULL;
	/* issue 4: display platforms render at the window's / mode's size */
	struct display_loop disp;
	display_begin(&disp, plat, &p);
	if (plat->headless && p.count == 0) {
		log_error("--count 0 (until closed) needs a display platform (gbm, wayland, x11), not '%s'",
			  plat->backend->name);
		goto out;
	}
	if (!plat->headless) {
		w = plat->width;
		h = plat->height;
	}
	struct gpu_caps caps;
	if (gpu_init(&caps, p.verbose, err, sizeof(err)) < 0) {
		log_error("%s", err);
		goto out;
	}
	log_debug("platform %s on %s", plat->backend->name, plat->device_desc);
	r = renderer_create(w, h, err, sizeof(err));
	if (!r) {
		log_error("%s", err);
		goto out;
	}
	ctl = controls_create(&p, err, sizeof(err));
	if (!ctl) {
		log_error("%s", err);
		rc = 2;
		goto out;
	}
	struct hal_v4l2_config vc;
	controls_v4l2_config(&p, w, h, &vc);
	v4l2 = v4l2_out_open(&vc, err, sizeof(err));
	if (!v4l2 && err[0]) {
		log_error("%s", err);
		rc = 2;
		goto out;
	}
	if (sink_open(&fs, &p, w, h) < 0)
		goto out;
	struct frame_out o = { .fs = &fs, .plat = plat, .disp = &disp, .r = r, .w = w, .h = h, .ctl = ctl,
			      .v4l2 = v4l2 };
	rc = p.scene == SCENE_WORLD ? run_world(&p, &o) : run_volume(&p, &o);
	r = o.r; /* a resize may have replaced it */
	if (sink_close(&fs) < 0)
		rc = 1;
	if (quit_requested && rc == 0)
		log_info("stopped by signal");
out:
	v4l2_out_close(v4l2);
	controls_destroy(ctl);
	renderer_destroy(r);
	platform_close(plat);
	display_end(&disp);
	return rc;
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
	struct grid g;
	grid_from_params(&g, &p);
	struct pipeline *pl = pipeline_create(&g, &p, err, errlen);
	if (!pl)
		return -1;
	struct renderer *r = renderer_create(w, h, err, errlen);
	int rc = -1;
	if (r) {
		struct pipeline_draw d;
		struct camera cam;
		float t0 = p.time;
		rc = 0;
		for (int f = 0; f < p.count && rc == 0; f++) {
			float t = (float)f / p.fps;
			p.time = t0 + t;
			rc = pipeline_run(pl, &p);
			pipeline_draw_info(pl, &d);
			camera_orbit(&cam, &p, &g, t, (float)w / (float)h);
			if (rc == 0)
				rc = renderer_draw(r, &d, &cam, &p);
		}
		if (rc == 0)
			rc = renderer_read(r, img);
		if (rc < 0)
			snprintf(err, errlen, "rendering failed (see the log)");
	}
	renderer_destroy(r);
	pipeline_destroy(pl);
	return rc;
}
