/* isoterra — the terrain as a field provider for the extraction engine
 * (app/extract/field.h): shaders/density.comp + density.glsl (noise, domain
 * warp, fractal, shapes, terraces; the analytic test fields the `field`
 * parameter selects; the heightmap and the curves' cut and fill).  It owns
 * the noise's GL objects (made on the first bind, again when the seed
 * changes) and borrows the edit state (curves, heightmap), whose files each
 * bind reloads when they changed; its program is specialized on that state
 * too (HAS_CURVES: no curves, no carve code; docs/PIPELINE.md).
 *
 *   struct edits *ed = edits_create();
 *   struct terrain *t = terrain_create(ed);
 *   struct pipeline *pl = pipeline_create(&g, p, terrain_field(t), err, errlen);
 *   ...
 *   pipeline_destroy(pl);
 *   terrain_destroy(t);
 *   edits_destroy(ed);
 */
#ifndef ISOTERRA_TERRAIN_H
#define ISOTERRA_TERRAIN_H

#include "edit.h"
#include "extract.h"

struct terrain;

/* A terrain carving the edit state ed (borrowed: it must outlive the
 * terrain).  NULL when ed is NULL or out of memory. */
struct terrain *terrain_create(struct edits *ed);
/* Deletes the noise's GL objects (their context must be current).  NULL
 * is fine. */
void terrain_destroy(struct terrain *t);
/* The field for pipeline_create(), valid while t lives; NULL for NULL. */
const struct field *terrain_field(const struct terrain *t);

/* the rest of the folder: noise tables, the CPU reference of the field and
 * the bound of its density over a block (the world's empty-block skip) */
#include "noise.h"
#include "density_ref.h"
#include "density_bound.h"

#endif
