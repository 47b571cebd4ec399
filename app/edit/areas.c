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

/* The samples of a polygon's bounding box [i0, i1] x [j0, j1] (world x =
 * (i - cx) * sc, z = (j - cz) * sc): inside (even-odd over its rings, the
 * outer one and its holes: a row's crossings sorted, the spans between
 * filled; O(rows x edges + samples)), and the distance to the nearest ring
 * edge where it is under fall (each edge visits the samples of its box
 * grown by fall; elsewhere INFINITY).  inside and dist hold nx * nz. */
struct poly_grid {
	int i0, j0, nx, nz;
	float cx, cz, sc;
};

/* v (a sample index, in float) as an int within [lo, hi] */
static int clamp_index(float v, int lo, int hi)
{
	return v < (float)lo ? lo : v > (float)hi ? hi : (int)v;
}

static int cmp_float(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return x < y ? -1 : x > y;
}

static void poly_fill(const struct curve_path *rings, int first, int end, const struct poly_grid *g, unsigned char *inside,
		      float *xs)
{
	for (int r = 0; r < g->nz; r++) {
		float z = ((float)(g->j0 + r) - g->cz) * g->sc;
		int n = 0;
		for (int k = first; k < end; k++) {
			const struct curve_path *c = &rings[k];
			for (int i = 0, j = c->npts - 1; i < c->npts; j = i++) {
				float zi = c->pts[3 * i + 2], zj = c->pts[3 * j + 2];
				if ((zi > z) != (zj > z)) {
					float xi = c->pts[3 * i], xj = c->pts[3 * j];
					xs[n++] = xi + (xj - xi) * (z - zi) / (zj - zi);
				}
			}
		}
		qsort(xs, (size_t)n, sizeof(float), cmp_float);
		for (int p = 0; p + 1 < n; p += 2) {
			float fa = ceilf(xs[p] / g->sc + g->cx) - (float)g->i0;
			float fb = floorf(xs[p + 1] / g->sc + g->cx) - (float)g->i0;
			if (fb < fa)
				continue;
			int a = clamp_index(fa, 0, g->nx), b = clamp_index(fb, -1, g->nx - 1);
			for (int i = a; i <= b; i++)
				inside[(size_t)r * g->nx + i] = 1;
		}
	}
}

static void poly_band(const struct curve_path *rings, int first, int end, const struct poly_grid *g, float fall,
		      float *dist)
{
	for (int k = first; k < end; k++) {
		const struct curve_path *c = &rings[k];
		for (int i = 0, j = c->npts - 1; i < c->npts; j = i++) {
			float ax = c->pts[3 * j], az = c->pts[3 * j + 2], bx = c->pts[3 * i] - ax, bz = c->pts[3 * i + 2] - az;
			float l2 = bx * bx + bz * bz;
			int x0 = clamp_index(floorf((fminf(ax, ax + bx) - fall) / g->sc + g->cx) - (float)g->i0, 0, g->nx);
			int x1 = clamp_index(ceilf((fmaxf(ax, ax + bx) + fall) / g->sc + g->cx) - (float)g->i0, -1, g->nx - 1);
			int z0 = clamp_index(floorf((fminf(az, az + bz) - fall) / g->sc + g->cz) - (float)g->j0, 0, g->nz);
			int z1 = clamp_index(ceilf((fmaxf(az, az + bz) + fall) / g->sc + g->cz) - (float)g->j0, -1, g->nz - 1);
			for (int zz = z0; zz <= z1; zz++)
				for (int xx = x0; xx <= x1; xx++) {
					float x = ((float)(g->i0 + xx) - g->cx) * g->sc, z = ((float)(g->j0 + zz) - g->cz) * g->sc;
					float t = l2 > 0.0f ? ((x - ax) * bx + (z - az) * bz) / l2 : 0.0f;
					t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
					float dx = x - ax - bx * t, dz = z - az - bz * t;
					float *d = &dist[(size_t)zz * g->nx + xx];
					*d = fminf(*d, sqrtf(dx * dx + dz * dz));
				}
		}
	}
}

void areas_restore(struct edits *ed)
{
	if (!ed->hm_pristine)
		return;
	memcpy(ed->hm.v, ed->hm_pristine, sizeof(float) * (size_t)ed->hm.w * (size_t)ed->hm.h);
	free(ed->hm_pristine);
	ed->hm_pristine = NULL;
	ed->hm_gen++;
}

/* The sample index of world coordinate x on an axis of n samples centred
 * on 0, sc apart, rounded by `round`, clamped to [-1, n] (so a far polygon
 * makes an empty range, never an int overflow). */
static int sample_at(float x, float sc, int n, float (*round)(float))
{
	return clamp_index(round(x / sc + 0.5f * (float)(n - 1)), -1, n);
}

/* One polygon, rings [first, end) (the outer one first), on the heightmap:
 * inside set to floor_y, beyond the rim blended to level over fall (the
 * quintic Θ).  The samples are world heights base + v * k.  0, or -1 when
 * out of memory. */
