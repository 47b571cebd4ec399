/* isoterra — bench_pipeline's peers on the same field and grid: libnoise's
 * Perlin module as the same fBm (the density pass's samples, margin
 * included) and VTK's flying edges on the corners of the grid, once on
 * isoterra's own density volume (read back from the GPU: identical
 * samples, so the triangle counts must agree) and once on libnoise's. */
#include "bench_pipeline.h"
#include "peer.h"
#include "terrain.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct peers {
	struct peer_fbm fbm;
	float *lib_vol;   /* the density pass's samples, by libnoise */
	float *vols[2];   /* the grid's corners: isoterra's (read back), libnoise's */
	int nvol, corners[3];
	struct peer_vtk *vtk;
	struct series s[PEER_SERIES];
	struct series *lib, *fe[2];
	double sigma_iso, sigma_lib;
	long samples;
};

/* Why libnoise's Perlin module cannot compute field p (NULL: it can). */
static const char *field_mismatch(const struct params *p)
{
	if (p->field != FIELD_TERRAIN || p->shape != SHAPE_GROUND || p->noise != NOISE_ALU)
		return "field, shape or noise other than terrain, ground, alu";
	if (p->fractal != FRACTAL_FBM && p->fractal != FRACTAL_GEISS)
		return "a fractal family other than fbm or geiss (libnoise's Perlin module is a plain sum)";
	if (p->warp_amp != 0 || p->floor_strength != 0 || p->rotated_octaves != 0)
		return "domain warp, hard floor or rotated octaves on (--warp-amp 0 --floor-strength 0 --rotated-octaves 0)";
	if (p->noise_y_scale != 1)
		return "noise stretched along y (--noise-y-scale 1: libnoise's module is isotropic)";
	if (p->closed)
		return "a closed volume (--no-closed)";
	if (p->terrace != TERRACE_OFF || p->shelf != SHELF_OFF || p->flat_spot || p->curves[0] || p->heightmap[0])
		return "terraces, a shelf, a flat spot, curves or a heightmap";
	if (p->scroll_speed * p->time != 0)
		return "a scrolled field (--time, --scroll-speed)";
	return NULL;
}

/* The standard deviation of isoterra's basis (one octave of improved
 * Perlin noise) over the points peer_libnoise_basis_std samples. */
static double iso_basis_std(int seed, int n)
{
	struct noise_set *ns = malloc(sizeof(*ns));
	if (!ns)
		return 0;
	noise_set_init(ns, seed);
	unsigned s = 12345u;
	double sum = 0, sum2 = 0;
	for (int i = 0; i < n; i++) {
		float c[3];
		for (int k = 0; k < 3; k++) {
			s = s * 1664525u + 1013904223u;
			c[k] = (float)((s >> 8) * (256.0 / 16777216.0));
		}
		double v = noise_perlin(ns, c[0], c[1], c[2]);
		sum += v;
		sum2 += v * v;
	}
	free(ns);
	double mean = sum / n;
	return sqrt(sum2 / n - mean * mean);
}

/* The corners (0..n per axis) out of a volume with a margin of m samples. */
static float *corners_of(const float *vol, const struct grid *g, const int c[3])
{
	float *out = malloc((size_t)c[0] * c[1] * c[2] * sizeof(float));
	if (!out)
		return NULL;
	for (int k = 0; k < c[2]; k++)
		for (int j = 0; j < c[1]; j++)
			for (int i = 0; i < c[0]; i++)
				out[((size_t)k * c[1] + j) * c[0] + i] = vol[grid_dens_index(g, i, j, k)];
	return out;
}

static int run_libnoise(struct series *s, struct run_sample *o)
{
	struct peers *pe = s->ctx;
	double t0 = clock_ms(), c0 = bench_cpu_ms();
	int rc = peer_libnoise_volume(&pe->fbm, pe->lib_vol);
	o->wall = clock_ms() - t0;
	o->cpu = bench_cpu_ms() - c0;
	return rc;
}

static int run_flying_edges(struct series *s, struct run_sample *o)
{
	struct peers *pe = s->ctx;
	return peer_vtk_run(pe->vtk, s->k, &o->wall, &o->cpu, &s->triangles, &s->vertices);
}

static struct series *add_series(struct peers *pe, int i, const char *name, int (*run)(struct series *, struct run_sample *),
				 int k)
{
	struct series *s = &pe->s[i];
	s->name = name;
	s->run = run;
	s->ctx = pe;
	s->k = k;
	s->triangles = s->vertices = -1;
	return s;
}

