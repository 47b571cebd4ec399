/* isoterra — V4L2 output benchmark: render fps of the volume scene at
 * 640x480 without video output (the baseline) and with every frame streamed
 * (GPU conversion to YUYV BT.601, PBO read-back, write()), in one run,
 * interleaved (grid 48, extracted every frame as in the app): rounds of A (no output), B (output paced to --v4l2-fps,
 * default 30) and C (output of every frame, no pacing).  Goal: B and C at
 * most 10% below A.
 *
 * The device: --device /dev/videoN, else the first /dev/video* that is a
 * video output; with none (CI machines) the same conversion and read-back
 * run and each frame is write()n into a file (--sink FILE, default a
 * temporary file): the pipeline up to the kernel, without a driver.
 * usage: bench_v4l2 [--quick] [--platform NAME] [--device DEV] [--v4l2-fps N] */
#include "app.h"
#include "v4l2_out.h"
#include "hal_config.h"
#include "terrain.h"

#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include "bench.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

/* the first video output device, or "" */
static void find_output(char *path, size_t len)
{
	path[0] = 0;
	for (int i = 0; i < 64; i++) {
		char p[32];
		snprintf(p, sizeof(p), "/dev/video%d", i);
		int fd = open(p, O_RDWR | O_NONBLOCK);
		if (fd < 0)
			continue;
		struct v4l2_capability cap;
		memset(&cap, 0, sizeof(cap));
		int ok = ioctl(fd, VIDIOC_QUERYCAP, &cap) == 0;
		close(fd);
		uint32_t caps = cap.capabilities & V4L2_CAP_DEVICE_CAPS ? cap.device_caps : cap.capabilities;
		if (ok && (caps & V4L2_CAP_VIDEO_OUTPUT)) {
			snprintf(path, len, "%s", p);
			return;
		}
	}
}

/* No device: each converted frame is written into a file. */
struct file_out {
	int fd;
	unsigned long errors;
};

static void to_file(void *user, const uint8_t *bytes, size_t size)
{
	struct file_out *fo = user;
	if (pwrite(fo->fd, bytes, size, 0) != (ssize_t)size)
		fo->errors++;
}

struct bench_scene {
	struct params p;
	struct grid g;
	struct pipeline *pl;
	struct renderer *r;
	int w, h, frame;
};

/* n frames; v: NULL = no video output.  Returns frames per second. */
static double run(struct bench_scene *s, struct v4l2_out *v, int n)
{
	struct pipeline_draw d;
	struct camera cam;
	glFinish();
	double t0 = clock_ms() / 1e3;
	for (int i = 0; i < n; i++, s->frame++) {
		float t = (float)s->frame / 30.0f;
		s->p.time = t;
		if (bench_run(s->pl, &s->p) < 0)
			return -1;
		pipeline_draw_info(s->pl, &d);
		camera_orbit(&cam, &s->p, &s->g, t, (float)s->w / (float)s->h);
		if (renderer_draw(s->r, &d, &cam, &s->p) < 0)
			return -1;
		if (v) {
			unsigned fbo;
			int fw, fh;
			renderer_target(s->r, &fbo, &fw, &fh);
			if (v4l2_out_frame(v, fbo, fw, fh) < 0)
				return -1;
		}
		glFinish(); /* the frame is done: as the headless app's loop ends a frame */
	}
	return n / (clock_ms() / 1e3 - t0);
}

struct options {
	const char *plat_name, *dev, *sink_path;
	int quick;
	double fps;
};

