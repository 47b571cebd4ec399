/* isoterra — what the edit state shows beyond the terrain's shape, for a
 * scene's frame: the roads' paint (edits_road_map: made again only when
 * the curves change) and the lakes of its water areas, handed to the
 * renderer. */
#include "scene.h"
#include "edit.h"
#include "render.h"

int scene_roads(struct edits *ed, const struct params *p, struct renderer *r, char *err, size_t errlen)
{
	struct road_map m;
	if (edits_road_map(ed, p, &m, err, errlen) < 0)
		return -1;
	renderer_set_road_map(r, m.tex, m.origin, m.size, m.y0, m.tol);
	renderer_set_lakes(r, (const float (*)[5])ed->lakes, ed->nlakes);
	return 0;
}
