/* isoterra — the process-wide terrain edit state: curves and heightmap,
 * loaded from the files the parameters name (reloaded when a file changes)
 * or set through the API, and the record of the region that changed. */
#include "edits.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

struct file_key {
	char path[PARAM_STR_MAX];
	long long size, mtime_ns;
};

static struct edits E;
static struct file_key curves_key, hm_key;
static int hash_dim;
static bool changed;
static float changed_box[4];

const struct edits *edits_get(void)
{
	return &E;
}

static void note_change(const float box[4])
{
	if (!changed) {
		memcpy(changed_box, box, sizeof(changed_box));
		changed = true;
		return;
	}
	changed_box[0] = box[0] < changed_box[0] ? box[0] : changed_box[0];
	changed_box[1] = box[1] < changed_box[1] ? box[1] : changed_box[1];
	changed_box[2] = box[2] > changed_box[2] ? box[2] : changed_box[2];
	changed_box[3] = box[3] > changed_box[3] ? box[3] : changed_box[3];
}

bool edits_take_changes(float aabb[4])
{
	bool c = changed;
	if (c)
		memcpy(aabb, changed_box, sizeof(changed_box));
	else
		aabb[0] = aabb[1] = aabb[2] = aabb[3] = 0.0f;
	changed = false;
	return c;
}

static int file_key_of(const char *path, struct file_key *k, const char *what, char *err, size_t errlen)
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

static bool same_key(const struct file_key *a, const struct file_key *b)
{
	return !strcmp(a->path, b->path) && a->size == b->size && a->mtime_ns == b->mtime_ns;
}

/* Takes ownership of *s (on success and failure). */
static int install_curves(struct curve_set *s, int dim, bool from_file, char *err, size_t errlen)
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
	float box[4];
	if (curves_affected_bounds(&E.curves, s, box))
		note_change(box);
	curve_set_free(&E.curves);
	curve_quads_free(&E.quads);
	curve_hash_free(&E.hash);
	E.curves = *s;
	memset(s, 0, sizeof(*s));
	E.quads = q;
	E.hash = h;
	E.curves_from_file = from_file;
	E.curves_gen++;
	hash_dim = dim;
	return 0;
}

int edits_set_curves(const struct curve_set *s, int dim, char *err, size_t errlen)
{
	struct curve_set copy;
	if (curve_set_copy(&copy, s) < 0) {
		snprintf(err, errlen, "out of memory copying the curves");
		return -1;
	}
	for (int i = 0; i < copy.npaths; i++)
		if (!copy.paths[i].label[0])
			snprintf(copy.paths[i].label, sizeof(copy.paths[i].label), "curve %d", i + 1);
	memset(&curves_key, 0, sizeof(curves_key));
	return install_curves(&copy, dim, false, err, errlen);
}

static const float whole_plane[4] = { -FLT_MAX, -FLT_MAX, FLT_MAX, FLT_MAX };

int edits_load(const struct params *p, char *err, size_t errlen)
{
	/* curves */
	if (p->curves[0]) {
		struct file_key k;
		if (file_key_of(p->curves, &k, "curves", err, errlen) < 0) {
			struct curve_set s; /* the loader's message: format or open error */
			if (curves_load(p->curves, &s, err, errlen) == 0)
				curve_set_free(&s);
			return -1;
		}
		if (!same_key(&k, &curves_key) || !E.curves_from_file) {
			struct curve_set s;
			if (curves_load(p->curves, &s, err, errlen) < 0)
				return -1;
			if (install_curves(&s, p->curve_hash_dim, true, err, errlen) < 0)
				return -1;
			curves_key = k;
		} else if (p->curve_hash_dim != hash_dim) {
			struct curve_set s;
			if (curve_set_copy(&s, &E.curves) < 0) {
				snprintf(err, errlen, "out of memory");
				return -1;
			}
			if (install_curves(&s, p->curve_hash_dim, true, err, errlen) < 0)
				return -1;
		}
	} else if (E.curves_from_file) {
		struct curve_set none = { NULL, 0 };
		if (install_curves(&none, p->curve_hash_dim, false, err, errlen) < 0)
			return -1;
		memset(&curves_key, 0, sizeof(curves_key));
	}
	/* heightmap */
	if (p->heightmap[0]) {
		struct file_key k;
		if (file_key_of(p->heightmap, &k, "heightmap", err, errlen) < 0) {
			struct heightmap hm; /* the loader's message: format or open error */
			if (heightmap_load(p->heightmap, &hm, err, errlen) == 0)
				heightmap_free(&hm);
			return -1;
		}
		if (!same_key(&k, &hm_key)) {
			struct heightmap hm;
			if (heightmap_load(p->heightmap, &hm, err, errlen) < 0)
				return -1;
			heightmap_free(&E.hm);
			E.hm = hm;
			E.hm_gen++;
			hm_key = k;
			note_change(whole_plane);
		}
	} else if (E.hm.w) {
		heightmap_free(&E.hm);
		E.hm_gen++;
		memset(&hm_key, 0, sizeof(hm_key));
		note_change(whole_plane);
	}
	if (p->field == FIELD_HEIGHTMAP && !E.hm.w) {
		snprintf(err, errlen, "field=heightmap needs a heightmap file (--heightmap FILE.png, 16-bit grayscale)");
		return -1;
	}
	return 0;
}

void edits_clear(void)
{
	curve_set_free(&E.curves);
	curve_quads_free(&E.quads);
	curve_hash_free(&E.hash);
	heightmap_free(&E.hm);
	E.curves_from_file = false;
	E.curves_gen++;
	E.hm_gen++;
	memset(&curves_key, 0, sizeof(curves_key));
	memset(&hm_key, 0, sizeof(hm_key));
	changed = false;
}
