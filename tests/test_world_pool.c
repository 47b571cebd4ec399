/* isoterra — the streaming world's block memory (app/scene/world_pool.c):
 * meshes kept at their real sizes in an arena of chunks added as the
 * blocks need them.  A world whose arena is in 64 KB chunks (many added,
 * some packed) draws the same image and exports the same mesh as one in a
 * few large chunks; the arena holds exactly the exported triangles and
 * vertices (plus alignment), its chunks at most twice that plus one chunk,
 * and a fraction of the worst case; evictions and
 * blocks over capacity (--block-tris 256) keep every staging canary intact
 * and every mesh inside the arena, apart from the others; the table of
 * known blocks stays bounded over a long flight. */
#include "app.h"
#include "world.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "abi.h" /* VERTEX_BYTES */

#include <string.h>

static void pool_world(struct params *p)
{
	fixture_small_world(p, 64);
	p->seed = 7;
}

struct run {
	struct image img;
	struct mesh mesh;
	struct world_stats st;
	int faults, faults_moved;
	int compacted;        /* meshes moved by a compaction after the move */
	bool same_compacted;  /* the same image before and after it */
};

/* A world filled for the autopilot's camera at t, drawn and exported; then
 * (moved) filled again at t + 60 s, where other blocks are wanted. */
static int run_world(const struct params *p, long long arena_start, bool move, struct run *out)
{
	char err[512] = "";
	memset(out, 0, sizeof(*out));
	world_test_arena_start(arena_start);
	struct edits *ed = edits_create();
	struct world *w = world_create(p, ed, err, sizeof(err));
	world_test_arena_start(0);
	struct renderer *r = renderer_create(160, 96, ANTIALIAS_AUTO, err, sizeof(err));
	struct autopilot ap;
	int rc = -1;
	if (w && r && autopilot_init(&ap, p, ed) == 0) {
		struct camera c;
		autopilot_advance(&ap, 4.0);
		autopilot_camera(&ap, &c, p->fov, 160.0f / 96.0f, p->view_distance * 1.2f);
		if (world_fill(w, p, &c, 4.0) == 0 && world_draw(w, r, &c, p, 14.0) == 0 &&
		    renderer_read(r, &out->img) == 0 && world_read_mesh(w, &out->mesh) == 0) {
			out->faults = world_check_pool(w);
			rc = 0;
		}
		if (rc == 0 && move) {
			autopilot_advance(&ap, 64.0);
			autopilot_camera(&ap, &c, p->fov, 160.0f / 96.0f, p->view_distance * 1.2f);
			struct mesh m2;
			struct image i2 = { 0 }, i3 = { 0 };
			if (world_fill(w, p, &c, 64.0) < 0 || world_draw(w, r, &c, p, 74.0) < 0 || world_read_mesh(w, &m2) < 0 ||
			    renderer_read(r, &i2) < 0)
				rc = -1;
			else
				mesh_free(&m2);
			out->faults_moved = world_check_pool(w);
			/* the evictions left holes: packing them moves meshes, and
			 * their draw commands must follow */
			out->compacted = rc == 0 ? world_test_compact(w) : -1;
			if (out->compacted >= 0 && world_draw(w, r, &c, p, 74.0) == 0 && renderer_read(r, &i3) == 0)
				out->same_compacted = !memcmp(i2.rgba, i3.rgba, (size_t)i2.width * i2.height * 4);
			out->faults_moved += world_check_pool(w);
			image_free(&i2);
			image_free(&i3);
		}
		world_get_stats(w, &out->st);
		autopilot_free(&ap);
	}
	if (rc < 0 && err[0])
		fprintf(stderr, "%s\n", err);
	renderer_destroy(r);
	world_destroy(w);
	edits_destroy(ed);
	return rc;
}

static void run_free(struct run *r)
{
	image_free(&r->img);
	mesh_free(&r->mesh);
}

static bool same_mesh(const struct mesh *a, const struct mesh *b)
{
	return a->nverts == b->nverts && a->ntris == b->ntris &&
	       !memcmp(a->pos, b->pos, sizeof(float) * 3 * a->nverts) &&
	       !memcmp(a->nrm, b->nrm, sizeof(float) * 3 * a->nverts) &&
	       !memcmp(a->idx, b->idx, sizeof(uint32_t) * 3 * a->ntris);
}