static int parse_args(int argc, char **argv, struct options *o)
{
	*o = (struct options){ .plat_name = "auto", .fps = 30 };
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--quick"))
			o->quick = 1;
		else if (!strcmp(argv[i], "--platform") && i + 1 < argc)
			o->plat_name = argv[++i];
		else if (!strcmp(argv[i], "--device") && i + 1 < argc)
			o->dev = argv[++i];
		else if (!strcmp(argv[i], "--sink") && i + 1 < argc)
			o->sink_path = argv[++i];
		else if (!strcmp(argv[i], "--v4l2-fps") && i + 1 < argc)
			o->fps = atof(argv[++i]);
		else {
			fprintf(stderr, "usage: %s [--quick] [--platform NAME] [--device DEV] [--sink FILE] [--v4l2-fps N]\n",
				argv[0]);
			return -1;
		}
	}
	return 0;
}

/* The outputs: paced and (without a device) every-frame.  0 or -1. */
static int open_outputs(const struct options *o, const struct bench_scene *s, struct file_out *fo, struct v4l2_out **paced,
			struct v4l2_out **every)
{
	char err[512], found[64], tmpl[] = "/tmp/isoterra-bench-v4l2-XXXXXX";
	const char *dev = o->dev;
	if (!dev) {
		find_output(found, sizeof(found));
		dev = found[0] ? found : NULL;
	}
	if (dev) {
		struct hal_v4l2_config vc = { .device = dev, .format = CF_YUYV, .matrix = CM_BT601,
					      .io = HAL_V4L2_IO_AUTO, .fps = o->fps, .width = s->w, .height = s->h,
					      .gpu = *hal_config_gpu(), .log = hal_config_log() };
		*paced = v4l2_out_open(&vc, err, sizeof(err));
		if (!*paced) {
			fprintf(stderr, "bench: %s: %s\n", dev, err);
			return -1;
		}
		printf("output: %s (a V4L2 video output device), YUYV 640x480 BT.601\n", dev);
		return 0;
	}
	fo->fd = o->sink_path ? open(o->sink_path, O_WRONLY | O_CREAT | O_TRUNC, 0644) : mkstemp(tmpl);
	if (fo->fd < 0) {
		fprintf(stderr, "bench: %s: %s\n", o->sink_path ? o->sink_path : tmpl, strerror(errno));
		return -1;
	}
	if (!o->sink_path)
		unlink(tmpl);
	struct frame_format f = { .fmt = CF_YUYV, .width = s->w, .height = s->h, .matrix = CM_BT601 };
	conv_fmt_tight(f.fmt, s->w, s->h, &f.bytesperline, &f.sizeimage);
	*paced = v4l2_out_open_bytes(&f, o->fps, to_file, fo, hal_config_gpu(), err, sizeof(err));
	*every = *paced ? v4l2_out_open_bytes(&f, 0, to_file, fo, hal_config_gpu(), err, sizeof(err)) : NULL;
	if (!*every) {
		fprintf(stderr, "bench: %s\n", err);
		return -1;
	}
	printf("output: no V4L2 output device here: GPU conversion to YUYV 640x480 BT.601, PBO read-back and "
	       "write() of each frame into %s (no driver)\n", o->sink_path ? o->sink_path : "a temporary file");
	return 0;
}

/* The output path alone, on the last rendered frame: resolve, GPU
 * conversion, read-back and hand-over, each frame finished.  Only unpaced
 * (the sink): a device's output waits for its frame slots.  ms per frame,
 * or -1. */
static double output_alone(struct bench_scene *s, struct v4l2_out *every, int n)
{
	unsigned fbo;
	int fw, fh;
	renderer_target(s->r, &fbo, &fw, &fh);
	double t1 = clock_ms();
	for (int i = 0; i < n; i++) {
		if (v4l2_out_frame(every, fbo, fw, fh) < 0)
			return -1;
		glFinish();
	}
	return (clock_ms() - t1) / n;
}

static double median(double *v, int n)
{
	qsort(v, (size_t)n, sizeof(double), bench_cmp_double);
	return v[n / 2];
}

