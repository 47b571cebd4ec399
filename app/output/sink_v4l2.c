/* isoterra — the V4L2 sink: hal's video output (hal/v4l2_out.h) fed with
 * every finished frame.  Paced to p->v4l2_fps; a missing or vanished device
 * is reported and retried by hal, rendering goes on. */
#include "sink.h"
#include "hal_config.h"
#include "render.h"
#include "v4l2_out.h"

#include <stdio.h>
#include <stdlib.h>

struct v4l2_sink {
	struct sink base;
	struct v4l2_out *out;
};

static int v4l2_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	struct v4l2_sink *vs = (struct v4l2_sink *)s;
	GLuint fbo;
	int w, h;
	renderer_target(fr->r, &fbo, &w, &h);
	if (v4l2_out_frame(vs->out, fbo, w, h) < 0) {
		if (errlen)
			err[0] = 0; /* reported by hal */
		return -1;
	}
	return 0;
}

/* Drains the read-backs in flight and closes the device (GL). */
static int v4l2_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	struct v4l2_sink *vs = (struct v4l2_sink *)s;
	(void)end;
	(void)err;
	(void)errlen;
	v4l2_out_close(vs->out);
	vs->out = NULL;
	return 0;
}

static void v4l2_destroy(struct sink *s)
{
	free(s); /* the output needs GL to close: v4l2_finish did */
}

static const struct sink_ops v4l2_ops = { .frame = v4l2_frame, .finish = v4l2_finish, .destroy = v4l2_destroy };

struct sink *sink_v4l2_open(const struct params *p, int w, int h, char *err, size_t errlen)
{
	err[0] = 0;
	if (!p->v4l2[0])
		return NULL;
	struct hal_v4l2_config cfg;
	hal_config_v4l2(p, w, h, &cfg);
	struct v4l2_out *out = v4l2_out_open(&cfg, err, errlen);
	if (!out)
		return NULL;
	struct v4l2_sink *vs = calloc(1, sizeof(*vs));
	if (!vs) {
		v4l2_out_close(out);
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	vs->base.ops = &v4l2_ops;
	vs->out = out;
	return &vs->base;
}
