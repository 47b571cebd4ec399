/* isoterra — the roads' paint for a scene's frame: the edit state's road
 * map (edits_road_map: made again only when the curves change) handed to
 * the renderer, or none. */
#include "scene.h"
#include "edit.h"
#include "render.h"

int scene_roads(struct edits *ed, const struct params *p, struct renderer *r, char *err, size_t errlen)
{
	struct road_map m;
	if (edits_road_map(ed, p, &m, err, errlen) < 0)
		return -1;
	renderer_set_road_map(r, m.tex, m.origin, m.size, m.y0, m.tol);
	return 0;
}
