/* isoterra — hal's configuration from the parameter table: the hal_*_config
 * structs hal/ takes (GPIO encoders and buttons, keys, gamepad, V4L2 output), hal's
 * messages routed to the log, and the V4L2 conversion's program built by
 * the shader loader.  hal/ knows nothing of parameters: this is where they
 * meet (hal_config.c, v4l2_config.c). */
#ifndef ISOTERRA_HAL_CONFIG_H
#define ISOTERRA_HAL_CONFIG_H

#include <stddef.h>

#include "params.h"
#include "hal.h"
#include "convert.h"
#include "v4l2_out.h"

/* Encoder e (0-based) reads the keys enc<e+1>_*, button b button<b+1>_*:
 * another encoder is HAL_ENCODERS plus its keys in params_hal.def.  Encoder
 * 1 selects the parameter, the others change it.  -1 with err when a key is
 * missing from the table. */
int hal_config_gpio(const struct params *p, struct hal_gpio_config *cfg, char *err, size_t errlen);
void hal_config_keys(const struct params *p, struct hal_keys_config *cfg);
/* The gamepad (gamepad = auto): its device, dead zones, curve, D-pad
 * repeat and map; a rescan every gpio_retry s where inotify cannot watch. */
void hal_config_gamepad(const struct params *p, struct hal_gamepad_config *cfg);
/* The V4L2 output of frames of width x height. */
void hal_config_v4l2(const struct params *p, int width, int height, struct hal_v4l2_config *cfg);
/* hal's messages into the log, as the program's own ("isoterra: warning: ..."). */
struct hal_log hal_config_log(void);
/* The V4L2 conversion's program (the shader loader) and units (abi.h). */
const struct hal_gpu *hal_config_gpu(void);

/* A choice's index v of a table of n, or 0 (the table's first) out of range. */
static inline int hal_choice(int v, size_t n)
{
	return v >= 0 && (size_t)v < n ? v : 0;
}

#endif
