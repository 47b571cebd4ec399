/* isoterra — app/output, the folder's door: where finished frames go,
 * behind one small interface (sink.h: PNG, PNG sequence, Y4M, V4L2, the
 * display, the mesh export), the file writers (PLY, Y4M), and hal's
 * configuration from the parameters (hal_config.h: the V4L2 sink's, and
 * the GPIO and keys the controls and the probe open). */
#ifndef ISOTERRA_OUTPUT_H
#define ISOTERRA_OUTPUT_H

#include "sink.h"
#include "ply.h"
#include "y4m.h"
#include "hal_config.h"

#endif
