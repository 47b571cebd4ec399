/* isoterra — the terrain edit state: curves and heightmap, loaded from the
 * files the parameters name (reloaded when a file changes) or set through
 * the API, and the record of the region that changed. */
#include "edits.h"
#include "core.h"
#include "geo_module.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

struct edits *edits_create(void)
{
	return calloc(1, sizeof(struct edits));
}

void edits_destroy(struct edits *ed)
{
	if (!ed)
		return;
	edits_gl_release(ed);
	edits_clear(ed);
	free(ed);
}

static void note_change(struct edits *ed, const float box[4])
{
	float *cb = ed->changed_box;
	if (!ed->changed) {
		memcpy(cb, box, sizeof(ed->changed_box));
		ed->changed = true;
		return;
	}
	cb[0] = box[0] < cb[0] ? box[0] : cb[0];
	cb[1] = box[1] < cb[1] ? box[1] : cb[1];
	cb[2] = box[2] > cb[2] ? box[2] : cb[2];
	cb[3] = box[3] > cb[3] ? box[3] : cb[3];
}

bool edits_take_changes(struct edits *ed, float aabb[4])
{
	bool c = ed->changed;
	if (c)
		memcpy(aabb, ed->changed_box, sizeof(ed->changed_box));
	else
		aabb[0] = aabb[1] = aabb[2] = aabb[3] = 0.0f;
	ed->changed = false;
	return c;
}

static int file_key_of(const char *path, struct edits_file *k, const char *what, char *err, size_t errlen)
{
	struct stat st;
	memset(k, 0, sizeof(*k));
	if (stat(path, &st) != 0) {
		snprintf(err, errlen, "cannot open %s file '%s'", what, path);
		return -1;
	}
	snprintf(k->path, sizeof(k->path), "%s", path);
	k->size = (long long)st.st_size;
	k->mtime_ns = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
	return 0;
}

static bool same_key(const struct edits_file *a, const struct edits_file *b)
{
	return !strcmp(a->path, b->path) && a->size == b->size && a->mtime_ns == b->mtime_ns;
}

/* Takes ownership of *s (on success and failure). */
static int install_curves(struct edits *ed, struct curve_set *s, int dim, bool from_file, char *err, size_t errlen)
{
	struct curve_quads q;
	struct curve_hash h;
	if (curves_build(s, &q, err, errlen) < 0) {
		curve_set_free(s);
		return -1;
	}
	if (curve_hash_build(&q, dim, &h, err, errlen) < 0) {
		curve_quads_free(&q);
		curve_set_free(s);
		return -1;
	}
	if (q.nquads)
		log_debug("curves: %d pieces, hash %dx%d cells, at most %d a cell", q.nquads, h.dim, h.dim, h.max_per_cell);
	if (h.max_per_cell > CURVE_CELL_MAX)
		log_warn("curves: a cell of the %dx%d curve hash lists %d curve pieces, more than %d: a software "
			 "rasterizer (llvmpipe) ends a shader's loops after 65535 iterations and the carve may lose "
			 "samples; raise curve_hash_dim (0: sized to the curves)", h.dim, h.dim, h.max_per_cell,
			 CURVE_CELL_MAX);
	float box[4];
	if (curves_affected_bounds(&ed->curves, s, box))
		note_change(ed, box);
	curve_set_free(&ed->curves);
	curve_quads_free(&ed->quads);
	curve_hash_free(&ed->hash);
	ed->curves = *s;
	memset(s, 0, sizeof(*s));
	ed->quads = q;
	ed->hash = h;
	ed->curves_from_file = from_file;
	ed->curves_gen++;
	ed->hash_dim = dim;
	return 0;
}

int edits_set_curves(struct edits *ed, const struct curve_set *s, int dim, char *err, size_t errlen)
{
	struct curve_set copy;
	if (curve_set_copy(&copy, s) < 0) {
		snprintf(err, errlen, "out of memory copying the curves");
		return -1;
	}
	for (int i = 0; i < copy.npaths; i++)
		if (!copy.paths[i].label[0])
			snprintf(copy.paths[i].label, sizeof(copy.paths[i].label), "curve %d", i + 1);
	memset(&ed->curves_file, 0, sizeof(ed->curves_file));
	return install_curves(ed, &copy, dim, false, err, errlen);
}

