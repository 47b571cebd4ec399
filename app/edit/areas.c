/* isoterra — areas (GeoJSON Polygon / MultiPolygon rings, curves.h
 * enum curve_area) on a heightmap: the samples under a flat area (a
 * square, a field, landuse) set to its rim's mean height, under water to
 * its rim's lowest height less a depth, blended back over road_falloff
 * beyond the rim; each water area a lake whose surface the renderer draws
 * at that level.  The heightmap's own samples are kept, so a new set of
 * areas starts from them. */
#include "edits.h"
#include "core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Even-odd: is (x, z) inside the ring's XZ polygon? */
static bool ring_inside(const struct curve_path *r, float x, float z)
{
	bool in = false;
	for (int i = 0, j = r->npts - 1; i < r->npts; j = i++) {
		float xi = r->pts[3 * i], zi = r->pts[3 * i + 2], xj = r->pts[3 * j], zj = r->pts[3 * j + 2];
		if ((zi > z) != (zj > z) && x < (xj - xi) * (z - zi) / (zj - zi) + xi)
			in = !in;
	}
	return in;
}

/* The XZ distance from (x, z) to the ring's edges. */
static float ring_distance(const struct curve_path *r, float x, float z)
{
	float best = INFINITY;
	for (int i = 0, j = r->npts - 1; i < r->npts; j = i++) {
		float ax = r->pts[3 * j], az = r->pts[3 * j + 2], bx = r->pts[3 * i] - ax, bz = r->pts[3 * i + 2] - az;
		float l2 = bx * bx + bz * bz, t = l2 > 0.0f ? ((x - ax) * bx + (z - az) * bz) / l2 : 0.0f;
		t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
		float dx = x - ax - bx * t, dz = z - az - bz * t;
		best = fminf(best, dx * dx + dz * dz);
	}
	return sqrtf(best);
}

/* The polygon of rings [first, end): inside the outer ring and no hole;
 * the distance to its nearest ring. */
static bool poly_inside(const struct curve_path *rings, int first, int end, float x, float z, float *dist)
{
	bool in = ring_inside(&rings[first], x, z);
	*dist = ring_distance(&rings[first], x, z);
	for (int k = first + 1; k < end; k++) {
		in = in && !ring_inside(&rings[k], x, z);
		*dist = fminf(*dist, ring_distance(&rings[k], x, z));
	}
	return in;
}

static void restore(struct edits *ed)
{
	if (!ed->hm_pristine)
		return;
	if (ed->hm.w * ed->hm.h == ed->hm_pristine_n)
		memcpy(ed->hm.v, ed->hm_pristine, sizeof(float) * (size_t)ed->hm_pristine_n);
	free(ed->hm_pristine);
	ed->hm_pristine = NULL;
	ed->hm_pristine_n = 0;
	ed->hm_gen++;
}

void areas_restore(struct edits *ed)
{
	restore(ed);
}