static int apply_polygon(struct heightmap *hm, const struct curve_path *rings, int first, int end, const float lo[2],
			 const float hi[2], float level, float floor_y, float fall, float base, float k, float sc)
{
	int i0 = sample_at(lo[0] - fall, sc, hm->w, floorf), i1 = sample_at(hi[0] + fall, sc, hm->w, ceilf);
	int j0 = sample_at(lo[1] - fall, sc, hm->h, floorf), j1 = sample_at(hi[1] + fall, sc, hm->h, ceilf);
	i0 = i0 < 0 ? 0 : i0, j0 = j0 < 0 ? 0 : j0;
	i1 = i1 > hm->w - 1 ? hm->w - 1 : i1, j1 = j1 > hm->h - 1 ? hm->h - 1 : j1;
	if (i1 < i0 || j1 < j0)
		return 0;
	struct poly_grid g = { i0, j0, i1 - i0 + 1, j1 - j0 + 1, 0.5f * (float)(hm->w - 1), 0.5f * (float)(hm->h - 1), sc };
	size_t nxz = (size_t)g.nx * (size_t)g.nz;
	long nedge = 0;
	for (int r = first; r < end; r++)
		nedge += rings[r].npts;
	unsigned char *inside = calloc(nxz, 1);
	float *dist = malloc(sizeof(float) * nxz), *xs = malloc(sizeof(float) * (size_t)(nedge + 1));
	int rc = inside && dist && xs ? 0 : -1;
	if (rc == 0) {
		for (size_t q = 0; q < nxz; q++)
			dist[q] = INFINITY;
		poly_fill(rings, first, end, &g, inside, xs);
		poly_band(rings, first, end, &g, fall, dist);
		for (size_t q = 0; q < nxz; q++) {
			float w = 1.0f, t = 1.0f - dist[q] / fall;
			if (!inside[q]) {
				if (!(t > 0.0f))
					continue;
				w = t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
			}
			float *v = &hm->v[(size_t)(j0 + (int)(q / (size_t)g.nx)) * hm->w + i0 + (int)(q % (size_t)g.nx)];
			float y = base + *v * k, target = inside[q] ? floor_y : level;
			*v = (y + (target - y) * w - base) / k;
		}
	}
	free(inside);
	free(dist);
	free(xs);
	return rc;
}

int areas_apply(struct edits *ed, const struct params *p, char *err, size_t errlen)
{
	areas_restore(ed);
	free(ed->lakes);
	ed->lakes = NULL;
	ed->nlakes = 0;
	const struct curve_set *a = &ed->areas;
	if (a->npaths == 0 || !ed->hm.w || p->field != FIELD_HEIGHTMAP)
		return 0;
	struct heightmap *hm = &ed->hm;
	if (!(p->heightmap_height > 0.0f) || !(p->heightmap_scale > 0.0f)) {
		log_warn("areas: the heightmap has no relief to edit (heightmap_height %g): %d ring%s unused",
			 (double)p->heightmap_height, a->npaths, a->npaths == 1 ? "" : "s");
		return 0;
	}
	int npoly = 0;
	for (int i = 0; i < a->npaths; i++)
		npoly += a->paths[i].ring == 0;
	size_t n = (size_t)hm->w * (size_t)hm->h;
	ed->hm_pristine = malloc(sizeof(float) * n);
	ed->lakes = calloc((size_t)(npoly ? npoly : 1), sizeof(*ed->lakes));
	if (!ed->hm_pristine || !ed->lakes) {
		free(ed->hm_pristine);
		ed->hm_pristine = NULL;
		snprintf(err, errlen, "out of memory for the areas");
		return -1;
	}
	memcpy(ed->hm_pristine, hm->v, sizeof(float) * n);
	ed->hm_gen++;
	/* a sample's world height and back (carve_ref.c heightmap_ref_base) */
	float k = p->heightmap_height / 65535.0f, base = p->heightmap_base, sc = p->heightmap_scale;
	float fall = fmaxf(p->road_falloff, 1.5f * sc);
	float depth = 2.0f * p->curves_geo_scale * p->vertical_exaggeration;
	int nflat = 0, nwater = 0;
	double t0 = clock_ms();
	for (int first = 0, end; first < a->npaths; first = end) {
		for (end = first + 1; end < a->npaths && a->paths[end].ring > 0; end++)
			;
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
		if (apply_polygon(hm, a->paths, first, end, lo, hi, level, water ? level - depth : level, fall, base, k,
				  sc) < 0) {
			snprintf(err, errlen, "out of memory for the areas");
			return -1;
		}
		if (water) {
			float *l = ed->lakes[ed->nlakes++];
			l[0] = lo[0], l[1] = lo[1], l[2] = hi[0], l[3] = hi[1], l[4] = level;
		}
		nwater += water;
		nflat += !water;
	}
	log_info("areas: %d flattened, %d filled with water, on the heightmap's %dx%d samples (blended over %g world "
		 "units), in %.2f ms", nflat, nwater, hm->w, hm->h, (double)fall, clock_ms() - t0);
	return 0;
}
