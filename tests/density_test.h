/* isoterra — test_density: one test program in files by concern
 * (test_density.c has main and the order of the checks); what they share. */
#ifndef ISOTERRA_DENSITY_TEST_H
#define ISOTERRA_DENSITY_TEST_H

#define TCHECK_SHARED /* one pair of counters for the program (test_density.c) */
#include "tcheck.h"
#include "noise.h"

/* test_density.c: the noise tables of two seeds */
extern struct noise_set ns_a, ns_b;

/* test_density_noise.c */
void test_half(void);
void test_tables(void);
void test_perlin(void);
void test_tex_noise(void);
void test_worley(void);

#endif