/* libnoise's fBm of field p at the density pass's samples of grid g. */
static int open_libnoise(struct peers *pe, const struct params *p, const struct grid *g, int threads)
{
	const char *missing = peer_libnoise_missing();
	if (missing) {
		printf("  %s\n", missing);
		return 0;
	}
	int m = grid_margin(g);
	struct peer_fbm *f = &pe->fbm;
	f->octaves = p->octaves;
	f->seed = p->seed;
	f->freq = p->noise_freq;
	f->lacunarity = p->lacunarity;
	f->persistence = p->fractal == FRACTAL_FBM ? pow(p->lacunarity, -p->hurst) : p->gain;
	pe->sigma_iso = iso_basis_std(p->seed, 200000);
	pe->sigma_lib = peer_libnoise_basis_std(p->seed, 200000);
	f->amp = p->noise_amp * pe->sigma_iso / pe->sigma_lib;
	f->slope = p->ground_slope;
	f->cell = g->cell;
	f->dims[0] = g->nx + 1 + 2 * m;
	f->dims[1] = g->ny + 1 + 2 * m;
	f->dims[2] = g->nz + 1 + 2 * m;
	for (int a = 0; a < 3; a++)
		f->origin[a] = g->origin[a] + (g->base[a] - m) * g->cell;
	f->threads = threads;
	pe->samples = (long)f->dims[0] * f->dims[1] * f->dims[2];
	pe->lib_vol = malloc((size_t)pe->samples * sizeof(float));
	if (!pe->lib_vol || peer_libnoise_volume(f, pe->lib_vol) < 0 || !(pe->vols[1] = corners_of(pe->lib_vol, g, pe->corners))) {
		printf("  libnoise peer skipped: its volume could not be computed (out of memory?)\n");
		return 0;
	}
	printf("  libnoise 1.0 Perlin module: %d octaves, frequency %g, lacunarity %g, persistence %.5f, seed %d,\n"
	       "    QUALITY_BEST (quintic), %d threads, %ld samples (isoterra's density pass: the grid's corners + margin);\n"
	       "    d = -%g y + %g * Perlin: noise_amp %g x (std of one octave: isoterra %.4f / libnoise %.4f)\n",
	       f->octaves, f->freq, f->lacunarity, f->persistence, f->seed, threads, pe->samples, f->slope, f->amp,
	       p->noise_amp, pe->sigma_iso, pe->sigma_lib);
	pe->lib = add_series(pe, 0, "libnoise", run_libnoise, 0);
	return 1;
}

/* flying edges on isoterra's corners (read back from pl) and libnoise's. */
static void open_vtk(struct peers *pe, const struct params *p, const struct grid *g, struct pipeline *pl, int threads)
{
	float *dens = malloc((size_t)grid_dens_count(g) * sizeof(float));
	if (!dens || bench_density(pl, p) < 0 || pipeline_read_density(pl, dens) < 0 ||
	    !(pe->vols[0] = corners_of(dens, g, pe->corners))) {
		printf("  VTK peer skipped: isoterra's density volume could not be read back\n");
		free(dens);
		return;
	}
	free(dens);
	const float *vols[2] = { pe->vols[0], pe->vols[1] };
	char err[256];
	pe->vtk = peer_vtk_open(vols, pe->vols[1] ? 2 : 1, pe->corners, p->iso, threads, err, sizeof(err));
	if (!pe->vtk) {
		printf("  %s: VTK peer skipped\n", err);
		return;
	}
	printf("  vtkFlyingEdges3D (%s): normals on, contour %g, on the grid's %d x %d x %d corners\n",
	       peer_vtk_info(pe->vtk), p->iso, pe->corners[0], pe->corners[1], pe->corners[2]);
	pe->fe[0] = add_series(pe, 1, "flying edges, isoterra's volume", run_flying_edges, 0);
	if (pe->vols[1])
		pe->fe[1] = add_series(pe, 2, "flying edges, libnoise's volume", run_flying_edges, 1);
}

