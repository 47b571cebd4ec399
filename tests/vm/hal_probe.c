/* isoterra — helper of the VM tests (tests/vm/).
 *
 *   hal_probe compare CAPTURE.raw REF.png FORMAT MATRIX MIN_PSNR [W H]
 *       the last whole frame of a capture (YUYV, UYVY or NV12) back to RGB
 *       (CPU, limited range, BT.601 or BT.709: an implementation independent
 *       of the app's GPU shader) against the reference PNG: prints the PSNR,
 *       exit 1 below MIN_PSNR.  W H: the capture's size when the app scaled
 *       its frame up to the device's (an integer factor): box-filtered down.
 *   hal_probe keys
 *       a virtual keyboard through /dev/uinput (the kernel's evdev, for the
 *       app's --keyboard evdev): prints its /dev/input/eventN, then presses
 *       and releases one key per line read from stdin (right, left, up,
 *       down, p, r, s, n, q); ends at EOF.
 *   hal_probe pad
 *       a virtual gamepad through /dev/uinput (two s16 sticks with a flat,
 *       0..255 triggers, a hat D-pad, the gamepad buttons): prints its
 *       /dev/input/eventN, then per line read from stdin: "AXIS VALUE"
 *       (x y rx ry z rz hat0x hat0y: set and reported), "press BUTTON"
 *       (south east north west tl tr select start mode: pressed, released)
 *       or "hat right|left|up|down" (the D-pad pushed and let go); ends
 *       at EOF (the device goes away).
 *   hal_probe convert IN.png OUT.raw [--v4l2-format F --v4l2-matrix M]
 *       (GL) the app's GPU conversion and PBO read-back of an image, to
 *       produce captures by hand when investigating.
 */
#include "app.h"
#include "hal_config.h"
#include "convert.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <linux/uinput.h>
#include <math.h>
#include <sys/ioctl.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>

static int parse(int argc, char **argv, struct params *p)
{
	char err[512];
	enum cli_result r = cli_parse(argc, argv, p, err, sizeof(err));
	if (r == CLI_ERROR) {
		log_error("%s", err);
		return -1;
	}
	return r == CLI_RUN ? 0 : -1;
}

static uint8_t *read_file(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	uint8_t *buf = NULL;
	if (fseek(f, 0, SEEK_END) == 0) {
		long n = ftell(f);
		if (n > 0 && fseek(f, 0, SEEK_SET) == 0 && (buf = malloc((size_t)n)) != NULL) {
			if (fread(buf, 1, (size_t)n, f) != (size_t)n) {
				free(buf);
				buf = NULL;
			} else {
				*len = (size_t)n;
			}
		}
	}
	fclose(f);
	return buf;
}

