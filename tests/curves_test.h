/* isoterra — test_curves: one test program in files by concern
 * (test_curves.c has main and the order of the checks); what they share. */
#ifndef ISOTERRA_CURVES_TEST_H
#define ISOTERRA_CURVES_TEST_H

#define TCHECK_SHARED /* one pair of counters for the program (test_curves.c) */
#include "app.h"
#include "tcheck.h"

/* test_curves.c: the helpers */
float frand(void); /* [0,1) */
float frange(float a, float b);
void set(struct params *p, const char *kv);
struct curve_path make_path(int n, const float *pts, float w, float lam, float incl, float om);
void qeval(const float c[3][4], double t, double *x, double *z);
double qdist2(const float c[3][4], double t, double px, double pz);
double brute_dist(const float c[3][4], double px, double pz);
void random_set(struct curve_set *s, int npaths, float extent);
extern char tmpdir[]; /* the files the tests write */

/* test_curves_cpu.c */
int make_closest_cases(float *items, int max);
void test_closest_cpu(const float *items, int n, double *worst);
void test_pipeline_cpu(void);
void test_hash_cpu(void);
void test_hash_vs_brute_eval(struct edits *ed);
void test_affected(struct edits *ed);
void test_tunnel_cpu(struct edits *ed);

/* test_curves_files.c */
void test_io(void);
void test_geojson_skips(void);
void test_road_widths(void);
void test_structures(void);
void test_areas(void);
void test_sizes(void);
void test_geo(void);
void test_gpx(void);
void test_flat_zero(void);
void test_inside_fraction(void);
void test_geo_terrain(void);
void test_heightmap_cpu(struct edits *ed, struct params *p, const struct noise_set *ns);

/* test_curves_gpu.c */
void test_closest_gpu(struct edits *ed, const struct params *p, const float *items, int n);
void test_eval_gpu(struct edits *ed, struct params *p);
void test_heightmap_gpu(struct edits *ed, struct params *p, const struct noise_set *ns);
void check_density(struct edits *ed, const char *what, const struct params *p, int gridn);
void test_road_centreline(struct edits *ed);
void test_world_edits(struct edits *ed);

#endif