struct peers *peers_open(const struct params *p, const struct grid *g, struct pipeline *pl, int threads,
			 struct series **s, int *ns)
{
	printf("\npeers, same field and grid:\n");
	struct peers *pe = calloc(1, sizeof(*pe));
	if (!pe)
		return NULL;
	pe->corners[0] = g->nx + 1;
	pe->corners[1] = g->ny + 1;
	pe->corners[2] = g->nz + 1;
	const char *why = field_mismatch(p);
	if (why)
		printf("  libnoise peer skipped: its Perlin fBm does not compute this field: %s\n", why);
	else
		open_libnoise(pe, p, g, threads);
	open_vtk(pe, p, g, pl, threads);
	if (!pe->lib && !pe->fe[0]) {
		peers_close(pe);
		return NULL;
	}
	for (int i = 0; i < PEER_SERIES; i++)
		if (pe->s[i].run)
			s[(*ns)++] = &pe->s[i];
	return pe;
}

static bool usable(const struct series *s)
{
	return s && !s->failed && s->n > 0;
}

static const char *num(double v, const char *fmt, char *buf, size_t len)
{
	if (isnan(v))
		snprintf(buf, len, "-");
	else
		snprintf(buf, len, fmt, v);
	return buf;
}

/* One line: the peer's wall and CPU, isoterra's, the ratios (NAN: none). */
static void ratio_line(const char *what, struct bench_stat pw, double pc, struct bench_stat iw, double ic)
{
	char a[64], b[64], c[4][32];
	printf("  %-30s %-26s %9s  %-26s %9s  %6.3f  %6s\n", what, bench_stat_str(pw, 1, a, sizeof(a)),
	       num(pc, "%.1f", c[0], sizeof(c[0])), bench_stat_str(iw, 1, b, sizeof(b)), num(ic, "%.1f", c[1], sizeof(c[1])),
	       iw.med / pw.med, num(ic / pc, "%.3f", c[2], sizeof(c[2])));
}

void peers_report(const struct peers *pe, const struct series *iso_density, const struct series *iso_profiled,
		  const struct series *iso_full)
{
	if (!pe)
		return;
	printf("\npeers vs isoterra (isoterra without AO and shadows: the peers compute neither), ms median [min-max], ratio = isoterra / peer:\n");
	printf("  %-30s %-26s %9s  %-26s %9s  %6s  %6s\n", "", "peer wall", "peer CPU", "isoterra wall", "iso CPU", "wall",
	       "CPU");
	struct bench_stat lw = { 0 }, fw = { 0 };
	double lc = 0, fc = 0;
	if (usable(pe->lib)) {
		lw = series_stat(pe->lib, V_WALL);
		lc = series_stat(pe->lib, V_CPU).med;
		ratio_line("density: libnoise", lw, lc, series_stat(iso_density, V_WALL), series_stat(iso_density, V_CPU).med);
	}
	if (usable(pe->fe[0]))
		ratio_line("after density: flying edges", series_stat(pe->fe[0], V_WALL), series_stat(pe->fe[0], V_CPU).med,
			   series_stat(iso_profiled, V_AFTER_DENSITY),
			   series_stat(iso_full, V_CPU).med - series_stat(iso_density, V_CPU).med);
	if (usable(pe->lib) && usable(pe->fe[1])) {
		fw = series_stat(pe->fe[1], V_WALL);
		fc = series_stat(pe->fe[1], V_CPU).med;
		struct bench_stat sum = { lw.med + fw.med, lw.min + fw.min, lw.max + fw.max, lw.n };
		ratio_line("whole: libnoise + flying edges", sum, lc + fc, series_stat(iso_full, V_WALL),
			   series_stat(iso_full, V_CPU).med);
	}
	printf("  (after density, isoterra: wall = classify + pyramid + vertices + indices of the profiled runs,\n"
	       "   CPU = whole run's CPU - density pass's CPU (medians).  whole, peer: the sums of the two medians,\n"
	       "   of the minima and of the maxima.  flying edges times one Update() in its own process)\n");
	printf("  triangles: isoterra %ld", iso_full->triangles);
	if (pe->fe[0])
		printf(", flying edges on isoterra's volume %ld", pe->fe[0]->triangles);
	if (pe->fe[1])
		printf(", flying edges on libnoise's volume %ld", pe->fe[1]->triangles);
	printf("\n  vertices:  isoterra %ld", iso_full->vertices);
	if (pe->fe[0])
		printf(", flying edges on isoterra's volume %ld", pe->fe[0]->vertices);
	if (pe->fe[1])
		printf(", on libnoise's %ld", pe->fe[1]->vertices);
	printf("\n");
}

void peers_close(struct peers *pe)
{
	if (!pe)
		return;
	peer_vtk_close(pe->vtk);
	free(pe->lib_vol);
	free(pe->vols[0]);
	free(pe->vols[1]);
	free(pe);
}