static int convert(int argc, char **argv)
{
	struct params p;
	const char *in = argv[1], *out = argv[2];
	argv[2] = argv[0];
	if (parse(argc - 2, argv + 2, &p) < 0)
		return 2;
	char err[512];
	struct image img = { 0 };
	if (image_read_png(&img, in, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return 2;
	}
	struct platform_options po = { .name = "surfaceless", .width = 64, .height = 64 };
	struct platform *plat = platform_open(&po, err, sizeof(err));
	struct gpu_caps caps;
	if (!plat || gpu_init(&caps, false, err, sizeof(err)) < 0) {
		log_error("%s", err);
		return 1;
	}
	int w = img.width, h = img.height;
	uint8_t *flip = malloc((size_t)w * h * 4);
	for (int y = 0; y < h; y++)
		memcpy(flip + (size_t)(h - 1 - y) * w * 4, img.rgba + (size_t)y * w * 4, (size_t)w * 4);
	GLuint tex, fbo;
	glGenTextures(1, &tex);
	glBindTexture(GL_TEXTURE_2D, tex);
	glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, w, h);
	glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
	glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, flip);
	glGenFramebuffers(1, &fbo);
	glBindFramebuffer(GL_FRAMEBUFFER, fbo);
	glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
	struct hal_v4l2_config vc; /* --v4l2-format, --v4l2-matrix as the app maps them */
	hal_config_v4l2(&p, w, h, &vc);
	struct frame_format f = { .fmt = vc.format >= 0 ? (enum conv_fmt)vc.format : CF_YUYV, .width = w, .height = h,
				  .matrix = vc.matrix };
	conv_fmt_tight(f.fmt, w, h, &f.bytesperline, &f.sizeimage);
	struct gpu_conv *c = gpu_conv_create(&f, 2, hal_config_gpu(), err, sizeof(err));
	int rc = 1;
	const uint8_t *bytes = NULL;
	if (c && gpu_conv_submit(c, fbo, w, h) == 1 && (bytes = gpu_conv_ready(c, true)) != NULL) {
		char tmp[1100];
		snprintf(tmp, sizeof(tmp), "%s.tmp", out);
		FILE *o = fopen(tmp, "wb");
		if (o && fwrite(bytes, 1, f.sizeimage, o) == f.sizeimage && fclose(o) == 0 && rename(tmp, out) == 0) {
			rc = 0;
			printf("%s: %dx%d %s, %u bytes\n", out, w, h, conv_fmt_name(f.fmt), f.sizeimage);
		} else {
			log_error("cannot write %s", out);
		}
		gpu_conv_release(c);
	} else {
		log_error("conversion failed: %s", err);
	}
	gpu_conv_destroy(c);
	free(flip);
	image_free(&img);
	platform_close(plat);
	return rc;
}

static int compare(int argc, char **argv)
{
	char err[512];
	struct image ref = { 0 };
	if (image_read_png(&ref, argv[2], err, sizeof(err)) < 0) {
		log_error("%s", err);
		return 2;
	}
	const char *fmt = argv[3];
	double kr = 0.299, kb = 0.114, min_psnr = atof(argv[5]);
	if (!strcmp(argv[4], "bt709")) {
		kr = 0.2126;
		kb = 0.0722;
	}
	/* the capture's size (default: the reference's); an integer multiple
	 * of the reference's is box-filtered down to it (the app scales its
	 * frame to the device's size) */
	int w = argc >= 8 ? atoi(argv[6]) : ref.width, h = argc >= 8 ? atoi(argv[7]) : ref.height;
	int fx = w / ref.width, fy = h / ref.height;
	if (w < 2 || h < 2 || fx < 1 || fy < 1 || fx * ref.width != w || fy * ref.height != h) {
		log_error("compare: capture %dx%d is no integer multiple of the reference %dx%d", w, h, ref.width,
			  ref.height);
		return 2;
	}
	bool nv12 = !strcmp(fmt, "NV12"), uyvy = !strcmp(fmt, "UYVY");
	if (!nv12 && !uyvy && strcmp(fmt, "YUYV")) {
		log_error("compare: format %s not supported (YUYV, UYVY, NV12)", fmt);
		return 2;
	}
	size_t fsize = nv12 ? (size_t)w * h * 3 / 2 : (size_t)w * h * 2, len = 0;
	uint8_t *cap = read_file(argv[1], &len);
	if (!cap || len < fsize) {
		log_error("compare: %s: %zu bytes, less than one %dx%d %s frame", argv[1], len, w, h, fmt);
		return 1;
	}
	const uint8_t *fr = cap + (len / fsize - 1) * fsize; /* the last whole frame */
	struct image got = { w, h, malloc((size_t)w * h * 4) };
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double Y, U, V;
			if (nv12) {
				Y = fr[(size_t)y * w + x];
				const uint8_t *c = fr + (size_t)w * h + (size_t)(y / 2) * w + (x / 2) * 2;
				U = c[0];
				V = c[1];
			} else {
				const uint8_t *q = fr + (size_t)y * w * 2 + (x / 2) * 4;
				Y = uyvy ? q[1 + 2 * (x % 2)] : q[2 * (x % 2)];
				U = uyvy ? q[0] : q[1];
				V = uyvy ? q[2] : q[3];
			}
			double yl = (Y - 16) / 219, cb = (U - 128) / 224, cr = (V - 128) / 224;
			double r = yl + 2 * (1 - kr) * cr, b = yl + 2 * (1 - kb) * cb;
			double g = (yl - kr * r - kb * b) / (1 - kr - kb);
			double rgb[3] = { r, g, b };
			for (int k = 0; k < 3; k++) {
				double v = floor(rgb[k] * 255 + 0.5);
				got.rgba[4 * ((size_t)y * w + x) + k] = (uint8_t)(v < 0 ? 0 : v > 255 ? 255 : v);
			}
			got.rgba[4 * ((size_t)y * w + x) + 3] = 255;
		}
	if (fx > 1 || fy > 1) {
		struct image small = { ref.width, ref.height, malloc((size_t)ref.width * ref.height * 4) };
		for (int y = 0; y < ref.height; y++)
			for (int x = 0; x < ref.width; x++)
				for (int k = 0; k < 4; k++) {
					int sum = 0;
					for (int j = 0; j < fy; j++)
						for (int i = 0; i < fx; i++)
							sum += got.rgba[4 * ((size_t)(y * fy + j) * w + (size_t)(x * fx + i)) + k];
					small.rgba[4 * ((size_t)y * ref.width + x) + k] = (uint8_t)((sum + fx * fy / 2) / (fx * fy));
				}
		image_free(&got);
		got = small;
	}
	struct image_diff d;
	image_compare(&got, &ref, 48, &d);
	printf("capture vs rendered frame (%s, %dx%d, %zu frames captured): PSNR %.2f dB, mean abs %.2f, max %d\n", fmt, w,
	       h, len / fsize, d.psnr, d.mean_abs, d.max_abs);
	if (getenv("HAL_PROBE_SAVE"))
		image_write_png(&got, getenv("HAL_PROBE_SAVE"), err, sizeof(err));
	free(cap);
	image_free(&got);
	image_free(&ref);
	return d.psnr >= min_psnr ? 0 : 1;
}

