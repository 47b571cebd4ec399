/* isoterra — the app folder's door: everything the program, the tests and
 * the benchmarks use. */
#ifndef ISOTERRA_APP_H
#define ISOTERRA_APP_H

#include "log.h"
#include "params.h"
#include "cli.h"
#include "mesh.h"
#include "grid.h"
#include "image.h"
#include "ply.h"
#include "noise.h"
#include "density_ref.h"
#include "curves.h"
#include "edits.h"
#include "mc.h"
#include "gpu.h"
#include "pipeline.h"
#include "render.h"
#include "platform.h"
#include "controls.h"
#include "run.h"

#endif