/* Rounds of A (no output), B (paced), C (every frame); the medians. */
static int measure(struct bench_scene *s, const struct options *o, struct v4l2_out *paced, struct v4l2_out *every)
{
	run(s, paced, 3); /* warm-up: shaders, converter */
	if (every)
		run(s, every, 3);
	run(s, NULL, 3);
	int rounds = o->quick ? 3 : 5, n = o->quick ? 10 : 30;
	double a[16], b[16], c[16];
	for (int i = 0; i < rounds; i++) {
		a[i] = run(s, NULL, n);
		b[i] = run(s, paced, n);
		c[i] = every ? run(s, every, n) : 0;
		if (a[i] < 0 || b[i] < 0 || c[i] < 0) {
			fprintf(stderr, "bench: rendering failed\n");
			return -1;
		}
	}
	double ma = median(a, rounds), mb = median(b, rounds), mc = median(c, rounds);
	printf("%d rounds x %d frames, median fps:\n", rounds, n);
	printf("  no video output          %7.1f fps\n", ma);
	printf("  V4L2 out paced to %2.0f fps %7.1f fps  (%+.1f%% vs no output)%s\n", o->fps, mb, 100 * (mb / ma - 1),
	       ma > o->fps ? "  [the render loop is paced to the output rate]" : "");
	if (!every)
		return 0;
	printf("  V4L2 out, every frame    %7.1f fps  (%+.1f%% vs no output)\n", mc, 100 * (mc / ma - 1));
	double out_ms = output_alone(s, every, n);
	if (out_ms < 0) {
		fprintf(stderr, "bench: video output failed\n");
		return -1;
	}
	printf("  output path alone        %7.1f ms per frame (%.1f%% of a %.0f ms frame without output)\n", out_ms,
	       100 * out_ms * ma / 1e3, 1e3 / ma);
	return 0;
}

int main(int argc, char **argv)
{
	struct options o;
	if (parse_args(argc, argv, &o) < 0)
		return 2;
	log_set_level(LOG_WARN);
	char err[512];
	struct bench_scene s;
	memset(&s, 0, sizeof(s));
	s.w = 640;
	s.h = 480;
	struct platform *plat = bench_open(o.plat_name, 64, 64);
	if (!plat)
		return 1;
	params_defaults(&s.p);
	s.p.grid = 48; /* the terrain is extracted every frame, as in the app: a grid that leaves the frame rate to rendering */
	grid_from_params(&s.g, &s.p);
	struct edits *ed = edits_create();
	struct terrain *tr = terrain_create(ed);
	s.pl = pipeline_create(&s.g, &s.p, terrain_field(tr), err, sizeof(err));
	s.r = s.pl ? renderer_create(s.w, s.h, s.p.antialias, err, sizeof(err)) : NULL;
	if (!s.r) {
		fprintf(stderr, "bench: %s\n", err);
		return 1;
	}
	struct v4l2_out *paced = NULL, *every = NULL;
	struct file_out fo = { .fd = -1 };
	if (open_outputs(&o, &s, &fo, &paced, &every) < 0)
		return 1;
	printf("scene: volume, grid %d, 640x480; %s\n", s.p.grid, o.quick ? "quick" : "full");
	if (measure(&s, &o, paced, every) < 0)
		return 1;
	struct v4l2_stats st;
	v4l2_out_stats(paced, &st);
	printf("paced output: %lu frames written, %lu dropped (read-back busy)%s\n", st.written, st.dropped_busy,
	       fo.errors ? ", WRITE ERRORS" : "");
	if (every) {
		v4l2_out_stats(every, &st);
		printf("every-frame output: %lu frames written, %lu dropped (read-back busy)\n", st.written,
		       st.dropped_busy);
	}
	v4l2_out_close(paced);
	v4l2_out_close(every);
	if (fo.fd >= 0)
		close(fo.fd);
	renderer_destroy(s.r);
	pipeline_destroy(s.pl);
	terrain_destroy(tr);
	edits_destroy(ed);
	platform_close(plat);
	return 0;
}
