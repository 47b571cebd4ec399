/* isoterra — the streaming world's planning: the table of known blocks
 * (open addressing on (x, y, z, lod)) and, each frame, the blocks the camera
 * wants: every level out to its range, inside the frustum widened by
 * `prefetch` and the band of heights where the surface can be, nearest
 * first (docs/WORLD.md). */
#include "world_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static uint32_t hash_key(const int k[4])
{
	uint32_t h = (uint32_t)k[0] * 73856093u ^ (uint32_t)k[1] * 19349663u ^ (uint32_t)k[2] * 83492791u ^
		     (uint32_t)k[3] * 2654435761u;
	return h ^ (h >> 15);
}

static int rehash(struct world *w);

int find_block(struct world *w, const int k[4], bool create)
{
	if (create && (w->count + 1) * 4 > w->cap * 3 && rehash(w) < 0)
		return -1;
	uint32_t mask = w->cap - 1;
	for (uint32_t i = hash_key(k) & mask;; i = (i + 1) & mask) {
		struct block *b = &w->blocks[i];
		if (b->key[3] < 0) {
			if (!create)
				return -1;
			memcpy(b->key, k, sizeof(b->key));
			b->state = B_FREE;
			b->slot = -1;
			b->readback = -1;
			b->stale = false;
			b->generations = 0;
			b->probe = PROBE_UNKNOWN;
			w->count++;
			return (int)i;
		}
		if (!memcmp(b->key, k, sizeof(b->key)))
			return (int)i;
	}
}

/* Whether block b stays in the table when it is pruned: it holds a slot or
 * a result in flight, or was wanted in the last `age` frames (age 0: all). */
static bool keep_block(const struct world *w, const struct block *b, uint32_t age)
{
	return !age || b->slot >= 0 || b->readback >= 0 || b->stale || w->frame - b->frame < age;
}

/* The table re-made with ncap entries, keeping the blocks keep_block keeps. */
static int rebuild(struct world *w, uint32_t ncap, uint32_t age)
{
	struct block *old = w->blocks;
	uint32_t ocap = w->cap;
	struct block *nb = malloc(sizeof(*nb) * ncap);
	if (!nb)
		return -1;
	for (uint32_t i = 0; i < ncap; i++)
		nb[i].key[3] = -1;
	w->blocks = nb;
	w->cap = ncap;
	w->count = 0;
	for (int i = 0; i < w->slots; i++)
		w->slot_block[i] = -1;
	for (uint32_t i = 0; i < ocap; i++) {
		if (old[i].key[3] < 0 || !keep_block(w, &old[i], age))
			continue;
		int j = find_block(w, old[i].key, true);
		w->blocks[j] = old[i];
		if (old[i].slot >= 0)
			w->slot_block[old[i].slot] = j;
		if (old[i].readback >= 0)
			w->rb[old[i].readback].block = j;
	}
	free(old);
	return 0;
}

static int rehash(struct world *w)
{
	return rebuild(w, w->cap * 2, 0);
}

int prune_blocks(struct world *w, uint32_t age)
{
	if (w->count * 2 <= w->cap)
		return 0;
	uint32_t keep = 0;
	for (uint32_t i = 0; i < w->cap; i++)
		keep += w->blocks[i].key[3] >= 0 && keep_block(w, &w->blocks[i], age);
	uint32_t ncap = w->cap;
	while (keep * 2 > ncap)
		ncap *= 2;
	w->st.forgotten += w->count - keep;
	return rebuild(w, ncap, age);
}

int world_block_generations(const struct world *w, int lod, const int idx[3], int *state)
{
	int k[4] = { idx[0], idx[1], idx[2], lod };
	uint32_t mask = w->cap - 1;
	for (uint32_t i = hash_key(k) & mask;; i = (i + 1) & mask) {
		const struct block *b = &w->blocks[i];
		if (b->key[3] < 0) {
			*state = 0;
			return -1;
		}
		if (!memcmp(b->key, k, sizeof(b->key))) {
			*state = (int)b->state;
			return b->generations;
		}
	}
}

float block_world_size(const struct params *p, int lod)
{
	return p->block_size * (float)(1 << lod);
}

void block_aabb(const struct params *p, const int k[4], float lo[3], float hi[3])
{
	float s = block_world_size(p, k[3]);
	for (int a = 0; a < 3; a++) {
		lo[a] = (float)k[a] * s;
		hi[a] = lo[a] + s;
	}
}

/* Frustum planes (Gribb & Hartmann) from a column-major view-projection. */
static void frustum(const float m[16], float pl[6][4])
{
	for (int i = 0; i < 3; i++)
		for (int s = 0; s < 2; s++) {
			float *q = pl[i * 2 + s];
			float sign = s ? -1.0f : 1.0f;
			for (int j = 0; j < 4; j++)
				q[j] = m[j * 4 + 3] + sign * m[j * 4 + i];
		}
}

static bool aabb_visible(float pl[6][4], const float lo[3], const float hi[3])
{
	for (int i = 0; i < 6; i++) {
		float px = pl[i][0] >= 0 ? hi[0] : lo[0];
		float py = pl[i][1] >= 0 ? hi[1] : lo[1];
		float pz = pl[i][2] >= 0 ? hi[2] : lo[2];
		if (pl[i][0] * px + pl[i][1] * py + pl[i][2] * pz + pl[i][3] < 0)
			return false;
	}
	return true;
}

float lod_range(const struct params *p, int lod)
{
	if (lod == p->lod_levels - 1)
		return p->view_distance;
	float r = p->lod_distance * block_world_size(p, lod);
	return r < p->view_distance ? r : p->view_distance;
}

