/* isoterra — app/output, the folder's door: where finished frames go,
 * behind one small interface (sink.h: PNG, PNG sequence, Y4M, V4L2, the
 * display, the mesh export), and the file writers (PLY, Y4M). */
#ifndef ISOTERRA_OUTPUT_H
#define ISOTERRA_OUTPUT_H

#include "sink.h"
#include "ply.h"
#include "y4m.h"

#endif