static void check_sized_to_need(const struct params *p)
{
	struct run a, b;
	CHECK(run_world(p, 0, false, &a) == 0, "world with the default arena");
	CHECK(run_world(p, 64 << 10, true, &b) == 0, "world with an arena of 64 KB chunks");
	printf("arena: default %lld KB in %d chunks of %lld KB (%lld KB used, worst case %lld KB), %llu added, %llu packed; "
	       "in 64 KB chunks: %lld KB in %d, %llu added, %llu packed, %llu evicted after the move; %u triangles, "
	       "%u vertices\n",
	       a.st.arena_bytes >> 10, a.st.arena_chunks, a.st.arena_chunk >> 10, a.st.arena_used >> 10,
	       a.st.arena_max >> 10, (unsigned long long)a.st.arena_grown, (unsigned long long)a.st.arena_packed,
	       b.st.arena_bytes >> 10, b.st.arena_chunks, (unsigned long long)b.st.arena_grown,
	       (unsigned long long)b.st.arena_packed, (unsigned long long)b.st.evicted, a.mesh.ntris, a.mesh.nverts);
	CHECK(a.mesh.ntris > 1000, "the view holds a surface (%u triangles)", a.mesh.ntris);
	CHECK(b.st.arena_grown >= 3 && b.st.arena_chunks == (int)b.st.arena_grown + 1,
	      "the 64 KB chunks: %llu added, %d in all", (unsigned long long)b.st.arena_grown, b.st.arena_chunks);
	CHECK(a.img.rgba && b.img.rgba && !memcmp(a.img.rgba, b.img.rgba, (size_t)a.img.width * a.img.height * 4),
	      "the arena of small chunks draws a different image");
	CHECK(same_mesh(&a.mesh, &b.mesh), "the arena of small chunks exports a different mesh");
	/* exactly the exported mesh, each block's range aligned to 32 bytes */
	long long mesh_bytes = (long long)a.mesh.nverts * VERTEX_BYTES + (long long)a.mesh.ntris * 12;
	int blocks = a.st.ready + a.st.pending;
	CHECK(a.st.arena_used >= mesh_bytes && a.st.arena_used <= mesh_bytes + 32LL * blocks,
	      "arena use %lld bytes for a mesh of %lld bytes in %d blocks", a.st.arena_used, mesh_bytes, blocks);
	/* a chunk added only when every chunk is more than half full (none
	 * evicted here): at most twice the meshes plus one chunk, and well
	 * under the worst case (the view, tilted down at the ground, holds
	 * about a fifth of it) */
	CHECK(a.st.evicted == 0, "the view's blocks do not fit the pool of %d slots (%llu evicted): the case tests "
				 "the arena's growth without evictions",
	      p->block_pool, (unsigned long long)a.st.evicted);
	CHECK(a.st.arena_bytes <= 2 * a.st.arena_used + a.st.arena_chunk && a.st.arena_bytes < a.st.arena_max / 2,
	      "arena of %lld KB for %lld KB of meshes: not sized to need (worst case %lld KB)", a.st.arena_bytes >> 10,
	      a.st.arena_used >> 10, a.st.arena_max >> 10);
	CHECK(a.faults == 0 && b.faults == 0, "pool faults: %d, %d", a.faults, b.faults);
	CHECK(b.st.evicted > 0, "the move evicted no block (the pool of %d slots never filled)", p->block_pool);
	CHECK(b.faults_moved == 0, "pool faults after the move and its evictions: %d", b.faults_moved);
	printf("compaction after the move: %d meshes moved\n", b.compacted);
	CHECK(b.compacted > 0, "the compaction after the evictions moved no mesh (%d)", b.compacted);
	CHECK(b.same_compacted, "the packed arena draws a different image");
	run_free(&a);
	run_free(&b);
}

/* Capacity follows the field: with slots far too small for the blocks
 * (256 triangles), every block that overflows is drawn clamped until the
 * staging slots have grown to what it needed, then generated again: the
 * world ends with no block clamped and exactly the mesh of slots that were
 * large enough from the start, and nothing written past a slot. */