/* Heights where the surface can be (ground shape): the noise adds at most
 * about 1.6 x noise_amp, the warp moves it by warp_amp. */
static void height_band(const struct world *w, const struct params *p, const float eye[3], float range, float *ylo,
			float *yhi)
{
	if (p->shape != SHAPE_GROUND) { /* planet, caves: anywhere */
		*ylo = eye[1] - range;
		*yhi = eye[1] + range;
		return;
	}
	float reach = 1.6f * p->noise_amp / (p->ground_slope > 0.05f ? p->ground_slope : 0.05f) + p->warp_amp;
	*ylo = -reach;
	*yhi = reach;
	if (p->floor_strength > 0 && p->floor_y - 1.0f > *ylo)
		*ylo = p->floor_y - 1.0f;
	/* terrain edits: the heightmap's own range; curves put the surface at
	 * their heights (cut and fill) */
	if (p->field == FIELD_HEIGHTMAP) {
		float extra = p->heightmap_detail + 1.6f * p->heightmap_noise * p->noise_amp + p->warp_amp + 1.0f;
		*ylo = fminf(*ylo, p->heightmap_base - extra);
		*yhi = fmaxf(*yhi, p->heightmap_base + p->heightmap_height + extra);
	}
	const struct curve_quads *q = &w->ed->quads;
	for (int i = 0; i < q->nctrl; i++) {
		*ylo = fminf(*ylo, q->ctrl[i][1] - 1.0f);
		*yhi = fmaxf(*yhi, q->ctrl[i][1] + 1.0f);
	}
}

/* Nearest first; finer first at equal distance; then by key (a total
 * order: any sort gives the same list). */
static int cmp_want(const void *a, const void *b)
{
	const struct want_key *x = a, *y = b;
	if (x->dist != y->dist)
		return x->dist < y->dist ? -1 : 1;
	if (x->key[3] != y->key[3])
		return x->key[3] < y->key[3] ? -1 : 1;
	return memcmp(x->key, y->key, sizeof(x->key));
}

static void sort_want(struct world *w)
{
	if (w->nwant < 2) /* (none wanted: the list may not exist yet, and qsort takes no NULL) */
		return;
	for (int i = 0; i < w->nwant; i++) {
		const struct block *b = &w->blocks[w->want[i]];
		struct want_key *k = &w->want_sort[i];
		k->dist = b->dist;
		memcpy(k->key, b->key, sizeof(k->key));
		k->block = w->want[i];
	}
	qsort(w->want_sort, (size_t)w->nwant, sizeof(*w->want_sort), cmp_want);
	for (int i = 0; i < w->nwant; i++)
		w->want[i] = w->want_sort[i].block;
}

static int push_want(struct world *w, int b)
{
	if (w->nwant == w->want_cap) {
		int nc = w->want_cap ? w->want_cap * 2 : 1024;
		int *nw = realloc(w->want, sizeof(int) * (size_t)nc);
		if (nw)
			w->want = nw;
		struct want_key *ns = realloc(w->want_sort, sizeof(*ns) * (size_t)nc);
		if (ns)
			w->want_sort = ns;
		if (!nw || !ns)
			return -1;
		w->want_cap = nc;
	}
	w->want[w->nwant++] = b;
	return 0;
}

int plan_blocks(struct world *w, const struct params *p, const struct camera *c)
{
	/* Blocks are wanted in a frustum widened by `prefetch` (the view turns
	 * while blocks stream in), drawn only when in the real one. */
	float pl[6][4], wide[6][4], proj[16], vp[16];
	frustum(c->viewproj, pl);
	memcpy(proj, c->proj, sizeof(proj));
	/* clip x and y shrunk about the centre: a wider view around the
	 * frame's own (a wall's off-axis tile too: its rows 0 and 1 carry
	 * the shift) */
	for (int col = 0; col < 4; col++) {
		proj[col * 4 + 0] /= p->prefetch;
		proj[col * 4 + 1] /= p->prefetch;
	}
	mat4_mul(vp, proj, c->view);
	frustum(vp, wide);
	w->nwant = 0;
	for (int lod = 0; lod < p->lod_levels; lod++) {
		float s = block_world_size(p, lod), range = lod_range(p, lod);
		float ylo, yhi;
		height_band(w, p, c->eye, range, &ylo, &yhi);
		int lo[3], hi[3];
		for (int a = 0; a < 3; a++) {
			float l = c->eye[a] - range, h = c->eye[a] + range;
			if (a == 1) {
				l = fmaxf(l, ylo);
				h = fminf(h, yhi);
			}
			lo[a] = (int)floorf(l / s);
			hi[a] = (int)floorf(h / s);
		}
		for (int z = lo[2]; z <= hi[2]; z++)
			for (int y = lo[1]; y <= hi[1]; y++)
				for (int x = lo[0]; x <= hi[0]; x++) {
					int k[4] = { x, y, z, lod };
					float blo[3], bhi[3];
					block_aabb(p, k, blo, bhi);
					float d = camera_box_distance(c, blo, bhi);
					if (d > range || !aabb_visible(wide, blo, bhi))
						continue;
					int b = find_block(w, k, true);
					if (b < 0)
						return -1;
					/* pointers may move with a rehash: use indices */
					w->blocks[b].dist = d;
					w->blocks[b].frame = w->frame;
					w->blocks[b].visible = aabb_visible(pl, blo, bhi);
					if (w->blocks[b].state == B_EMPTY) {
						w->st.empty_skipped++;
						continue;
					}
					if (push_want(w, b) < 0)
						return -1;
				}
	}
	sort_want(w);
	return 0;
}
