/* isoterra — HistoPyramid on the GPU vs a CPU prefix sum on random inputs:
 * totals, the (cell, rank) of every output key, and every cell's prefix. */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"

#include <string.h>

static uint64_t rng = 88172645463325252ull;
static uint32_t rnd(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (uint32_t)(rng >> 32);
}

static int count_of(uint8_t b, int comp)
{
	return comp == 0 ? (b & 7) : __builtin_popcount((unsigned)(b >> 3));
}

static void run_band(uint32_t n, int density_pct, int comp, uint32_t from, uint32_t to, uint32_t hint_keys)
{
	uint8_t *bytes = malloc(n ? n : 1);
	for (uint32_t i = 0; i < n; i++) {
		uint8_t b = 0;
		if (i >= from && i < to && (int)(rnd() % 100) < density_pct)
			b = (uint8_t)((rnd() % 6) | ((rnd() % 8) << 3));
		bytes[i] = b;
	}
	/* CPU expectation */
	uint32_t total[2] = { 0, 0 };
	uint32_t *prefix = malloc(4 * (size_t)(n ? n : 1));
	for (uint32_t i = 0; i < n; i++) {
		prefix[i] = total[comp];
		total[0] += (uint32_t)count_of(bytes[i], 0);
		total[1] += (uint32_t)count_of(bytes[i], 1);
	}
	size_t room = (size_t)n * (comp == 0 ? 5 : 3) + 1;
	uint32_t *kc = malloc(4 * room), *kr = malloc(4 * room), *gp = malloc(4 * (size_t)(n ? n : 1));
	uint32_t *gf = malloc(4 * (size_t)(n ? n : 1));
	uint32_t gt[2] = { 0, 0 };
	char err[512] = "";
	int rc = hp_selftest(bytes, n, comp, hint_keys, gt, kc, kr, gp, gf, err, sizeof(err));
	CHECK(rc == 0, "hp_selftest n=%u: %s", n, err);
	if (rc == 0) {
		CHECK(gt[0] == total[0] && gt[1] == total[1], "n=%u totals GPU %u/%u CPU %u/%u", n, gt[0], gt[1], total[0],
		      total[1]);
		uint32_t key = 0, bad_keys = 0, bad_prefix = 0, bad_fast = 0;
		for (uint32_t i = 0; i < n; i++) {
			for (int r = 0; r < count_of(bytes[i], comp); r++, key++)
				if (kc[key] != i || kr[key] != (uint32_t)r)
					bad_keys++;
			if (gp[i] != prefix[i])
				bad_prefix++;
			if (gf[i] != prefix[i])
				bad_fast++;
		}
		CHECK(bad_fast == 0, "n=%u comp=%d: %u wrong down-swept prefix sums", n, comp, bad_fast);
		CHECK(bad_keys == 0, "n=%u comp=%d: %u of %u keys traverse to the wrong cell/rank", n, comp, bad_keys, key);
		CHECK(bad_prefix == 0, "n=%u comp=%d: %u wrong prefix sums", n, comp, bad_prefix);
	}
	free(bytes);
	free(prefix);
	free(kc);
	free(kr);
	free(gp);
	free(gf);
}

static void run_case(uint32_t n, int density_pct, int comp)
{
	run_band(n, density_pct, comp, 0, n, 0);
}

int main(void)
{
	struct platform *p = fixture_open();
	uint32_t sizes[] = { 1, 3, 4, 5, 16, 17, 63, 64, 65, 1000, 4097, 65537, 300001 };
	for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
		run_case(sizes[i], 30, 0);
		run_case(sizes[i], 30, 1);
	}
	run_case(100000, 100, 0); /* every cell emits */
	run_case(100000, 1, 1);   /* sparse */
	run_case(4096, 0, 0);     /* nothing at all */
	/* a surface in the middle of a 128^3 grid's owner cells: long runs of
	 * empty nodes before and after */
	run_band(2146689, 3, 0, 900000, 1200000, 0);
	run_band(2146689, 3, 1, 900000, 1200000, 0);
	/* hints for the first 1000 keys only (a world stage grown past its
	 * pipeline's capacity): the keys past them searched over every node */
	run_band(2146689, 3, 0, 900000, 1200000, 1000);
	run_band(100000, 30, 1, 0, 100000, 1000);
	run_band(100000, 30, 0, 0, 100000, 64);
	/* 65 536 and 65 537 level-2 nodes: 16 and 17 halvings of the search */
	run_case(1048576, 3, 0);
	run_case(1048577, 3, 0);
	platform_close(p);
	return tc_done("histopyramid");
}
