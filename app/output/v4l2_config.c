/* isoterra — the V4L2 output's configuration from the parameter table
 * (hal_config.h): format, colour matrix, I/O method, pacing. */
#include "hal_config.h"
#include "core.h"

static const int format_of[] = {
	[V4L2_FORMAT_AUTO] = -1,	  [V4L2_FORMAT_YUYV] = CF_YUYV, [V4L2_FORMAT_UYVY] = CF_UYVY,
	[V4L2_FORMAT_NV12] = CF_NV12,	  [V4L2_FORMAT_NV21] = CF_NV21, [V4L2_FORMAT_YU12] = CF_YU12,
	[V4L2_FORMAT_RGB24] = CF_RGB24, [V4L2_FORMAT_BGR24] = CF_BGR24,
};
_Static_assert(ARRAY_SIZE(format_of) == V4L2_FORMAT_COUNT, "every V4L2 format choice maps");
static const enum conv_matrix matrix_of[] = { [V4L2_MATRIX_BT601] = CM_BT601, [V4L2_MATRIX_BT709] = CM_BT709 };
_Static_assert(ARRAY_SIZE(matrix_of) == V4L2_MATRIX_COUNT, "every matrix choice maps");
static const enum hal_v4l2_io io_of[] = {
	[V4L2_IO_AUTO] = HAL_V4L2_IO_AUTO, [V4L2_IO_WRITE] = HAL_V4L2_IO_WRITE, [V4L2_IO_MMAP] = HAL_V4L2_IO_MMAP,
};
_Static_assert(ARRAY_SIZE(io_of) == V4L2_IO_COUNT, "every V4L2 I/O choice maps");

void hal_config_v4l2(const struct params *p, int width, int height, struct hal_v4l2_config *cfg)
{
	*cfg = (struct hal_v4l2_config){ .device = p->v4l2,
					 .format = format_of[hal_choice(p->v4l2_format, ARRAY_SIZE(format_of))],
					 .matrix = matrix_of[hal_choice(p->v4l2_matrix, ARRAY_SIZE(matrix_of))],
					 .io = io_of[hal_choice(p->v4l2_io, ARRAY_SIZE(io_of))],
					 .fps = p->v4l2_fps,
					 .width = width,
					 .height = height,
					 .gpu = *hal_config_gpu(),
					 .log = hal_config_log() };
}
