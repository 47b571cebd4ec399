/* isoterra — the rotary encoder decoder (hal/rotary.c): both directions,
 * every illegal jump, contact bounce, missed edges, steps per detent,
 * acceleration.  Direction +1 is the Gray sequence 00 01 11 10 (B leads). */
#include "rotary.h"
#include "tcheck.h"

#include <math.h>
#include <stdint.h>

#define MS 1000000ull
#define US 1000ull

static const int gray_a[4] = { 0, 0, 1, 1 }; /* binary position -> gray (a, b) */
static const int gray_b[4] = { 0, 1, 1, 0 };

static struct rotary_config cfg(int spd, uint64_t db, uint64_t accel_ns, int accel_max)
{
	struct rotary_config c = { .steps_per_detent = spd, .debounce_ns = db, .accel_ns = accel_ns, .accel_max = accel_max };
	return c;
}

/* One quarter step from binary position *pos in direction dir as an edge at
 * time *t (advanced by dt). */
static void step_edge(struct rotary *r, int *pos, int dir, uint64_t *t, uint64_t dt)
{
	int np = ((*pos + dir) % 4 + 4) % 4;
	int line = gray_a[np] != gray_a[*pos] ? 0 : 1;
	int level = line == 0 ? gray_a[np] : gray_b[np];
	*t += dt;
	rotary_edge(r, line, level, *t);
	*pos = np;
}

static void test_directions(void)
{
	static const int spds[3] = { 1, 2, 4 };
	for (int k = 0; k < 3; k++) {
		int spd = spds[k];
		for (int dir = -1; dir <= 1; dir += 2) {
			struct rotary r;
			struct rotary_config c = cfg(spd, 0, 0, 1);
			CHECK(rotary_init(&r, &c, 0, 0), "init spd %d", spd);
			int pos = 0, total = 0;
			uint64_t t = 0;
			for (int q = 0; q < 40; q++) {
				step_edge(&r, &pos, dir, &t, 100 * MS);
				int d = rotary_take(&r);
				/* a detent exactly when the quarter count reaches a multiple of spd */
				int want = (q + 1) % spd == 0 ? dir : 0;
				CHECK(d == want, "spd %d dir %d quarter %d: got %d detents, want %d", spd, dir, q, d, want);
				total += d;
			}
			CHECK(total == dir * 40 / spd, "spd %d dir %d: total %d", spd, dir, total);
			CHECK(r.illegal == 0 && r.steps == 40, "spd %d: illegal %lu steps %lu", spd, r.illegal, r.steps);
		}
	}
	/* the same through rotary_sample (levels read together) */
	struct rotary r;
	struct rotary_config c = cfg(4, 0, 0, 1);
	rotary_init(&r, &c, 0, 0);
	int total = 0;
	for (int q = 1; q <= 12; q++) {
		rotary_sample(&r, gray_a[q % 4], gray_b[q % 4], (uint64_t)q * 50 * MS);
		total += rotary_take(&r);
	}
	CHECK(total == 3, "3 full periods forward by samples: %d", total);
	for (int q = 11; q >= 0; q--) {
		rotary_sample(&r, gray_a[q % 4], gray_b[q % 4], (uint64_t)(30 - q) * 50 * MS);
		total += rotary_take(&r);
	}
	CHECK(total == 0, "and back: %d", total);
	CHECK(rotary_gray2bin(0, 0) == 0 && rotary_gray2bin(0, 1) == 1 && rotary_gray2bin(1, 1) == 2 &&
		      rotary_gray2bin(1, 0) == 3, "gray to binary");
}

