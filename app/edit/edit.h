/* isoterra — app/edit, the folder's door: the terrain edits, i.e. curves
 * (roads, rivers, railways from GeoJSON/CSV, the Bézier pipeline, the
 * spatial hash) and heightmaps, held in an edit state (struct edits) with
 * its GL side and the CPU mirror of the carve.  Input to the terrain field
 * (app/terrain); knows nothing of extraction or drawing. */
#ifndef ISOTERRA_EDIT_H
#define ISOTERRA_EDIT_H

#include "curves.h"
#include "edits.h"

#endif
