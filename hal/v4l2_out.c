/* isoterra — V4L2 video output (see v4l2_out.h).
 *
 * Device: open(O_RDWR | O_NONBLOCK) -> VIDIOC_QUERYCAP (V4L2_CAP_VIDEO_OUTPUT)
 * -> VIDIOC_S_FMT / G_FMT with the requested format, or the first of our
 * formats the device takes (the device may change the size: the conversion
 * scales) -> write() one frame per call, or VIDIOC_REQBUFS/QUERYBUF/mmap,
 * QBUF/DQBUF and STREAMON.  Non-blocking: a full queue drops the frame.
 * Busy / refused / vanished devices are reported once and retried every
 * RETRY_S seconds; rendering never stops for them. */
#include "v4l2_out.h"

#include <errno.h>
#include <stdarg.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#define RETRY_S 2.0
#define NBUF 4
#define NSLOTS 3

struct mbuf {
	void *ptr;
	size_t len;
	bool queued;
};

struct v4l2_out {
	/* configuration */
	char path[HAL_NAME_MAX];
	int want_fmt;          /* -1 auto, else enum conv_fmt */
	enum conv_matrix matrix;
	enum hal_v4l2_io io;
	int width, height;     /* requested (the render size) */
	double fps;
	v4l2_bytes_fn deliver; /* bytes mode when set or when path is empty */
	void *user;
	bool bytes_mode;
	struct hal_gpu gpu;
	struct hal_log log;
	/* device state */
	int fd;
	bool use_mmap, streaming, gave_up;
	bool worked; /* it took our frames once: a refusal later may be a device coming back unconfigured */
	struct mbuf bufs[NBUF];
	int nbufs;
	char problem[256];     /* the last reported problem (report once) */
	uint64_t next_try;
	/* conversion and pacing */
	struct frame_format f;
	struct gpu_conv *conv;
	bool conv_stale;       /* the format changed: new converter needed */
	uint64_t next_due;
	struct v4l2_stats st;
};

static int xioctl(int fd, unsigned long req, void *arg)
{
	int r;
	do
		r = ioctl(fd, req, arg);
	while (r < 0 && errno == EINTR);
	return r;
}