static const float whole_plane[4] = { -FLT_MAX, -FLT_MAX, FLT_MAX, FLT_MAX };

void edits_set_ground(struct edits *ed, edits_ground_fn fn, void *ctx)
{
	ed->ground = fn;
	ed->ground_ctx = ctx;
}

struct ground_call {
	const struct edits *ed;
	const struct params *p;
};

static bool ground_at(void *ctx, float x, float z, float *y)
{
	const struct ground_call *c = ctx;
	return c->ed->ground(c->ed->ground_ctx, c->p, c->ed, x, z, y);
}

/* The volume scene carves only inside its box: curves mostly outside it
 * would leave the picture as it is without them.  A warning with both
 * extents (the streaming world goes wherever they are). */
static void outside_volume(const struct params *p, const struct curve_set *s)
{
	if (p->scene != SCENE_VOLUME || s->npaths == 0)
		return;
	float h = 0.5f * p->vol_size, box[4] = { p->vol_x - h, p->vol_z - h, p->vol_x + h, p->vol_z + h }, e[4];
	double in = curves_inside_fraction(s, box, e);
	if (in >= 0.5)
		return;
	char share[32];
	if (in == 0.0)
		snprintf(share, sizeof(share), "all");
	else if (in < 0.001)
		snprintf(share, sizeof(share), "over 99.9%%");
	else
		snprintf(share, sizeof(share), "%.1f%%", 100.0 * (1.0 - in));
	log_warn("%s: %s of the curves' length lies outside the volume: the curves span x [%g, %g] z [%g, %g], the "
		 "volume x [%g, %g] z [%g, %g] (world units); scale them (curves_geo_scale) or move or widen the volume "
		 "(vol_x, vol_z, vol_size)", p->curves, share, (double)e[0], (double)e[2], (double)e[1], (double)e[3],
		 (double)box[0], (double)box[2], (double)box[1], (double)box[3]);
}

/* The file's curves in world units: lon/lat projected, 2D curves on the
 * ground (curves_geo.c). */
static int load_curves_file(struct edits *ed, const struct params *p, struct curve_set *s, char *err, size_t errlen)
{
	if (curves_load(p->curves, s, err, errlen) < 0)
		return -1;
	curves_road_widths(s, p->road_width, p->road_falloff);
	bool lonlat;
	const char *why;
	double c[2];
	int mode;
	char crs[128] = "";
	if (curves_crs_parse(p->curves_crs, &mode, err, errlen) < 0 ||
	    (mode == CURVES_CRS_NAMED && curves_from_crs(s, p->curves_crs, geo_crs_to_lonlat, crs, sizeof(crs), err,
							 errlen) < 0))
		goto fail;
	/* one frame for all data: a georeferenced heightmap's */
	const struct heightmap_geo *g = &ed->hm.geo;
	struct curves_geo_frame fr = { g->lon0, g->lat0, p->curves_geo_scale * p->vertical_exaggeration };
	bool on_map = g->on && p->field == FIELD_HEIGHTMAP;
	if (curves_geo_project(s, mode, p->curves_geo_scale, on_map ? &fr : NULL, &lonlat, &why, c, err, errlen) < 0)
		goto fail;
	if (lonlat)
		log_info("%s: %s%s%s (%s), put on the east-north-up plane of %s at lon %.6f lat %.6f, %g world units per "
			 "metre", p->curves, crs[0] ? crs : "WGS84 lon/lat", crs[0] ? " " : "",
			 crs[0] ? p->curves_crs : "", why, on_map ? "the heightmap's centre" : "the curves' centroid",
			 c[0], c[1], (double)p->curves_geo_scale);
	/* what the readers and the projection did instead of refusing the
	 * file: one warning each */
	for (int i = 0; i < s->nnotes; i++)
		log_warn("%s", s->notes[i]);
	outside_volume(p, s);
	struct ground_call gc = { ed, p };
	if (curves_follow_ground(s, p->curves_follow_step, ed->ground ? ground_at : NULL, &gc, err, errlen) < 0)
		goto fail;
	return 0;
fail:
	curve_set_free(s);
	return -1;
}

