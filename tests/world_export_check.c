/* isoterra tests — checks a PLY the program exported with --scene world
 * --count 1 --export-mesh against an expectation built independently of the
 * export:
 *   world_export_check MESH.ply OPTIONS...   (the program's own options)
 * rebuilds frame 0's world with the same options (the autopilot's camera at
 * t = 0, world_fill), finds every block the world holds ready and generates
 * each one again on its own (world_block_mesh: the pipeline's own buffers,
 * not the pool the export reads), then checks
 *   - the file's triangle count equals the sum of those blocks' triangles;
 *   - every vertex lies inside one of those blocks;
 *   - every triangle is one of a cell (no side longer than its diagonal);
 *   - every vertex is where Marching Cubes puts it by the CPU reference of
 *     the density (density_ref): on a lattice edge of the block grid whose
 *     two corners' densities straddle the iso level, at the linear
 *     interpolation of those densities (within 0.02 cells).
 * One level of detail only (lod_levels = 1): coarser levels are generated
 * eroded by lod_bias, which world_block_mesh does not reproduce. */
#include "app.h"
#include "world.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct ready {
	float lo[3], hi[3];
	uint32_t tris;
};

/* Frame 0 of the world scene: the blocks ready after world_fill. */
static int ready_blocks(const struct params *p, struct ready **out, int *n)
{
	char err[512];
	int w, h;
	struct edits *ed = edits_create();
	struct world *wd = ed ? world_create(p, ed, err, sizeof(err)) : NULL;
	struct autopilot ap;
	if (cli_parse_size(p->size, &w, &h) < 0 || !wd || autopilot_init(&ap, p, ed) < 0) {
		fprintf(stderr, "world: %s\n", err);
		world_destroy(wd);
		edits_destroy(ed);
		return -1;
	}
	struct camera cam;
	autopilot_advance(&ap, 0.0);
	autopilot_camera(&ap, &cam, p->fov, (float)w / (float)h, p->view_distance * 1.2f);
	int rc = world_fill(wd, p, &cam, 0.0);
	float s = p->block_size;
	int r = (int)ceilf(p->view_distance / s) + 3, cap = 0;
	*n = 0;
	*out = NULL;
	for (int z = -r; z <= r && rc == 0; z++)
		for (int y = -r; y <= r && rc == 0; y++)
			for (int x = -r; x <= r && rc == 0; x++) {
				int idx[3] = { (int)floorf(cam.eye[0] / s) + x, (int)floorf(cam.eye[1] / s) + y,
					       (int)floorf(cam.eye[2] / s) + z };
				int state;
				if (world_block_generations(wd, 0, idx, &state) < 0 || state != 2)
					continue;
				struct mesh m;
				if (world_block_mesh(wd, p, 0, idx, &m) < 0) {
					rc = -1;
					break;
				}
				if (*n == cap) {
					cap = cap ? 2 * cap : 64;
					*out = realloc(*out, sizeof(**out) * (size_t)cap);
				}
				struct ready *b = &(*out)[(*n)++];
				for (int a = 0; a < 3; a++) {
					b->lo[a] = (float)idx[a] * s;
					b->hi[a] = b->lo[a] + s;
				}
				b->tris = m.ntris;
				mesh_free(&m);
			}
	autopilot_free(&ap);
	world_destroy(wd);
	edits_destroy(ed);
	return rc;
}

static bool inside(const struct ready *b, int n, const float *v, float eps)
{
	for (int i = 0; i < n; i++)
		if (v[0] >= b[i].lo[0] - eps && v[0] <= b[i].hi[0] + eps && v[1] >= b[i].lo[1] - eps &&
		    v[1] <= b[i].hi[1] + eps && v[2] >= b[i].lo[2] - eps && v[2] <= b[i].hi[2] + eps)
			return true;
	return false;
}

/* A vertex against the CPU reference: on the lattice edge of the grid of
 * cell size `cell` it lies on (two coordinates on lattice planes), between
 * corners whose densities straddle iso, at their linear interpolation.
 * Returns the position error in cells, or INFINITY when the vertex is on no
 * edge or the corners do not straddle iso. */