static void test_illegal(void)
{
	/* every two-step jump, from every state, through samples and through
	 * simultaneous edges; each is rejected and the decoder resynchronises */
	for (int s = 0; s < 4; s++) {
		for (int via_edges = 0; via_edges < 2; via_edges++) {
			struct rotary r;
			struct rotary_config c = cfg(1, via_edges ? 1 * MS : 0, 0, 1);
			rotary_init(&r, &c, gray_a[s], gray_b[s]);
			int j = (s + 2) % 4;
			uint64_t t = 10 * MS;
			if (via_edges) {
				rotary_edge(&r, 0, gray_a[j], t);
				rotary_edge(&r, 1, gray_b[j], t);
				rotary_flush(&r, t + 5 * MS);
			} else {
				rotary_sample(&r, gray_a[j], gray_b[j], t);
			}
			CHECK(r.illegal == 1, "jump %d->%d (%s) rejected: illegal %lu", s, j, via_edges ? "edges" : "sample",
			      r.illegal);
			CHECK(rotary_take(&r) == 0, "jump %d->%d gives no detent", s, j);
			CHECK(r.state == j, "resynchronised on %d (state %d)", j, r.state);
			/* then one legal step each way counts normally */
			int n = (j + 1) % 4;
			rotary_sample(&r, gray_a[n], gray_b[n], t + 100 * MS);
			CHECK(rotary_take(&r) == 1, "after jump %d->%d: step forward", s, j);
			rotary_sample(&r, gray_a[j], gray_b[j], t + 200 * MS);
			CHECK(rotary_take(&r) == -1, "after jump %d->%d: step back", s, j);
		}
	}
	/* no change is not a step */
	struct rotary r;
	struct rotary_config c = cfg(1, 0, 0, 1);
	rotary_init(&r, &c, 1, 1);
	rotary_sample(&r, 1, 1, 5 * MS);
	CHECK(r.steps == 0 && r.illegal == 0 && rotary_take(&r) == 0, "repeated state ignored");
	/* a jump in the middle of a detent (spd 4): at the next rest the count
	 * is rounded, so a turn with one lost pair still gives its detent */
	c = cfg(4, 0, 0, 1);
	rotary_init(&r, &c, 0, 0);
	rotary_sample(&r, gray_a[1], gray_b[1], 1 * MS);
	rotary_sample(&r, gray_a[3], gray_b[3], 2 * MS); /* 1 -> 3: illegal */
	rotary_sample(&r, gray_a[0], gray_b[0], 3 * MS);
	CHECK(r.illegal == 1 && rotary_take(&r) == 1, "detent with a skipped pair still counted once");
	CHECK(rotary_init(&r, &(struct rotary_config){ .steps_per_detent = 3, .accel_max = 1 }, 0, 0) == false,
	      "3 steps per detent refused");
	CHECK(rotary_init(&r, &(struct rotary_config){ .steps_per_detent = 4, .accel_max = 0 }, 0, 0) == false,
	      "accel_max 0 refused");
}

/* Pseudo-random numbers (deterministic). */
static uint32_t rng = 12345;
static uint32_t rnd(void)
{
	rng = rng * 1664525u + 1013904223u;
	return rng >> 8;
}

static void test_bounce(void)
{
	/* each edge preceded by 0..5 glitches on the same line, 20..300 us
	 * apart, debounce 1 ms, quarter steps 3 ms apart: exact count */
	for (int spd = 1; spd <= 4; spd *= 2) {
		struct rotary r;
		struct rotary_config c = cfg(spd, 1 * MS, 0, 1);
		rotary_init(&r, &c, 0, 0);
		int pos = 0, total = 0, net = 0;
		uint64_t t = 0;
		unsigned glitches = 0;
		for (int q = 0; q < 400; q++) {
			int dir = (q / 40) % 2 ? -1 : 1; /* 40 forward, 40 back, ... */
			int np = ((pos + dir) % 4 + 4) % 4;
			int line = gray_a[np] != gray_a[pos] ? 0 : 1;
			int level = line == 0 ? gray_a[np] : gray_b[np];
			t += 3 * MS;
			int n = (int)(rnd() % 6);
			for (int g = 0; g < n; g++) {
				rotary_edge(&r, line, level, t);
				t += 20 * US + rnd() % (280 * US);
				rotary_edge(&r, line, !level, t);
				t += 20 * US + rnd() % (280 * US);
				glitches++;
			}
			rotary_edge(&r, line, level, t);
			pos = np;
			net += dir;
			total += rotary_take(&r);
		}
		rotary_flush(&r, t + 10 * MS);
		total += rotary_take(&r);
		CHECK(total == net / spd, "spd %d with bounce: %d detents, want %d", spd, total, net / spd);
		CHECK(r.bounces == 2 * glitches, "spd %d: %lu bounces filtered, %u glitch edges", spd, r.bounces, 2 * glitches);
		CHECK(r.illegal == 0, "spd %d: no illegal jumps from bounce (%lu)", spd, r.illegal);
	}
	/* without software debounce the quarter decoder still nets bounce to
	 * zero (each glitch is a step forth and back) */
	struct rotary r;
	struct rotary_config c = cfg(4, 0, 0, 1);
	rotary_init(&r, &c, 0, 0);
	int pos = 0, total = 0;
	uint64_t t = 0;
	for (int q = 0; q < 40; q++) {
		int np = (pos + 1) % 4;
		int line = gray_a[np] != gray_a[pos] ? 0 : 1;
		int level = line == 0 ? gray_a[np] : gray_b[np];
		for (int g = 0; g < 3; g++) {
			rotary_edge(&r, line, level, t += 50 * US);
			rotary_edge(&r, line, !level, t += 50 * US);
		}
		rotary_edge(&r, line, level, t += 5 * MS);
		pos = np;
		total += rotary_take(&r);
	}
	CHECK(total == 10, "no debounce, bouncy edges: %d detents, want 10", total);
	/* a pending edge settles by time alone (rotary_flush per frame) */
	rotary_init(&r, &(struct rotary_config){ .steps_per_detent = 1, .debounce_ns = 2 * MS, .accel_max = 1 }, 0, 0);
	rotary_edge(&r, 1, 1, 100 * MS);
	rotary_flush(&r, 101 * MS);
	CHECK(rotary_take(&r) == 0, "not settled after 1 ms of 2");
	rotary_flush(&r, 102 * MS);
	CHECK(rotary_take(&r) == 1, "settled after 2 ms");
}