/* The areas (polygon rings) out of s into ed->areas, the lines left in s.
 * 0, or -1 (out of memory). */
static int take_areas(struct edits *ed, struct curve_set *s, const struct params *p, char *err, size_t errlen)
{
	curve_set_free(&ed->areas);
	int keep = 0, nrings = 0, npoly = 0;
	for (int i = 0; i < s->npaths; i++) {
		struct curve_path *c = &s->paths[i];
		if (!c->area) {
			s->paths[keep++] = *c;
			continue;
		}
		nrings++;
		npoly += c->ring == 0;
		if (curve_set_add(&ed->areas, c) < 0) {
			snprintf(err, errlen, "out of memory");
			return -1;
		}
		free(c->pts);
	}
	s->npaths = keep;
	if (npoly && p->field != FIELD_HEIGHTMAP) {
		char field[32] = "?";
		const struct param_info *pi = params_find("field");
		if (pi)
			params_enum_name(pi, p->field, field, sizeof(field));
		log_warn("%s: %d area%s (%d ring%s) not carved: areas flatten or flood a heightmap (field = heightmap), "
			 "and this field is %s", p->curves, npoly, npoly == 1 ? "" : "s", nrings, nrings == 1 ? "" : "s",
			 field);
	}
	return 0;
}

/* The curves file p->curves, (re)loaded when it changed. */
static int load_curves(struct edits *ed, const struct params *p, char *err, size_t errlen)
{
	if (p->curves[0]) {
		struct edits_file k;
		if (file_key_of(p->curves, &k, "curves", err, errlen) < 0) {
			struct curve_set s; /* the loader's message: format or open error */
			if (curves_load(p->curves, &s, err, errlen) == 0)
				curve_set_free(&s);
			return -1;
		}
		/* a new heightmap: a new frame for lon/lat, new ground for 2D */
		if (!same_key(&k, &ed->curves_file) || !ed->curves_from_file || ed->curves_hm_gen != ed->hm_gen) {
			/* the ground 2D curves and rims follow is the map's own */
			unsigned g0 = ed->hm_gen;
			areas_restore(ed);
			struct curve_set s;
			if (load_curves_file(ed, p, &s, err, errlen) < 0)
				return -1;
			if (take_areas(ed, &s, p, err, errlen) < 0) {
				curve_set_free(&s);
				return -1;
			}
			if (install_curves(ed, &s, p->curve_hash_dim, true, err, errlen) < 0 ||
			    areas_apply(ed, p, err, errlen) < 0)
				return -1;
			if (ed->hm_gen != g0)
				note_change(ed, whole_plane);
			ed->curves_file = k;
			ed->curves_hm_gen = ed->hm_gen;
		} else if (p->curve_hash_dim != ed->hash_dim) {
			struct curve_set s;
			if (curve_set_copy(&s, &ed->curves) < 0) {
				snprintf(err, errlen, "out of memory");
				return -1;
			}
			if (install_curves(ed, &s, p->curve_hash_dim, true, err, errlen) < 0)
				return -1;
		}
	} else if (ed->curves_from_file) {
		struct curve_set none = { .paths = NULL, .npaths = 0 };
		if (install_curves(ed, &none, p->curve_hash_dim, false, err, errlen) < 0)
			return -1;
		if (ed->areas.npaths) {
			curve_set_free(&ed->areas);
			if (areas_apply(ed, p, err, errlen) < 0) /* restores, no lakes */
				return -1;
			note_change(ed, whole_plane);
		}
		memset(&ed->curves_file, 0, sizeof(ed->curves_file));
	}
	return 0;
}