int areas_apply(struct edits *ed, const struct params *p, char *err, size_t errlen)
{
	restore(ed);
	free(ed->lakes);
	ed->lakes = NULL;
	ed->nlakes = 0;
	const struct curve_set *a = &ed->areas;
	if (a->npaths == 0 || !ed->hm.w || p->field != FIELD_HEIGHTMAP)
		return 0;
	struct heightmap *hm = &ed->hm;
	long n = (long)hm->w * hm->h;
	if (!(p->heightmap_height > 0.0f) || !(p->heightmap_scale > 0.0f)) {
		log_warn("areas: the heightmap has no relief to edit (heightmap_height %g): %d ring%s unused",
			 (double)p->heightmap_height, a->npaths, a->npaths == 1 ? "" : "s");
		return 0;
	}
	int npoly = 0;
	for (int i = 0; i < a->npaths; i++)
		npoly += a->paths[i].ring == 0;
	ed->hm_pristine = malloc(sizeof(float) * (size_t)n);
	ed->lakes = calloc((size_t)(npoly ? npoly : 1), sizeof(*ed->lakes));
	if (!ed->hm_pristine || !ed->lakes) {
		free(ed->hm_pristine);
		ed->hm_pristine = NULL;
		snprintf(err, errlen, "out of memory for the areas");
		return -1;
	}
	memcpy(ed->hm_pristine, hm->v, sizeof(float) * (size_t)n);
	ed->hm_pristine_n = n;
	/* a sample's world height and back (carve_ref.c heightmap_ref_base) */
	float k = p->heightmap_height / 65535.0f, base = p->heightmap_base, sc = p->heightmap_scale;
	float fall = fmaxf(p->road_falloff, 1.5f * sc);
	float depth = 2.0f * p->curves_geo_scale * p->vertical_exaggeration;
	int nflat = 0, nwater = 0;
	double t0 = clock_ms();
	for (int first = 0; first < a->npaths;) {
		int end = first + 1;
		while (end < a->npaths && a->paths[end].ring > 0)
			end++;
		const struct curve_path *outer = &a->paths[first];
		float lo[2] = { INFINITY, INFINITY }, hi[2] = { -INFINITY, -INFINITY }, ymin = INFINITY;
		double ysum = 0.0, len = 0.0;
		for (int i = 0, j = outer->npts - 1; i < outer->npts; j = i++) {
			const float *q = outer->pts + 3 * i, *r = outer->pts + 3 * j;
			lo[0] = fminf(lo[0], q[0]), hi[0] = fmaxf(hi[0], q[0]);
			lo[1] = fminf(lo[1], q[2]), hi[1] = fmaxf(hi[1], q[2]);
			ymin = fminf(ymin, q[1]);
			/* the rim's mean height along its length */
			double l = hypot(q[0] - r[0], q[2] - r[2]);
			ysum += 0.5 * (q[1] + r[1]) * l;
			len += l;
		}
		bool water = outer->area == AREA_WATER;
		float level = water ? ymin : (float)(len > 0.0 ? ysum / len : outer->pts[1]);
		float floor_y = water ? level - depth : level;
		int i0 = (int)floorf((lo[0] - fall) / sc + 0.5f * (float)(hm->w - 1)), i1 = (int)ceilf((hi[0] + fall) / sc + 0.5f * (float)(hm->w - 1));
		int j0 = (int)floorf((lo[1] - fall) / sc + 0.5f * (float)(hm->h - 1)), j1 = (int)ceilf((hi[1] + fall) / sc + 0.5f * (float)(hm->h - 1));
		i0 = i0 < 0 ? 0 : i0, j0 = j0 < 0 ? 0 : j0;
		i1 = i1 > hm->w - 1 ? hm->w - 1 : i1, j1 = j1 > hm->h - 1 ? hm->h - 1 : j1;
		for (int j = j0; j <= j1; j++)
			for (int i = i0; i <= i1; i++) {
				float x = ((float)i - 0.5f * (float)(hm->w - 1)) * sc, z = ((float)j - 0.5f * (float)(hm->h - 1)) * sc;
				float d;
				bool in = poly_inside(a->paths, first, end, x, z, &d);
				float w = 1.0f, target = in ? floor_y : level;
				if (!in) {
					float t = 1.0f - d / fall;
					if (t <= 0.0f)
						continue;
					w = t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
				}
				float *v = &hm->v[(size_t)j * hm->w + i];
				float y = base + *v * k;
				*v = (y + (target - y) * w - base) / k;
			}
		if (water) {
			float *l = ed->lakes[ed->nlakes++];
			l[0] = lo[0], l[1] = lo[1], l[2] = hi[0], l[3] = hi[1], l[4] = level;
			nwater++;
		} else {
			nflat++;
		}
		first = end;
	}
	ed->hm_gen++;
	log_info("areas: %d flattened, %d filled with water, on the heightmap's %dx%d samples (blended over %g world "
		 "units), in %.2f ms", nflat, nwater, hm->w, hm->h, (double)fall, clock_ms() - t0);
	return 0;
}
