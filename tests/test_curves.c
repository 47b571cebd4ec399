/* isoterra — curves (roads, rivers, railways) and heightmaps.
 *
 * CPU: the curve pipeline (cubic handles and C1 continuity, inflection
 * split, degree reduction with its degenerate cases, quadratics close to
 * their cubics, inclination from curvature), the closed-form closest point
 * against a brute-force distance (dense sampling + golden-section
 * refinement in double) on random and near-degenerate curves, the spatial
 * hash against a brute-force box test and against the influence of every
 * curve, carving with the hash == carving without it, the affected-region
 * API (every density change lies inside the reported box), GeoJSON / CSV
 * parsing (good files and malformed ones: message with file:line), the
 * heightmap (16-bit PNG round trip, fractal interpolation exact at the
 * samples, detail between them).
 *
 * GPU (llvmpipe): closest point vs brute force, curve evaluation through
 * the GPU hash vs the CPU mirror, heightmap heights vs the mirror, the
 * density pass with curves / heightmap vs density_ref_volume, the 2D
 * displacement bake vs the CPU bake (and the iterative baseline close to
 * the analytic one), and the real pipeline: a road's centre line after
 * carving lies at the curve height +- one voxel in the extracted mesh, where
 * the uncarved terrain was both above (cut) and below (fill) the road.
 * The streaming world: a road added, raised and removed re-generates
 * exactly the known blocks whose samples the CPU carve reaches (none
 * missed, none outside the path's padded box, under half the view).
 * GeoTIFF through GDAL when the build has it.
 *
 * One program in four files: this one (the shared helpers, the order of
 * the checks), test_curves_cpu.c (the curve pipeline, closest point,
 * spatial hash, affected region, the tunnel's carve), test_curves_files.c
 * (GeoJSON / CSV, sizes, geographic input, heightmaps on the CPU) and
 * test_curves_gpu.c (everything on the GPU, the streaming world). */
#include "curves_test.h"
#include "gpu_fixture.h"
#include "world.h"
#include "terrain.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>
#include <unistd.h>

/* the program's counters (tcheck.h), shared by its files */
int tc_pass, tc_fail;

static uint32_t rng = 12345u;
float frand(void) /* [0,1) */
{
	rng = rng * 1664525u + 1013904223u;
	return (float)(rng >> 8) / 16777216.0f;
}
float frange(float a, float b)
{
	return a + (b - a) * frand();
}

void set(struct params *p, const char *kv)
{
	char buf[1024], err[256];
	snprintf(buf, sizeof(buf), "%s", kv);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
		char *eq = strchr(tok, '=');
		if (!eq)
			continue;
		*eq = 0;
		int rc = params_set(p, tok, eq + 1, err, sizeof(err));
		CHECK(rc == 0, "params_set %s: %s", tok, err);
	}
}

struct curve_path make_path(int n, const float *pts, float w, float lam, float incl, float om)
{
	struct curve_path p;
	memset(&p, 0, sizeof(p));
	curve_path_defaults(&p, CURVE_ROAD);
	p.width = w;
	p.falloff = lam;
	p.inclination = incl;
	p.smoothing = om;
	p.npts = n;
	p.pts = (float *)pts;
	snprintf(p.label, sizeof(p.label), "test path");
	return p;
}

/* ---- brute-force distance (double) ------------------------------------------ */

void qeval(const float c[3][4], double t, double *x, double *z)
{
	double u = 1.0 - t;
	*x = u * u * c[0][0] + 2 * u * t * c[1][0] + t * t * c[2][0];
	*z = u * u * c[0][2] + 2 * u * t * c[1][2] + t * t * c[2][2];
}

double qdist2(const float c[3][4], double t, double px, double pz)
{
	double x, z;
	qeval(c, t, &x, &z);
	return (x - px) * (x - px) + (z - pz) * (z - pz);
}

double brute_dist(const float c[3][4], double px, double pz)
{
	const int N = 4000;
	int bi = 0;
	double bd = DBL_MAX;
	for (int i = 0; i <= N; i++) {
		double d = qdist2(c, (double)i / N, px, pz);
		if (d < bd) {
			bd = d;
			bi = i;
		}
	}
	double a = fmax(0.0, (bi - 1.0) / N), b = fmin(1.0, (bi + 1.0) / N);
	for (int it = 0; it < 80; it++) { /* golden section */
		double m1 = a + (b - a) * 0.381966, m2 = a + (b - a) * 0.618034;
		if (qdist2(c, m1, px, pz) < qdist2(c, m2, px, pz))
			b = m2;
		else
			a = m1;
	}
	bd = fmin(bd, qdist2(c, 0.5 * (a + b), px, pz));
	return sqrt(bd);
}

/* ---- random curve sets ----------------------------------------------------------- */

void random_set(struct curve_set *s, int npaths, float extent)
{
	memset(s, 0, sizeof(*s));
	for (int i = 0; i < npaths; i++) {
		int n = 2 + (int)(frand() * 8);
		float pts[10 * 3];
		float x = frange(-extent, extent), z = frange(-extent, extent), a = frange(0, 6.28f);
		for (int k = 0; k < n; k++) {
			pts[3 * k] = x;
			pts[3 * k + 1] = frange(-5, 5);
			pts[3 * k + 2] = z;
			a += frange(-1.2f, 1.2f);
			float l = frange(5, extent * 0.3f);
			x += l * cosf(a);
			z += l * sinf(a);
		}
		struct curve_path p = make_path(n, pts, frange(2, 12), frange(0, 10), frange(-20, 20), frand());
		p.kind = i % CURVE_KIND_COUNT;
		CHECK(curve_set_add(s, &p) == 0, "curve_set_add");
	}
}