static const struct {
	const char *name;
	int code;
} key_names[] = { { "right", KEY_RIGHT }, { "left", KEY_LEFT }, { "up", KEY_UP }, { "down", KEY_DOWN },
		  { "p", KEY_P },	  { "r", KEY_R },	{ "s", KEY_S },	  { "n", KEY_N },
		  { "q", KEY_Q } };

static int emit(int fd, int type, int code, int value)
{
	struct input_event ev;
	memset(&ev, 0, sizeof(ev));
	ev.type = (unsigned short)type;
	ev.code = (unsigned short)code;
	ev.value = value;
	return write(fd, &ev, sizeof(ev)) == (ssize_t)sizeof(ev) ? 0 : -1;
}

static void event_node(int fd, char *path, size_t len)
{
	char sys[64] = "", dir[128];
	path[0] = 0;
	if (ioctl(fd, UI_GET_SYSNAME(sizeof(sys)), sys) < 0)
		return;
	snprintf(dir, sizeof(dir), "/sys/devices/virtual/input/%s", sys);
	DIR *d = opendir(dir);
	for (struct dirent *e; d && (e = readdir(d)) != NULL;)
		if (!strncmp(e->d_name, "event", 5))
			snprintf(path, len, "/dev/input/%s", e->d_name);
	if (d)
		closedir(d);
}

/* /dev/uinput opened for `what` (keys, pad): the fd, or -1 (said). */
static int uinput_open(const char *what)
{
	int fd = open("/dev/uinput", O_WRONLY | O_CLOEXEC);
	if (fd < 0)
		log_error("%s: /dev/uinput: %s", what, strerror(errno));
	return fd;
}

/* The device set up (ok: its bits were set) and created; its event node
 * into path.  0, or -1 (said; fd closed). */