static void check_over_capacity(const struct params *p_in)
{
	struct params q = *p_in;
	q.block_tris = 256; /* far below what a block of this view writes */
	struct run c, d;
	CHECK(run_world(&q, 0, true, &c) == 0, "world with 256-triangle blocks");
	CHECK(run_world(p_in, 0, false, &d) == 0, "world with the default blocks");
	printf("over capacity: slots grew %llu times, %llu blocks left clamped, %u triangles (%u with ample slots), "
	       "pool faults %d / %d\n",
	       (unsigned long long)c.st.stages_grown, (unsigned long long)c.st.overflowed, c.mesh.ntris, d.mesh.ntris,
	       c.faults, c.faults_moved);
	CHECK(c.st.stages_grown > 0, "the slots never grew from 256 triangles");
	CHECK(c.st.overflowed == 0, "%llu blocks left clamped", (unsigned long long)c.st.overflowed);
	CHECK(d.st.stages_grown == 0, "the default slots grew %llu times for the default field",
	      (unsigned long long)d.st.stages_grown);
	CHECK(c.faults == 0 && c.faults_moved == 0, "something wrote past a slot: %d, %d faults", c.faults,
	      c.faults_moved);
	CHECK(same_mesh(&c.mesh, &d.mesh), "grown slots hold another mesh (%u triangles, %u with ample slots)",
	      c.mesh.ntris, d.mesh.ntris);
	run_free(&c);
	run_free(&d);
}

/* A flight that sees a new area every frame (the autopilot 20 s further
 * each time) makes every block it sees known.  Remembered for ever, the
 * table only grows; forgotten after 5 frames unwanted, it holds at most the
 * last frames' blocks and those with a slot. */
struct table_run {
	uint32_t max_known, cap, max_wanted;
	uint64_t forgotten;
	int faults;
};

static int fly(const struct params *p, uint32_t age, struct table_run *out)
{
	char err[512] = "";
	memset(out, 0, sizeof(*out));
	struct edits *ed = edits_create();
	struct world *w = world_create(p, ed, err, sizeof(err));
	struct autopilot ap;
	int rc = -1;
	world_test_table_age(age);
	if (w && autopilot_init(&ap, p, ed) == 0) {
		rc = 0;
		for (int f = 0; f < 40 && rc == 0; f++) {
			struct camera c;
			double t = 4.0 + 20.0 * f;
			autopilot_advance(&ap, t);
			autopilot_camera(&ap, &c, p->fov, 160.0f / 96.0f, p->view_distance * 1.2f);
			rc = world_update(w, p, &c, t, true);
			struct world_stats st;
			world_get_stats(w, &st);
			if (st.blocks_known > out->max_known)
				out->max_known = st.blocks_known;
			if ((uint32_t)st.wanted > out->max_wanted)
				out->max_wanted = (uint32_t)st.wanted;
			out->cap = st.table_cap;
			out->forgotten = st.forgotten;
		}
		out->faults = world_check_pool(w);
		autopilot_free(&ap);
	}
	world_test_table_age(0);
	if (rc < 0 && err[0])
		fprintf(stderr, "%s\n", err);
	world_destroy(w);
	edits_destroy(ed);
	return rc;
}

static void check_table_bounded(const struct params *p_in)
{
	struct params q = *p_in;
	q.gen_per_frame = 1; /* planning is what is tested: few blocks made */
	struct table_run all, pruned;
	CHECK(fly(&q, 100000, &all) == 0, "flight remembering every block");
	CHECK(fly(&q, 5, &pruned) == 0, "flight forgetting blocks after 5 frames");
	printf("block table over 40 new areas: remembered %u blocks (table of %u), forgetting after 5 frames at most %u "
	       "(table of %u, %llu forgotten); at most %u wanted a frame\n",
	       all.max_known, all.cap, pruned.max_known, pruned.cap, (unsigned long long)pruned.forgotten,
	       pruned.max_wanted);
	CHECK(all.cap > 4096, "the flight did not outgrow the first table (%u blocks known)", all.max_known);
	/* pruned once over half full, keeping the blocks wanted in the last 5
	 * frames and those with a slot (fewer than half the first table's 4096
	 * here): never more than half of it plus one frame's new blocks */
	uint32_t kept = 5 * pruned.max_wanted + (uint32_t)q.block_pool;
	CHECK(kept < 2048, "the test's premise: %u blocks kept fit half the first table", kept);
	CHECK(pruned.max_known <= 2048 + pruned.max_wanted && pruned.cap == 4096,
	      "%u blocks known in a table of %u: more than half of the first table and a frame", pruned.max_known,
	      pruned.cap);
	CHECK(pruned.cap < all.cap && pruned.forgotten > 0, "the table was not bounded: %u entries (%u remembering all)",
	      pruned.cap, all.cap);
	CHECK(all.faults == 0 && pruned.faults == 0, "pool faults %d, %d", all.faults, pruned.faults);
}

int main(void)
{
	struct platform *plat = fixture_open();
	struct params p;
	pool_world(&p);
	check_sized_to_need(&p);
	check_over_capacity(&p);
	check_table_bounded(&p);
	platform_close(plat);
	return tc_done("world_pool");
}