static void test_missed(void)
{
	/* drop one edge in the middle of a turn: the next edges of the other
	 * line then repeat its level (ignored) or step back; never a detent in
	 * the wrong direction, and counting resumes exactly afterwards */
	for (int drop = 0; drop < 4; drop++) {
		struct rotary r;
		struct rotary_config c = cfg(4, 0, 0, 1);
		rotary_init(&r, &c, 0, 0);
		int pos = 0, before = 0;
		uint64_t t = 0;
		for (int q = 0; q < 8; q++) { /* two detents */
			step_edge(&r, &pos, 1, &t, 10 * MS);
			before += rotary_take(&r);
		}
		CHECK(before == 2, "two detents before the dropped edge");
		int d = 0;
		for (int q = 0; q < 4; q++) {
			int np = (pos + 1) % 4;
			if (q == drop) { /* missed: the level changes, no event */
				pos = np;
				continue;
			}
			int line = gray_a[np] != gray_a[pos] ? 0 : 1;
			rotary_edge(&r, line, line == 0 ? gray_a[np] : gray_b[np], t += 10 * MS);
			pos = np;
			int k = rotary_take(&r);
			CHECK(k >= 0, "dropped edge %d: detent in the wrong direction (%d)", drop, k);
			d += k;
		}
		CHECK(d <= 1, "dropped edge %d: at most the one detent (%d)", drop, d);
		/* resync: the decoder's idea of the lines now matches them after
		 * at most one full period; then every detent counts */
		int after = 0;
		for (int q = 0; q < 4; q++) {
			step_edge(&r, &pos, 1, &t, 10 * MS);
			rotary_take(&r);
		}
		for (int q = 0; q < 12; q++) {
			step_edge(&r, &pos, 1, &t, 10 * MS);
			after += rotary_take(&r);
		}
		CHECK(after == 3, "dropped edge %d: 3 detents after resync, got %d", drop, after);
	}
}

static void test_accel(void)
{
	struct rotary r;
	struct rotary_config c = cfg(4, 0, 80 * MS, 8);
	/* slow: one detent each 200 ms -> x1 */
	rotary_init(&r, &c, 0, 0);
	int pos = 0;
	uint64_t t = 0;
	int got[10];
	for (int k = 0; k < 10; k++) {
		for (int q = 0; q < 4; q++)
			step_edge(&r, &pos, 1, &t, 50 * MS);
		got[k] = rotary_take(&r);
	}
	for (int k = 0; k < 10; k++)
		CHECK(got[k] == 1, "slow detent %d counts 1 (got %d)", k, got[k]);
	/* fast: 4 ms per detent (< 80/4 ms) -> x8 after the first */
	for (int k = 0; k < 10; k++) {
		for (int q = 0; q < 4; q++)
			step_edge(&r, &pos, 1, &t, k == 0 ? 200 * MS : 1 * MS);
		got[k] = rotary_take(&r);
	}
	CHECK(got[0] == 1, "first detent after a pause counts 1 (got %d)", got[0]);
	for (int k = 1; k < 10; k++)
		CHECK(got[k] == 8, "fast detent %d counts 8 (got %d)", k, got[k]);
	/* medium: 50 ms per detent -> between (1 + 7*(80-50)/60 = 4) */
	for (int k = 0; k < 3; k++) {
		for (int q = 0; q < 4; q++)
			step_edge(&r, &pos, 1, &t, k == 0 ? 200 * MS : 12500 * US);
		got[k] = rotary_take(&r);
	}
	CHECK(got[1] == 4 && got[2] == 4, "medium speed counts 4 (got %d %d)", got[1], got[2]);
	/* a direction change never accelerates */
	for (int q = 0; q < 4; q++)
		step_edge(&r, &pos, -1, &t, 1 * MS);
	CHECK(rotary_take(&r) == -1, "reversal counts -1");
	for (int q = 0; q < 4; q++)
		step_edge(&r, &pos, -1, &t, 1 * MS);
	CHECK(rotary_take(&r) == -8, "fast reverse counts -8");
	/* acceleration off */
	c = cfg(4, 0, 0, 8);
	rotary_init(&r, &c, 0, 0);
	pos = 0;
	int total = 0;
	for (int q = 0; q < 40; q++) {
		step_edge(&r, &pos, 1, &t, 100 * US);
		total += rotary_take(&r);
	}
	CHECK(total == 10, "accel_ns 0: no acceleration (%d)", total);
}

int main(void)
{
	test_directions();
	test_illegal();
	test_bounce();
	test_missed();
	test_accel();
	return tc_done("rotary");
}