/* The heightmap file p->heightmap, (re)loaded when it changed. */
static int load_heightmap(struct edits *ed, const struct params *p, char *err, size_t errlen)
{
	if (p->heightmap[0]) {
		struct edits_file k;
		if (file_key_of(p->heightmap, &k, "heightmap", err, errlen) < 0) {
			struct heightmap hm; /* the loader's message: format or open error */
			if (heightmap_load(p->heightmap, &hm, err, errlen) == 0)
				heightmap_free(&hm);
			return -1;
		}
		if (!same_key(&k, &ed->hm_file)) {
			struct heightmap hm;
			if (heightmap_load(p->heightmap, &hm, err, errlen) < 0)
				return -1;
			char line[1024];
			heightmap_describe(&hm, p->heightmap, line, sizeof(line));
			log_info("%s", line);
			heightmap_free(&ed->hm);
			ed->hm = hm;
			free(ed->hm_pristine); /* the old map's: the curves load again, and the areas */
			ed->hm_pristine = NULL;
			ed->hm_gen++;
			ed->hm_file = k;
			note_change(ed, whole_plane);
		}
	} else if (ed->hm.w) {
		heightmap_free(&ed->hm);
		ed->hm_gen++;
		memset(&ed->hm_file, 0, sizeof(ed->hm_file));
		note_change(ed, whole_plane);
	}
	return 0;
}

/* The control map file p->control_map, (re)loaded when it changed. */
static int load_control(struct edits *ed, const struct params *p, char *err, size_t errlen)
{
	if (p->control_map[0]) {
		struct edits_file k;
		if (file_key_of(p->control_map, &k, "control map", err, errlen) < 0)
			return -1;
		if (!same_key(&k, &ed->control_file)) {
			struct heightmap m;
			if (heightmap_read_png(p->control_map, "control map", &m, err, errlen) < 0)
				return -1;
			heightmap_free(&ed->control);
			ed->control = m;
			ed->control_gen++;
			ed->control_file = k;
			note_change(ed, whole_plane);
		}
	} else if (ed->control.w) {
		heightmap_free(&ed->control);
		ed->control_gen++;
		memset(&ed->control_file, 0, sizeof(ed->control_file));
		note_change(ed, whole_plane);
	}
	return 0;
}

int edits_load(struct edits *ed, const struct params *p, char *err, size_t errlen)
{
	/* the heightmap first: 2D curves may follow it */
	if (load_heightmap(ed, p, err, errlen) < 0 || load_control(ed, p, err, errlen) < 0 ||
	    load_curves(ed, p, err, errlen) < 0)
		return -1;
	if (p->field == FIELD_HEIGHTMAP && !ed->hm.w) {
		snprintf(err, errlen, "field=heightmap needs a heightmap file (--heightmap FILE.png, 16-bit grayscale)");
		return -1;
	}
	return 0;
}

void edits_clear(struct edits *ed)
{
	curve_set_free(&ed->curves);
	curve_set_free(&ed->areas);
	free(ed->hm_pristine);
	ed->hm_pristine = NULL;
	free(ed->lakes);
	ed->lakes = NULL;
	ed->nlakes = 0;
	curve_quads_free(&ed->quads);
	curve_hash_free(&ed->hash);
	heightmap_free(&ed->hm);
	heightmap_free(&ed->control);
	ed->control_gen++;
	memset(&ed->control_file, 0, sizeof(ed->control_file));
	ed->curves_from_file = false;
	ed->curves_gen++;
	ed->hm_gen++;
	memset(&ed->curves_file, 0, sizeof(ed->curves_file));
	memset(&ed->hm_file, 0, sizeof(ed->hm_file));
	ed->changed = false;
}

bool edits_has_tunnels(const struct edits *ed)
{
	for (int k = 0; k < ed->quads.nquads; k++)
		if (ed->quads.prm[ed->quads.first[k]][2] >= (float)CURVE_TUNNEL) /* tunnel or bridge */
			return true;
	return false;
}
