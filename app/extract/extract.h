/* isoterra — app/extract, the folder's door: the extraction engine (a field
 * provider's densities -> Marching Cubes classification -> HistoPyramid ->
 * shared vertices and indices -> indirect draw buffers; pipeline.h has the
 * five calls), the field seam (field.h) and the CPU Marching Cubes
 * reference (mc.h).  Knows nothing about what the field is. */
#ifndef ISOTERRA_EXTRACT_H
#define ISOTERRA_EXTRACT_H

#include "field.h"
#include "pipeline.h"
#include "mc.h"
#include "vertex.h"

#endif