static int uinput_start(int fd, const char *what, bool ok, const struct uinput_setup *us, char *path, size_t len)
{
	if (!(ok && ioctl(fd, UI_DEV_SETUP, us) == 0 && ioctl(fd, UI_DEV_CREATE) == 0)) {
		log_error("%s: setting up the uinput device failed: %s", what, strerror(errno));
		close(fd);
		return -1;
	}
	event_node(fd, path, len);
	if (!path[0]) {
		log_error("%s: no event node (is evdev loaded?)", what);
		ioctl(fd, UI_DEV_DESTROY);
		close(fd);
		return -1;
	}
	printf("%s\n", path);
	fflush(stdout);
	return 0;
}

static int keys(void)
{
	int fd = uinput_open("keys");
	if (fd < 0)
		return 1;
	struct uinput_setup us;
	memset(&us, 0, sizeof(us));
	us.id.bustype = BUS_VIRTUAL;
	snprintf(us.name, sizeof(us.name), "isoterra test keys");
	int ok = ioctl(fd, UI_SET_EVBIT, EV_KEY) == 0;
	for (size_t i = 0; i < sizeof(key_names) / sizeof(key_names[0]); i++)
		ok = ok && ioctl(fd, UI_SET_KEYBIT, key_names[i].code) == 0;
	char path[300];
	if (uinput_start(fd, "keys", ok, &us, path, sizeof(path)) < 0)
		return 1;
	char line[64];
	int rc = 0;
	while (fgets(line, sizeof(line), stdin)) {
		line[strcspn(line, "\r\n")] = 0;
		int code = -1;
		for (size_t i = 0; i < sizeof(key_names) / sizeof(key_names[0]); i++)
			if (!strcmp(line, key_names[i].name))
				code = key_names[i].code;
		if (code < 0) {
			log_error("keys: unknown key '%s'", line);
			rc = 1;
			continue;
		}
		if (emit(fd, EV_KEY, code, 1) < 0 || emit(fd, EV_SYN, SYN_REPORT, 0) < 0 || emit(fd, EV_KEY, code, 0) < 0 ||
		    emit(fd, EV_SYN, SYN_REPORT, 0) < 0) {
			log_error("keys: writing to /dev/uinput: %s", strerror(errno));
			rc = 1;
			break;
		}
	}
	ioctl(fd, UI_DEV_DESTROY);
	close(fd);
	return rc;
}

/* The event node of the uinput device just created on fd ("" none). */

static const struct {
	const char *name;
	int code, min, max, flat;
} pad_axes[] = {
	{ "x", ABS_X, -32768, 32767, 128 },   { "y", ABS_Y, -32768, 32767, 128 },  { "rx", ABS_RX, -32768, 32767, 128 },
	{ "ry", ABS_RY, -32768, 32767, 128 }, { "z", ABS_Z, 0, 255, 0 },	     { "rz", ABS_RZ, 0, 255, 0 },
	{ "hat0x", ABS_HAT0X, -1, 1, 0 },     { "hat0y", ABS_HAT0Y, -1, 1, 0 },
};
static const struct {
	const char *name;
	int code;
} pad_buttons[] = {
	{ "south", BTN_SOUTH }, { "east", BTN_EAST }, { "north", BTN_NORTH },   { "west", BTN_WEST },
	{ "tl", BTN_TL },	{ "tr", BTN_TR },     { "select", BTN_SELECT }, { "start", BTN_START },
	{ "mode", BTN_MODE },	{ "thumbl", BTN_THUMBL }, { "thumbr", BTN_THUMBR },
};

