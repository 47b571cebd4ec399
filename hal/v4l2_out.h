/* isoterra — V4L2 video output of the rendered frames: format negotiation,
 * GPU conversion (convert.h), write() or mmap streaming, frame pacing. */
#ifndef ISOTERRA_V4L2_OUT_H
#define ISOTERRA_V4L2_OUT_H

#include <stddef.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "convert.h"
#include "hal.h"

struct v4l2_stats {
	unsigned long submitted;     /* frames converted on the GPU */
	unsigned long written;       /* frames handed to the device (or the bytes callback) */
	unsigned long dropped_busy;  /* no free read-back slot / device buffer */
	unsigned long dropped_off;   /* device absent or failed */
};

typedef void (*v4l2_bytes_fn)(void *user, const uint8_t *bytes, size_t size);

enum hal_v4l2_io { HAL_V4L2_IO_AUTO, HAL_V4L2_IO_WRITE, HAL_V4L2_IO_MMAP };

struct hal_v4l2_config {
	const char *device;       /* /dev/videoN (copied); "" or NULL: no output */
	int format;               /* enum conv_fmt, or -1: the first the device takes */
	enum conv_matrix matrix;  /* YCbCr formats: BT.601 or BT.709, limited range */
	enum hal_v4l2_io io;      /* auto: mmap streaming when the device streams */
	double fps;               /* pacing: one frame every 1/fps s; 0 = every frame */
	int width, height;        /* the rendered frames' size */
	struct hal_gpu gpu;       /* the conversion's program (convert.h) */
	struct hal_log log;
};

struct v4l2_out;
/* NULL with err[0] == 0 when no device is configured; NULL with err for bad
 * configuration (a device that is not a video output, an odd size); a
 * missing or busy device is reported and retried. */
struct v4l2_out *v4l2_out_open(const struct hal_v4l2_config *cfg, char *err, size_t errlen);
/* No device: the same conversion and read-back, frames go to deliver (NULL:
 * dropped after mapping). */
struct v4l2_out *v4l2_out_open_bytes(const struct frame_format *f, double fps, v4l2_bytes_fn deliver, void *user,
				    const struct hal_gpu *gpu, char *err, size_t errlen);
/* Per frame, after drawing into fbo (w x h): hands finished read-backs to
 * the device, waits for the next frame time when pacing, submits this
 * frame.  0, or -1 on a GL error. */
int v4l2_out_frame(struct v4l2_out *v, GLuint fbo, int w, int h);
/* Drains the read-backs in flight, stops streaming, closes. */
void v4l2_out_close(struct v4l2_out *v);
void v4l2_out_stats(const struct v4l2_out *v, struct v4l2_stats *st);
/* The negotiated format (valid while the device is open). */
const struct frame_format *v4l2_out_format(const struct v4l2_out *v);

#endif
