/* isoterra — the app folder's door: everything the program, the tests and
 * the benchmarks use. */
#ifndef ISOTERRA_APP_H
#define ISOTERRA_APP_H

/* one door per folder (docs/ARCHITECTURE.md), in the direction data flows */
#include "core.h"      /* app/core: log, clock, atomic files, PNG, meshes */
#include "params.h"    /* app/params: the parameter table, presets, config, CLI */
#include "gpu.h"       /* app/gpu: GL helpers, shader loader, the shader ABI */
#include "edit.h"      /* app/edit: curves, heightmaps, the edit state */
#include "terrain.h"   /* app/terrain: the density field (a field provider) */
#include "extract.h"   /* app/extract: the extraction engine */
#include "render.h"    /* app/render: renderer, surface texture, OSD */
#include "scene.h"     /* app/scene: volume and world, camera, autopilot */
#include "output.h"    /* app/output: sinks, PLY, Y4M, the display */
#include "platform.h"  /* platform/: EGL backends */
#include "controls.h"  /* hal/ events -> parameters, OSD, screenshots */
#include "run.h"       /* the frame loop */

#endif