static double edge_error(const struct params *p, const struct noise_set *ns, const float *v, float cell)
{
	int axis = -1;
	double c[3];
	for (int a = 0; a < 3; a++) {
		double u = (double)v[a] / cell, r = u - floor(u + 0.5);
		c[a] = floor(u + 0.5);
		if (fabs(r) > 1e-3) {
			if (axis >= 0)
				return INFINITY; /* off the lattice in two axes */
			axis = a;
			c[a] = floor(u);
		}
	}
	if (axis < 0)
		return 0.0; /* on a corner: the corner is at the iso level */
	float lo[3] = { (float)(c[0] * cell), (float)(c[1] * cell), (float)(c[2] * cell) }, hi[3];
	memcpy(hi, lo, sizeof(hi));
	hi[axis] += cell;
	double d0 = density_ref(p, ns, NULL, lo[0], lo[1], lo[2]) - p->iso;
	double d1 = density_ref(p, ns, NULL, hi[0], hi[1], hi[2]) - p->iso;
	if ((d0 > 0) == (d1 > 0))
		return INFINITY;
	double t = d0 / (d0 - d1);
	return fabs(((double)v[axis] - lo[axis]) / cell - t);
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		fprintf(stderr, "usage: world_export_check MESH.ply OPTIONS...\n");
		return 2;
	}
	struct params p;
	char err[512];
	const char *ply = argv[1];
	argv[1] = argv[0];
	if (cli_parse(argc - 1, argv + 1, &p, err, sizeof(err)) != CLI_RUN || p.scene != SCENE_WORLD ||
	    p.lod_levels != 1) {
		fprintf(stderr, "world_export_check: the options of a --scene world --lod-levels 1 run, please (%s)\n", err);
		return 2;
	}
	struct platform *plat = fixture_open();
	shader_set_dir(p.shader_dir);
	struct mesh m;
	struct ready *blocks = NULL;
	int nb = 0;
	if (ply_read(&m, ply, err, sizeof(err)) < 0 || ready_blocks(&p, &blocks, &nb) < 0) {
		CHECK(0, "%s: %s", ply, err[0] ? err : "rebuilding frame 0's world failed");
		return tc_done("world_export");
	}
	uint64_t expect = 0;
	for (int i = 0; i < nb; i++)
		expect += blocks[i].tris;
	printf("%s: %u triangles, %u vertices; the world: %d blocks ready, %llu triangles\n", ply, m.ntris, m.nverts,
	       nb, (unsigned long long)expect);
	CHECK(nb > 0 && m.ntris > 0, "a surface was exported");
	CHECK(m.ntris == expect, "exported %u triangles, the blocks hold %llu", m.ntris, (unsigned long long)expect);
	static struct noise_set ns;
	noise_set_init(&ns, p.seed);
	struct params q = p;
	q.closed = false; /* as the world generates its blocks */
	float cell = p.block_size / (float)p.block_cells;
	uint32_t outside = 0, off = 0;
	double worst = 0;
	for (uint32_t i = 0; i < m.nverts; i++) {
		const float *v = m.pos + 3 * (size_t)i;
		outside += !inside(blocks, nb, v, 1e-3f * cell);
		double o = edge_error(&q, &ns, v, cell);
		worst = o > worst ? o : worst;
		off += !(o <= 0.02);
	}
	printf("vertices not where the CPU reference puts them (0.02 cells): %u of %u (worst %.4f cells)\n", off,
	       m.nverts, worst);
	CHECK(outside == 0, "%u of %u vertices outside the ready blocks", outside, m.nverts);
	CHECK(off == 0, "%u of %u vertices off their lattice edge's iso crossing (worst %.4f cells)", off, m.nverts,
	      worst);
	/* a Marching Cubes triangle joins points on the edges of one cell: each
	 * of its sides is at most a cell's diagonal (sqrt 3) long */
	uint32_t bad = 0, long_sides = 0;
	for (uint32_t t = 0; t < m.ntris; t++) {
		const uint32_t *i3 = m.idx + 3 * (size_t)t;
		if (i3[0] >= m.nverts || i3[1] >= m.nverts || i3[2] >= m.nverts) {
			bad++;
			continue;
		}
		for (int e = 0; e < 3; e++) {
			const float *a = m.pos + 3 * (size_t)i3[e], *b = m.pos + 3 * (size_t)i3[(e + 1) % 3];
			float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
			long_sides += sqrtf(dx * dx + dy * dy + dz * dz) > 1.733f * cell;
		}
	}
	CHECK(bad == 0, "%u triangles with indices past the vertices", bad);
	CHECK(long_sides == 0, "%u triangle sides longer than a cell's diagonal", long_sides);
	free(blocks);
	mesh_free(&m);
	platform_close(plat);
	return tc_done("world_export");
}