/* 0, or non-zero (a line not understood, a failed write) */
static int pad_line(int fd, const char *line)
{
	char a[32], b[32];
	int n = sscanf(line, "%31s %31s", a, b);
	if (n != 2)
		return -1;
	if (!strcmp(a, "press")) {
		for (size_t i = 0; i < sizeof(pad_buttons) / sizeof(pad_buttons[0]); i++)
			if (!strcmp(b, pad_buttons[i].name))
				return emit(fd, EV_KEY, pad_buttons[i].code, 1) || emit(fd, EV_SYN, SYN_REPORT, 0) ||
				       emit(fd, EV_KEY, pad_buttons[i].code, 0) || emit(fd, EV_SYN, SYN_REPORT, 0);
		return -1;
	}
	if (!strcmp(a, "hat")) {
		int code = !strcmp(b, "left") || !strcmp(b, "right") ? ABS_HAT0X : ABS_HAT0Y;
		int v = !strcmp(b, "right") || !strcmp(b, "down") ? 1 : -1;
		if (strcmp(b, "left") && strcmp(b, "right") && strcmp(b, "up") && strcmp(b, "down"))
			return -1;
		return emit(fd, EV_ABS, code, v) || emit(fd, EV_SYN, SYN_REPORT, 0) || emit(fd, EV_ABS, code, 0) ||
		       emit(fd, EV_SYN, SYN_REPORT, 0);
	}
	for (size_t i = 0; i < sizeof(pad_axes) / sizeof(pad_axes[0]); i++)
		if (!strcmp(a, pad_axes[i].name))
			return emit(fd, EV_ABS, pad_axes[i].code, atoi(b)) || emit(fd, EV_SYN, SYN_REPORT, 0);
	return -1;
}

static int pad(void)
{
	int fd = uinput_open("pad");
	if (fd < 0)
		return 1;
	struct uinput_setup us;
	memset(&us, 0, sizeof(us));
	us.id.bustype = BUS_VIRTUAL;
	us.id.vendor = 0x1209; /* pid.codes' test range */
	us.id.product = 0x0001;
	snprintf(us.name, sizeof(us.name), "isoterra test pad");
	int ok = ioctl(fd, UI_SET_EVBIT, EV_KEY) == 0 && ioctl(fd, UI_SET_EVBIT, EV_ABS) == 0;
	for (size_t i = 0; i < sizeof(pad_buttons) / sizeof(pad_buttons[0]); i++)
		ok = ok && ioctl(fd, UI_SET_KEYBIT, pad_buttons[i].code) == 0;
	for (size_t i = 0; i < sizeof(pad_axes) / sizeof(pad_axes[0]); i++) {
		struct uinput_abs_setup as;
		memset(&as, 0, sizeof(as));
		as.code = (unsigned short)pad_axes[i].code;
		as.absinfo.minimum = pad_axes[i].min;
		as.absinfo.maximum = pad_axes[i].max;
		as.absinfo.flat = pad_axes[i].flat;
		ok = ok && ioctl(fd, UI_SET_ABSBIT, pad_axes[i].code) == 0 && ioctl(fd, UI_ABS_SETUP, &as) == 0;
	}
	char path[300];
	if (uinput_start(fd, "pad", ok, &us, path, sizeof(path)) < 0)
		return 1;
	char line[64];
	int rc = 0;
	while (fgets(line, sizeof(line), stdin)) {
		line[strcspn(line, "\r\n")] = 0;
		if (pad_line(fd, line) != 0) {
			log_error("pad: '%s': %s", line, errno ? strerror(errno) : "not understood");
			rc = 1;
		}
		errno = 0;
	}
	ioctl(fd, UI_DEV_DESTROY);
	close(fd);
	return rc;
}

int main(int argc, char **argv)
{
	if (argc == 2 && !strcmp(argv[1], "keys"))
		return keys();
	if (argc == 2 && !strcmp(argv[1], "pad"))
		return pad();
	if (argc >= 4 && !strcmp(argv[1], "convert"))
		return convert(argc - 1, argv + 1);
	if ((argc == 7 || argc == 9) && !strcmp(argv[1], "compare"))
		return compare(argc - 1, argv + 1);
	fprintf(stderr, "usage: hal_probe keys|pad|convert|compare ... (see tests/vm/hal_probe.c)\n");
	return 2;
}