static void report(struct v4l2_out *v, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void report(struct v4l2_out *v, const char *fmt, ...)
{
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	if (strcmp(msg, v->problem)) /* once per distinct problem */
		hal_logf(&v->log, HAL_WARN, "v4l2: %s: %s", v->path, msg);
	snprintf(v->problem, sizeof(v->problem), "%s", msg);
}

static void dev_close(struct v4l2_out *v)
{
	if (v->fd < 0)
		return;
	if (v->streaming) {
		int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
		xioctl(v->fd, VIDIOC_STREAMOFF, &type);
	}
	for (int i = 0; i < v->nbufs; i++)
		if (v->bufs[i].ptr)
			munmap(v->bufs[i].ptr, v->bufs[i].len);
	if (v->nbufs) {
		struct v4l2_requestbuffers rb = { .count = 0, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP };
		xioctl(v->fd, VIDIOC_REQBUFS, &rb);
	}
	memset(v->bufs, 0, sizeof(v->bufs));
	v->nbufs = 0;
	v->streaming = false;
	close(v->fd);
	v->fd = -1;
}

static void offered(int fd, char *buf, size_t len)
{
	buf[0] = 0;
	struct v4l2_fmtdesc d = { .type = V4L2_BUF_TYPE_VIDEO_OUTPUT };
	for (d.index = 0; xioctl(fd, VIDIOC_ENUM_FMT, &d) == 0 && d.index < 64; d.index++) {
		size_t n = strlen(buf);
		snprintf(buf + n, len - n, "%s%.4s", n ? " " : "", (const char *)&d.pixelformat);
	}
	if (!buf[0])
		snprintf(buf, len, "nothing");
}

/* Tries one format; 1 accepted (v->f filled), 0 refused, -1 busy/error. */
static int try_format(struct v4l2_out *v, enum conv_fmt cf)
{
	struct v4l2_format fmt = { .type = V4L2_BUF_TYPE_VIDEO_OUTPUT };
	if (xioctl(v->fd, VIDIOC_G_FMT, &fmt) < 0) {
		report(v, "VIDIOC_G_FMT: %s", strerror(errno));
		return -1;
	}
	struct v4l2_pix_format *pix = &fmt.fmt.pix;
	uint32_t bpl, size;
	conv_fmt_tight(cf, v->width, v->height, &bpl, &size);
	pix->width = (uint32_t)v->width;
	pix->height = (uint32_t)v->height;
	pix->pixelformat = conv_fmt_fourcc(cf);
	pix->field = V4L2_FIELD_NONE;
	pix->bytesperline = bpl;
	pix->sizeimage = size;
	if (conv_fmt_is_yuv(cf)) {
		pix->colorspace = v->matrix == CM_BT709 ? V4L2_COLORSPACE_REC709 : V4L2_COLORSPACE_SMPTE170M;
		pix->ycbcr_enc = v->matrix == CM_BT709 ? V4L2_YCBCR_ENC_709 : V4L2_YCBCR_ENC_601;
		pix->quantization = V4L2_QUANTIZATION_LIM_RANGE;
	} else {
		pix->colorspace = V4L2_COLORSPACE_SRGB;
		pix->ycbcr_enc = V4L2_YCBCR_ENC_DEFAULT;
		pix->quantization = V4L2_QUANTIZATION_FULL_RANGE;
	}
	pix->xfer_func = V4L2_XFER_FUNC_DEFAULT;
	if (xioctl(v->fd, VIDIOC_S_FMT, &fmt) < 0) {
		if (errno == EBUSY) {
			report(v, "device is busy (another program is using it)");
			return -1;
		}
		return 0;
	}
	if (xioctl(v->fd, VIDIOC_G_FMT, &fmt) < 0) {
		report(v, "VIDIOC_G_FMT: %s", strerror(errno));
		return -1;
	}
	int got = conv_fmt_from_fourcc(pix->pixelformat);
	if (got < 0 || (v->want_fmt >= 0 && got != v->want_fmt) || (v->want_fmt < 0 && got != (int)cf))
		return 0;
	if (pix->field != V4L2_FIELD_NONE && pix->field != V4L2_FIELD_ANY) {
		report(v, "device wants interlaced fields (%u); only progressive frames are supported", pix->field);
		return 0;
	}
	if (pix->width < 2 || pix->height < 2 || pix->sizeimage < conv_fmt_min_size(got, (int)pix->height, pix->bytesperline)) {
		report(v, "device gave an unusable format (%ux%u, %u bytes per line, %u bytes)", pix->width, pix->height,
		       pix->bytesperline, pix->sizeimage);
		return 0;
	}
	v->f = (struct frame_format){ .fmt = got, .width = (int)pix->width, .height = (int)pix->height,
				      .bytesperline = pix->bytesperline, .sizeimage = pix->sizeimage, .matrix = v->matrix };
	return 1;
}

/* Opens the device and checks what it is; false when it cannot take our
 * frames.  first: at start-up, where a device of the wrong kind is a
 * configuration error (err). */
static bool dev_query(struct v4l2_out *v, bool first, struct v4l2_capability *cap, char *err, size_t errlen)
{
	v->fd = open(v->path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
	if (v->fd < 0) {
		report(v, "cannot open: %s; no video output, retrying every %g s", strerror(errno), RETRY_S);
		return false;
	}
	memset(cap, 0, sizeof(*cap));
	if (xioctl(v->fd, VIDIOC_QUERYCAP, cap) < 0) {
		if (first) {
			snprintf(err, errlen, "--v4l2 %s is not a V4L2 device (VIDIOC_QUERYCAP: %s)", v->path, strerror(errno));
			v->gave_up = true;
		} else {
			report(v, "VIDIOC_QUERYCAP: %s", strerror(errno));
		}
		dev_close(v);
		return false;
	}
	uint32_t caps = cap->capabilities & V4L2_CAP_DEVICE_CAPS ? cap->device_caps : cap->capabilities;
	if (!(caps & V4L2_CAP_VIDEO_OUTPUT)) {
		snprintf(err, errlen, "--v4l2 %s (%.32s, %.32s) is not a video output device%s", v->path,
			 (const char *)cap->card, (const char *)cap->driver,
			 caps & V4L2_CAP_VIDEO_OUTPUT_MPLANE ? " (only multi-planar output, which is not supported)" : "");
		if (!first)
			report(v, "%s", err);
		v->gave_up = true;
		dev_close(v);
		return false;
	}
	bool can_stream = caps & V4L2_CAP_STREAMING, can_write = caps & V4L2_CAP_READWRITE;
	v->use_mmap = v->io == HAL_V4L2_IO_MMAP || (v->io == HAL_V4L2_IO_AUTO && can_stream);
	if ((v->use_mmap && !can_stream) || (!v->use_mmap && !can_write)) {
		snprintf(err, errlen, "--v4l2 %s does not support %s I/O", v->path, v->use_mmap ? "mmap streaming" : "write()");
		v->gave_up = true;
		dev_close(v);
		return false;
	}
	return true;
}

/* The requested format, or the first of ours the device takes (v->f). */
static bool dev_negotiate(struct v4l2_out *v)
{
	static const enum conv_fmt order[] = { CF_YUYV, CF_NV12, CF_UYVY, CF_YU12, CF_NV21, CF_RGB24, CF_BGR24 };
	int r = 0;
	if (v->want_fmt >= 0) {
		r = try_format(v, (enum conv_fmt)v->want_fmt);
	} else {
		for (size_t i = 0; i < sizeof(order) / sizeof(order[0]) && r == 0; i++)
			r = try_format(v, order[i]);
	}
	if (r > 0)
		return true;
	if (r == 0) {
		char list[160];
		offered(v->fd, list, sizeof(list));
		/* at start a refusal will not change by retrying; a device that
		 * took our frames before and refuses them after coming back may
		 * still be being set up (by udev, by its own tool): retried */
		const char *then = v->worked ? ", retrying" : "";
		if (v->want_fmt >= 0)
			report(v, "device refuses %s at %dx%d (it offers: %s); no video output%s", conv_fmt_name(v->want_fmt),
			       v->width, v->height, list, then);
		else
			report(v, "device takes none of YUYV NV12 UYVY YU12 NV21 RGB24 BGR24 (it offers: %s); no video output%s",
			       list, then);
		v->gave_up = !v->worked;
	}
	dev_close(v);
	return false;
}

/* mmap streaming: the device's buffers, mapped. */
static bool dev_map_buffers(struct v4l2_out *v)
{
	struct v4l2_requestbuffers rb = { .count = NBUF, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP };
	if (xioctl(v->fd, VIDIOC_REQBUFS, &rb) < 0 || rb.count < 1) {
		report(v, "VIDIOC_REQBUFS: %s", rb.count < 1 ? "no buffers" : errno == EBUSY ? "device is busy" : strerror(errno));
		dev_close(v);
		return false;
	}
	v->nbufs = (int)(rb.count > NBUF ? NBUF : rb.count);
	for (int i = 0; i < v->nbufs; i++) {
		struct v4l2_buffer b = { .index = (uint32_t)i, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP };
		if (xioctl(v->fd, VIDIOC_QUERYBUF, &b) < 0) {
			report(v, "VIDIOC_QUERYBUF: %s", strerror(errno));
			dev_close(v);
			return false;
		}
		void *ptr = mmap(NULL, b.length, PROT_READ | PROT_WRITE, MAP_SHARED, v->fd, b.m.offset);
		if (ptr == MAP_FAILED) {
			report(v, "mmap: %s", strerror(errno));
			dev_close(v);
			return false;
		}
		v->bufs[i] = (struct mbuf){ .ptr = ptr, .len = b.length };
	}
	return true;
}

/* Opens and configures the device; true when frames can go out.  first:
 * at start-up, where a device of the wrong kind is a configuration error. */
static bool dev_open(struct v4l2_out *v, bool first, char *err, size_t errlen)
{
	v->next_try = hal_now_ns() + (uint64_t)(RETRY_S * 1e9);
	struct v4l2_capability cap;
	if (!dev_query(v, first, &cap, err, errlen) || !dev_negotiate(v))
		return false;
	if (v->fps > 0) {
		struct v4l2_streamparm sp = { .type = V4L2_BUF_TYPE_VIDEO_OUTPUT };
		sp.parm.output.timeperframe.numerator = 1000;
		sp.parm.output.timeperframe.denominator = (uint32_t)(v->fps * 1000 + 0.5);
		xioctl(v->fd, VIDIOC_S_PARM, &sp); /* optional: many devices ignore it */
	}
	if (v->use_mmap && !dev_map_buffers(v))
		return false;
	/* the converter for the negotiated format is made at the next frame */
	v->conv_stale = true;
	hal_logf(&v->log, HAL_INFO, "v4l2: %s (%.32s): %dx%d %s, %u bytes per frame, %s, %s%s", v->path,
		 (const char *)cap.card, v->f.width, v->f.height, conv_fmt_name(v->f.fmt), v->f.sizeimage,
		 v->use_mmap ? "mmap streaming" : "write()",
		 conv_fmt_is_yuv(v->f.fmt) ? (v->matrix == CM_BT709 ? "BT.709 limited" : "BT.601 limited") : "sRGB",
		 v->problem[0] ? " (recovered)" : "");
	v->problem[0] = 0;
	v->worked = true;
	return true;
}

static void dev_failed(struct v4l2_out *v, const char *what, int e)
{
	report(v, "%s: %s; video output stopped, retrying every %g s", what, strerror(e), RETRY_S);
	dev_close(v);
	v->next_try = hal_now_ns() + (uint64_t)(RETRY_S * 1e9);
}

/* write(): one frame per call; a full queue drops it. */
static void put_write(struct v4l2_out *v, const uint8_t *bytes, size_t size)
{
	ssize_t n = write(v->fd, bytes, size);
	if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
		v->st.dropped_busy++;
		return;
	}
	if (n < 0) {
		dev_failed(v, "write", errno);
		v->st.dropped_off++;
		return;
	}
	if ((size_t)n != size)
		hal_logf(&v->log, HAL_DEBUG, "v4l2: short write %zd of %zu bytes", n, size);
	v->st.written++;
}

/* mmap streaming: a buffer never queued, else one the device has finished
 * with; -1 when none is free (dropped) or the device failed. */
static int free_buffer(struct v4l2_out *v)
{
	for (int i = 0; i < v->nbufs; i++)
		if (!v->bufs[i].queued)
			return i;
	struct v4l2_buffer b = { .type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP };
	if (xioctl(v->fd, VIDIOC_DQBUF, &b) < 0) {
		if (errno == EAGAIN) {
			v->st.dropped_busy++;
			return -1;
		}
		dev_failed(v, "VIDIOC_DQBUF", errno);
		v->st.dropped_off++;
		return -1;
	}
	int idx = (int)b.index;
	if (idx < 0 || idx >= v->nbufs) {
		dev_failed(v, "VIDIOC_DQBUF returned a bad index", EIO);
		return -1;
	}
	v->bufs[idx].queued = false;
	return idx;
}

static void put_mmap(struct v4l2_out *v, const uint8_t *bytes, size_t size)
{
	int idx = free_buffer(v);
	if (idx < 0)
		return;
	struct mbuf *mb = &v->bufs[idx];
	size_t n = size < mb->len ? size : mb->len;
	memcpy(mb->ptr, bytes, n);
	struct v4l2_buffer b = { .index = (uint32_t)idx, .type = V4L2_BUF_TYPE_VIDEO_OUTPUT, .memory = V4L2_MEMORY_MMAP,
				 .bytesused = (uint32_t)n, .field = V4L2_FIELD_NONE };
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	b.timestamp.tv_sec = ts.tv_sec;
	b.timestamp.tv_usec = ts.tv_nsec / 1000;
	if (xioctl(v->fd, VIDIOC_QBUF, &b) < 0) {
		dev_failed(v, "VIDIOC_QBUF", errno);
		v->st.dropped_off++;
		return;
	}
	mb->queued = true;
	if (!v->streaming) {
		int type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
		if (xioctl(v->fd, VIDIOC_STREAMON, &type) < 0) {
			dev_failed(v, "VIDIOC_STREAMON", errno);
			return;
		}
		v->streaming = true;
	}
	v->st.written++;
}

/* Hands one converted frame to the device (or the bytes callback). */
static void put_frame(struct v4l2_out *v, const uint8_t *bytes)
{
	size_t size = v->f.sizeimage;
	if (v->bytes_mode) {
		if (v->deliver)
			v->deliver(v->user, bytes, size);
		v->st.written++;
	} else if (v->fd < 0) {
		v->st.dropped_off++;
	} else if (!v->use_mmap) {
		put_write(v, bytes, size);
	} else {
		put_mmap(v, bytes, size);
	}
}

/* Hands every finished read-back to the device (wait: all of them). */
static int harvest(struct v4l2_out *v, bool wait)
{
	if (!v->conv)
		return 0;
	const uint8_t *bytes;
	while ((bytes = gpu_conv_ready(v->conv, wait)) != NULL) {
		put_frame(v, bytes);
		if (gpu_conv_release(v->conv) < 0)
			return -1;
	}
	return 0;
}

static struct v4l2_out *alloc_out(double fps)
{
	struct v4l2_out *v = calloc(1, sizeof(*v));
	if (v) {
		v->fd = -1;
		v->fps = fps;
	}
	return v;
}

struct v4l2_out *v4l2_out_open(const struct hal_v4l2_config *cfg, char *err, size_t errlen)
{
	err[0] = 0;
	if (!cfg->device || !cfg->device[0])
		return NULL;
	struct v4l2_out *v = alloc_out(cfg->fps);
	if (!v) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	snprintf(v->path, sizeof(v->path), "%s", cfg->device);
	v->want_fmt = cfg->format;
	v->matrix = cfg->matrix;
	v->io = cfg->io;
	v->width = cfg->width;
	v->height = cfg->height;
	v->gpu = cfg->gpu;
	v->log = cfg->log;
	if (!dev_open(v, true, err, errlen) && err[0]) {
		v4l2_out_close(v);
		return NULL;
	}
	return v;
}

struct v4l2_out *v4l2_out_open_bytes(const struct frame_format *f, double fps, v4l2_bytes_fn deliver, void *user,
				    const struct hal_gpu *gpu, char *err, size_t errlen)
{
	struct v4l2_out *v = alloc_out(fps);
	if (!v) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	snprintf(v->path, sizeof(v->path), "(bytes)");
	v->bytes_mode = true;
	v->deliver = deliver;
	v->user = user;
	v->f = *f;
	if (gpu) {
		v->gpu = *gpu;
		v->log = gpu->log;
	}
	v->conv = gpu_conv_create(f, NSLOTS, gpu, err, errlen);
	if (!v->conv) {
		free(v);
		return NULL;
	}
	return v;
}

static void sleep_until(uint64_t t)
{
	struct timespec ts = { .tv_sec = (time_t)(t / 1000000000ull), .tv_nsec = (long)(t % 1000000000ull) };
	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
		;
}

int v4l2_out_frame(struct v4l2_out *v, GLuint fbo, int w, int h)
{
	if (!v)
		return 0;
	uint64_t now = hal_now_ns();
	if (!v->bytes_mode && v->fd < 0) {
		if (v->gave_up || now < v->next_try) {
			v->st.dropped_off++;
			return 0;
		}
		char e[256] = "";
		if (!dev_open(v, false, e, sizeof(e))) {
			v->st.dropped_off++;
			return 0;
		}
	}
	if (harvest(v, false) < 0)
		return -1;
	if (v->conv_stale || !v->conv) {
		char e[256];
		gpu_conv_destroy(v->conv);
		v->conv_stale = false;
		v->conv = gpu_conv_create(&v->f, NSLOTS, &v->gpu, e, sizeof(e));
		if (!v->conv) {
			hal_logf(&v->log, HAL_ERROR, "v4l2: %s", e);
			return -1;
		}
	}
	if (v->fps > 0) { /* pacing: one frame every 1/fps s */
		uint64_t period = (uint64_t)(1e9 / v->fps);
		if (!v->next_due || now > v->next_due + period)
			v->next_due = now; /* start, or fell behind by more than a frame */
		else if (now < v->next_due)
			sleep_until(v->next_due);
		v->next_due += period;
	}
	int r = gpu_conv_submit(v->conv, fbo, w, h);
	if (r < 0)
		return -1;
	if (r == 0)
		v->st.dropped_busy++;
	else
		v->st.submitted++;
	return 0;
}

void v4l2_out_close(struct v4l2_out *v)
{
	if (!v)
		return;
	harvest(v, true);
	if (v->st.submitted)
		hal_logf(&v->log, HAL_INFO, "v4l2: %s: %lu frames converted, %lu written, %lu dropped (busy), %lu not sent (no device)", v->path,
			 v->st.submitted, v->st.written, v->st.dropped_busy, v->st.dropped_off);
	gpu_conv_destroy(v->conv);
	dev_close(v);
	free(v);
}

void v4l2_out_stats(const struct v4l2_out *v, struct v4l2_stats *st)
{
	*st = v->st;
}

const struct frame_format *v4l2_out_format(const struct v4l2_out *v)
{
	return &v->f;
}
