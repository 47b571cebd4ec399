/* isoterra — app/core, the folder's door: what every other folder builds
 * on (logging, the clock, small helpers, atomic files, PNG through libpng,
 * meshes, grids, the service manager's notifications, the process's
 * signal flags).  Depends on nothing else of the program. */
#ifndef ISOTERRA_CORE_H
#define ISOTERRA_CORE_H

#include "util.h"
#include "log.h"
#include "clock.h"
#include "atomic_file.h"
#include "image.h"
#include "mesh.h"
#include "grid.h"
#include "notify.h"
#include "heap.h"
#include "signals.h"

#endif