char tmpdir[] = "/tmp/isoterra-curves-XXXXXX";

int main(void)
{
	if (!mkdtemp(tmpdir)) {
		perror("mkdtemp");
		return 1;
	}
	struct edits *ed = edits_create();
	test_pipeline_cpu();
	test_hash_cpu();
	test_hash_vs_brute_eval(ed);
	test_affected(ed);
	test_io();
	test_geojson_skips();
	test_road_widths();
	test_structures();
	test_areas();
	test_sizes();
	int ncases = 1200;
	float *items = malloc(sizeof(float) * 16 * (size_t)ncases);
	ncases = make_closest_cases(items, ncases);
	double worst_cpu;
	test_closest_cpu(items, ncases, &worst_cpu);
	printf("  closest point on the CPU: %d cases, worst error %.3g\n", ncases, worst_cpu);

	static struct noise_set ns;
	struct params p;
	params_defaults(&p);
	noise_set_init(&ns, p.seed);
	test_heightmap_cpu(ed, &p, &ns);
	test_tunnel_cpu(ed);
	test_geo();
	test_gpx();
	test_flat_zero();
	test_inside_fraction();
	test_geo_terrain();

	struct platform *plat = fixture_open();
	test_heightmap_gpu(ed, &p, &ns);
	/* density pass: heightmap field with detail, 3D noise and a river */
	{
		float riv[4 * 3] = { -8, -6, -8, -2, -7, 0, 3, -8, 3, 8, -9, 9 };
		struct curve_path rp = make_path(4, riv, 3, 2, 5, 0.7f);
		rp.kind = CURVE_RIVER;
		struct curve_set rs = { .paths = &rp, .npaths = 1 };
		char err[256];
		CHECK(edits_set_curves(ed, &rs, 8, err, sizeof(err)) == 0, "river: %s", err);
		set(&p, "heightmap_noise=0.2;octaves=3;vol_size=16;vol_y=-2;closed=false");
		check_density(ed, "heightmap + detail + noise + river", &p, 24);
	}
	edits_clear(ed);
	params_defaults(&p);
	{
		struct curve_set s;
		random_set(&s, 4, 20.0f);
		char err[256];
		CHECK(edits_set_curves(ed, &s, 16, err, sizeof(err)) == 0, "curves: %s", err);
		set(&p, "octaves=4;curve_incl_lo=0.2;curve_incl_hi=0.8");
		check_density(ed, "terrain + 4 random curves", &p, 24);
		curve_set_free(&s);
		edits_clear(ed);
		params_defaults(&p);
	}
	/* a dense network (a town's roads: 600 paths in the volume, bridges
	 * and tunnels among them): the auto-sized hash keeps every cell within
	 * CURVE_CELL_MAX pieces, so a software rasterizer's loop limit (65535
	 * iterations an invocation) loses no sample of the density pass */
	{
		struct curve_set s;
		random_set(&s, 600, 40.0f);
		for (int i = 0; i < s.npaths; i++) { /* streets: 2 .. 4 wide */
			s.paths[i].width = frange(2, 4);
			s.paths[i].falloff = frange(1, 3);
		}
		char err[256];
		CHECK(edits_set_curves(ed, &s, 0, err, sizeof(err)) == 0, "dense network: %s", err);
		printf("  dense network: %d pieces, hash %dx%d, at most %d a cell\n", ed->quads.nquads, ed->hash.dim,
		       ed->hash.dim, ed->hash.max_per_cell);
		CHECK(ed->hash.max_per_cell <= CURVE_CELL_MAX, "dense network: %d pieces in a cell, more than %d",
		      ed->hash.max_per_cell, CURVE_CELL_MAX);
		set(&p, "octaves=4");
		check_density(ed, "terrain + a dense network", &p, 24);
		curve_set_free(&s);
		edits_clear(ed);
		params_defaults(&p);
	}
	/* a tunnel through the terrain beside a road: the tube, its embankment,
	 * the road's blend skipping the tunnel */
	{
		float tun[4 * 3] = { -14, -3, -6, -4, -2, -1, 5, -1, 2, 14, 0, 7 };
		float road[3 * 3] = { -14, 1, 8, 0, 2, 4, 14, 2, -6 };
		struct curve_path tp[2] = { make_path(4, tun, 5, 3, 0, 0.5f), make_path(3, road, 4, 3, 0, 0.5f) };
		tp[0].kind = CURVE_TUNNEL;
		struct curve_set ts = { .paths = tp, .npaths = 2 };
		char err[256];
		CHECK(edits_set_curves(ed, &ts, 8, err, sizeof(err)) == 0, "tunnel and road: %s", err);
		set(&p, "octaves=4");
		check_density(ed, "terrain + tunnel + road", &p, 24);
		edits_clear(ed);
		params_defaults(&p);
	}
	test_closest_gpu(ed, &p, items, ncases);
	test_eval_gpu(ed, &p);
	edits_gl_release(ed);
	test_road_centreline(ed);
	edits_gl_release(ed);
	test_world_edits(ed);
	free(items);
	edits_destroy(ed);
	platform_close(plat);
	char cmd[300];
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		fprintf(stderr, "warning: could not remove %s\n", tmpdir);
	return tc_done("curves");
}
