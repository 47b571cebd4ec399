/* isoterra — GPU colour conversion of rendered frames into a V4L2 byte
 * layout, read back asynchronously through a ring of pixel-pack buffers
 * (glReadPixels into GL_PIXEL_PACK_BUFFER + glFenceSync; a slot is mapped
 * only once its fence has signalled, polled with a zero timeout). */
#ifndef ISOTERRA_CONVERT_H
#define ISOTERRA_CONVERT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "hal.h"

/* invocations of the conversion's work group (shaders/v4l2_convert.comp
 * gets it, and the format names below, from convert.c's defines) */
#define CONV_WG_SIZE 64

enum conv_fmt { CF_YUYV, CF_UYVY, CF_NV12, CF_NV21, CF_YU12, CF_RGB24, CF_BGR24, CF_COUNT };
enum conv_matrix { CM_BT601, CM_BT709 };

/* The #defines shaders/v4l2_convert.comp is compiled with: CONV_WG_SIZE,
 * F_<name> for every format of enum conv_fmt (from convert.c's table, so
 * the shader holds no copy of the enum) and FMT, the one it converts to.
 * At most CONV_DEFINES_MAX bytes. */
#define CONV_DEFINES_MAX 512
void conv_shader_defines(enum conv_fmt fmt, char *buf, size_t len);
/* the same for YUYV (app/gpu/gl_limits.c's table of passes) */
void conv_shader_defines_yuyv(char *buf, size_t len);

struct frame_format {
	enum conv_fmt fmt;
	int width, height;
	uint32_t bytesperline, sizeimage;
	enum conv_matrix matrix;
};

/* Names as in V4L2 ("YUYV", "NV12", ...), the fourcc code, lookups. */
const char *conv_fmt_name(enum conv_fmt f);
uint32_t conv_fmt_fourcc(enum conv_fmt f);
int conv_fmt_from_fourcc(uint32_t fourcc); /* -1 if unsupported */
bool conv_fmt_is_yuv(enum conv_fmt f);
/* Tight bytesperline and sizeimage for a format and size. */
void conv_fmt_tight(enum conv_fmt f, int w, int h, uint32_t *bpl, uint32_t *size);
/* The bytes a layout needs at least with this bytesperline. */
uint32_t conv_fmt_min_size(enum conv_fmt f, int h, uint32_t bpl);
/* Kr, Kb of a matrix. */
void conv_matrix_k(enum conv_matrix m, double *kr, double *kb);

/* What the conversion needs from its host: its program, which the host's
 * shader loader compiles from `file` (v4l2_convert.comp) with the extra
 * #define lines in `defines` (0 with err on failure), and the texture and
 * image units that program's bindings name (the host knows them from the
 * same place the shader does). */
struct hal_gpu {
	GLuint (*compile)(void *user, const char *file, const char *defines, char *err, size_t errlen);
	void *user;
	GLuint tex_frame;   /* texture unit the frame is sampled from */
	GLuint img_out;     /* image unit the packed bytes are written to */
	struct hal_log log; /* GL errors */
};

struct gpu_conv;
/* nslots pixel buffers (2..4).  Needs a current GLES 3.1 context. */
struct gpu_conv *gpu_conv_create(const struct frame_format *f, int nslots, const struct hal_gpu *gpu, char *err,
				 size_t errlen);
void gpu_conv_destroy(struct gpu_conv *c);
/* Resolves framebuffer src (sw x sh, may be multisampled), converts it and
 * starts the read-back into a free slot.  1 submitted, 0 no free slot (the
 * frame is dropped), -1 GL error. */
int gpu_conv_submit(struct gpu_conv *c, GLuint src_fbo, int sw, int sh);
/* The oldest submitted frame if its read-back has finished (wait: block
 * until it has), mapped; NULL when none is ready.  Call gpu_conv_release
 * after using the bytes (sizeimage of them). */
const uint8_t *gpu_conv_ready(struct gpu_conv *c, bool wait);
int gpu_conv_release(struct gpu_conv *c);
int gpu_conv_pending(const struct gpu_conv *c);

#endif
