/* isoterra — the frame-time governor (app/scene/governor.c) under a fake
 * clock and a synthetic load whose cost follows the quality it is given:
 * a light load keeps full quality; a heavy one (three times the target)
 * is brought under the target within 6 s, without oscillating; when it
 * goes away full quality comes back; a load between two steps does not make it flip back and
 * forth; hitches and broken clocks do not throw it; a load whose mean is
 * under the target while every third frame is far over it is not held
 * there (what the governor holds is the mean plus one deviation); after a
 * heavy stretch it climbs back as far as the steps' measured costs say the
 * level above fits, not only to where the frame is under a fixed line;
 * a view that turns far lighter (the sky) has full quality back at once. */
#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <stdio.h>

#include "governor.h"
#include "tcheck.h"

struct load {
	double fixed, pixels, gen, ao, far, view; /* ms at full quality */
	double smooth; /* the edge smoothing after the frame, while it is on */
	double detail; /* the close-up detail, while it is on */
};

static uint32_t rng; /* the jitter sequence's state (main) */
static double jitter(void) /* +-5 %, deterministic */
{
	rng = rng * 1664525u + 1013904223u;
	return 0.95 + 0.1 * (double)(rng >> 8) / (double)(1u << 24);
}

static double cost(const struct load *l, struct governor_quality q)
{
	return (l->fixed + l->pixels * q.render_scale * q.render_scale + l->gen * q.gen_budget + l->ao * q.ao_rays +
		l->far * (1.0 - 0.3 * q.far_octaves_drop) + l->view * q.view_distance * q.view_distance +
		l->smooth * q.smoothing + l->detail * q.detail) *
	       jitter();
}

struct run {
	struct governor g;
	struct governor_quality q;
	double now;
	unsigned changes; /* level changes in the current window */
	double worst_ms, sum_ms;
	unsigned frames;
};

/* Runs the load for secs of fake time; window statistics over the last `tail` seconds. */
static void fly(struct run *r, const struct load *l, double secs, double tail)
{
	double end = r->now + secs;
	r->changes = 0;
	r->worst_ms = r->sum_ms = 0;
	r->frames = 0;
	while (r->now < end) {
		double ms = cost(l, r->q);
		r->now += ms / 1000.0;
		int before = r->q.level;
		r->q = governor_update(&r->g, ms, r->now);
		if (r->now >= end - tail) {
			r->changes += r->q.level != before;
			r->worst_ms = fmax(r->worst_ms, ms);
			r->sum_ms += ms;
			r->frames++;
		}
	}
}

/* The dynamic cases, under the jitter sequence rng holds. */
static void cases(void)
{
	const double target = 1000.0 / 30;
	struct run r = { .now = 100.0 };
	governor_init(&r.g, target);
	r.q = governor_level(0);

	const struct load light = { 4, 10, 3, 1, 0, 2, 3, 2 }; /* 25 ms at full quality */
	fly(&r, &light, 20, 20);
	CHECK(r.q.level == 0 && r.g.steps_down == 0, "light load: full quality held (level %d, %u steps down)", r.q.level,
	      r.g.steps_down);

	/* heavy: 97 ms at full quality; under the target from scale 0.5 and half the budget */
	const struct load heavy = { 6, 52, 8, 6, 3, 4, 10, 8 };
	fly(&r, &heavy, 10, 4);
	double mean = r.sum_ms / r.frames;
	printf("heavy: level %d, scale %.2f, mean %.1f ms, worst %.1f ms, %u changes in the last 4 s\n", r.q.level,
	       r.q.render_scale, mean, r.worst_ms, r.changes);
	CHECK(mean <= target, "heavy load: mean frame %.1f ms over the target %.1f after 10 s", mean, target);
	/* settled within 6 s: several levels at a time while the mean is far
	 * over (one at a time, ten steps of 0.75 s, it settled at 7.5-7.8 s
	 * and the last 4 s held 32.7-33.6 ms) */
	CHECK(r.changes == 0, "heavy load: still stepping after 6 s (%u changes in the last 4 s)", r.changes);
	CHECK(r.q.level > 0 && r.q.render_scale < 1, "heavy load: quality lowered (level %d)", r.q.level);
	CHECK(r.q.view_distance == 1.0f, "heavy load: the view distance is the last thing given up (%.2f)", r.q.view_distance);
	int held = r.q.level;
	fly(&r, &heavy, 60, 60);
	printf("heavy, 60 s more: level %d, %u changes\n", r.q.level, r.changes);
	CHECK(r.changes <= 4, "heavy load held for 60 s: %u level changes (no oscillation)", r.changes);
	CHECK(abs(r.q.level - held) <= 1, "heavy load: level stays (%d then %d)", held, r.q.level);

	/* the load goes away */
	fly(&r, &light, 60, 60);
	printf("light again: level %d after 60 s\n", r.q.level);
	CHECK(r.q.level == 0, "load gone: full quality back within 60 s (level %d)", r.q.level);

	/* a load between two steps: level 1 (no smoothing) is at 90 % of the target, level 0 at 114 % */
	struct run b = { .now = 0 };
	governor_init(&b.g, target);
	b.q = governor_level(0);
	/* 38 ms full; without the smoothing 30 ms (under the target, over 0.75 of it) */
	const struct load edge = { 6, 24, 0, 0, 0, 0, 8, 0 };
	fly(&b, &edge, 180, 120);
	printf("edge: level %d, %u steps up, %u down, %u changes in the last 120 s\n", b.q.level, b.g.steps_up,
	       b.g.steps_down, b.changes);
	CHECK(b.q.level == 1, "edge load: settles one step down (level %d)", b.q.level);
	CHECK(b.changes == 0, "edge load: no flipping (%u changes in 120 s)", b.changes);

	/* a load with no level inside the band: full budget 42 ms, half 22 ms
	 * (under 75 %): it probes upward ever more rarely (2, 4, 8 ... 32 s) */
	struct run o = { .now = 0 };
	governor_init(&o.g, target);
	o.q = governor_level(0);
	const struct load probe = { 2, 0, 40, 0, 0, 0, 0, 0 };
	fly(&o, &probe, 60, 60);
	double over_s = 0;
	unsigned frames = 0;
	double end = o.now + 120;
	o.changes = 0;
	while (o.now < end) {
		double ms = cost(&probe, o.q);
		o.now += ms / 1000.0;
		over_s += ms > target ? ms / 1000.0 : 0;
		int before = o.q.level;
		o.q = governor_update(&o.g, ms, o.now);
		o.changes += o.q.level != before;
		frames++;
	}
	printf("probe: level %d, %u changes and %.2f s over the target in 120 s (%u frames)\n", o.q.level, o.changes,
	       over_s, frames);
	CHECK(o.changes <= 8, "probe load: at most 8 changes in 120 s (%u)", o.changes);
	CHECK(over_s <= 0.05 * 120, "probe load: over the target %.2f s of 120", over_s);

	/* a hitch (one 2 s frame) and broken frame times do not drop quality to the floor */
	struct run h = { .now = 0 };
	governor_init(&h.g, target);
	h.q = governor_level(0);
	fly(&h, &light, 5, 5);
	h.now += 2.0;
	h.q = governor_update(&h.g, 2000.0, h.now);
	h.q = governor_update(&h.g, NAN, h.now);
	h.q = governor_update(&h.g, -5.0, h.now);
	fly(&h, &light, 10, 10);
	CHECK(h.q.level <= 1 && h.g.steps_down <= 1, "hitch: at most one step (level %d, %u down)", h.q.level,
	      h.g.steps_down);
	fly(&h, &light, 30, 30);
	CHECK(h.q.level == 0, "hitch: full quality back (level %d)", h.q.level);

	/* spikes: every third frame carries 20 ms more (blocks generated over
	 * a heavy view); at full quality 24, 24, 44 ms: the mean, 30.7 ms, is
	 * under the target, a third of the frames 30 % over it */
	struct run sp = { .now = 0 };
	governor_init(&sp.g, target);
	sp.q = governor_level(0);
	const struct load base = { 4, 20, 0, 0, 0, 0, 0, 0 };
	double sp_end = 40, worst0 = 0, worst = 0, sum = 0, sum2 = 0;
	unsigned n = 0, k = 0, changes = 0;
	while (sp.now < sp_end) {
		double ms = cost(&base, sp.q) + (k++ % 3 == 0 ? 20.0 : 0.0);
		sp.now += ms / 1000.0;
		if (sp.now < 1.0)
			worst0 = fmax(worst0, ms);
		int before = sp.q.level;
		sp.q = governor_update(&sp.g, ms, sp.now);
		if (sp.now >= sp_end - 20) { /* the last 20 s */
			changes += sp.q.level != before;
			worst = fmax(worst, ms);
			sum += ms;
			sum2 += ms * ms;
			n++;
		}
	}
	double sp_mean = sum / n, sp_dev = sqrt(fmax(0.0, sum2 / n - sp_mean * sp_mean));
	printf("spikes: level %d, scale %.2f; last 20 s: mean %.1f ms, deviation %.1f, worst %.1f (first second: %.1f), "
	       "%u changes\n",
	       sp.q.level, sp.q.render_scale, sp_mean, sp_dev, worst, worst0, changes);
	CHECK(sp.q.level > 0, "spikes: a mean under the target with a third of the frames over it is not held (level %d)",
	      sp.q.level);
	/* at full quality mean + deviation is 30.7 + 9.4 ms: lower now, the
	 * spikes smaller (one step leaves them 1.2 ms over: inside the band
	 * the hysteresis keeps) */
	CHECK(sp_mean + sp_dev < 0.9 * (30.7 + 9.4), "spikes: mean + deviation down to %.1f ms", sp_mean + sp_dev);
	CHECK(worst < worst0 - 3, "spikes: the worst frame %.1f ms, was %.1f", worst, worst0);
	CHECK(changes == 0, "spikes: no flipping (%u changes in 20 s)", changes);

	/* a heavy stretch of the flight, then a lighter one that sits over
	 * the fixed line (0.75 of the target) at every level but whose steps
	 * cost little: 25 ms of fixed work and 4 of pixels (26-29 ms, held
	 * about 0.8 more).  The steps' costs measured on the way down (by the
	 * load's formula the level above 1.0-1.03 times the one below, clamped
	 * to 1.02 at least) let it climb back to
	 * where the next step does not fit; with the fixed line alone it would
	 * stay at the floor.  (26 ms of fixed work put scale 0.75's prediction
	 * within 1 % of the line, 29.1 x 1.02 against 30.0 ms: a quarter of
	 * the jitter sequences stayed there.) */
	struct run cl = { .now = 0 };
	governor_init(&cl.g, target);
	cl.q = governor_level(0);
	const struct load heavy_view = { 40, 4, 0, 0, 0, 0, 0, 0 }, light_view = { 25, 4, 0, 0, 0, 0, 0, 0 };
	fly(&cl, &heavy_view, 40, 40);
	int floor_level = cl.q.level;
	fly(&cl, &light_view, 90, 30);
	double cl_mean = cl.sum_ms / cl.frames;
	printf("climb: level %d after the heavy stretch, %d after the light one (scale %.2f), mean %.1f ms, %u changes "
	       "in its last 30 s\n",
	       floor_level, cl.q.level, cl.q.render_scale, cl_mean, cl.changes);
	CHECK(floor_level == GOVERNOR_LEVELS - 1, "climb: the heavy stretch takes it to the floor (level %d)", floor_level);
	CHECK(cl.q.render_scale >= 0.85f, "climb: back to a scale of 0.85 or more (level %d, scale %.2f)", cl.q.level,
	      cl.q.render_scale);
	CHECK(cl_mean <= target, "climb: the mean frame %.1f ms over the target", cl_mean);
	CHECK(cl.changes <= 2, "climb: settled (%u changes in the last 30 s)", cl.changes);

	/* a flight that turns from heavy land to the sky and back: the sky
	 * frames are far under the target at every level (8 ms at full
	 * quality), so full quality is back within a second and a half of
	 * each light stretch, not one level every few seconds (the steps' wait
	 * grown by the heavy stretches' failed tries); the heavy stretches are
	 * still brought under the target */
	struct run sk = { .now = 0 };
	governor_init(&sk.g, target);
	sk.q = governor_level(0);
	const struct load sky = { 2, 3, 1, 0, 0, 0, 1, 1 };
	unsigned sky_frames = 0, sky_full = 0, sky_changes = 0;
	double heavy_sum = 0;
	unsigned heavy_n = 0;
	for (int round = 0; round < 4; round++) {
		fly(&sk, &heavy, 10, 4);
		heavy_sum += sk.sum_ms;
		heavy_n += sk.frames;
		int from = sk.q.level;
		fly(&sk, &sky, 1.5, 1.5);
		double sky_end = sk.now + 3.5;
		while (sk.now < sky_end) { /* the rest of the light stretch */
			double ms = cost(&sky, sk.q);
			sk.now += ms / 1000.0;
			int before = sk.q.level;
			sk.q = governor_update(&sk.g, ms, sk.now);
			sky_changes += sk.q.level != before;
			sky_full += sk.q.level == 0;
			sky_frames++;
		}
		printf("sky %d: from level %d, level %d after 5 s\n", round, from, sk.q.level);
	}
	printf("sky: %u of %u frames at full quality after each stretch's first 1.5 s, %u changes; heavy stretches' last "
	       "4 s: mean %.1f ms\n",
	       sky_full, sky_frames, sky_changes, heavy_sum / heavy_n);
	CHECK(sky_full == sky_frames, "sky: full quality within 1.5 s of each light stretch (%u of %u frames)", sky_full,
	      sky_frames);
	CHECK(sky_changes == 0, "sky: settled at full quality (%u changes)", sky_changes);
	CHECK(heavy_sum / heavy_n <= target, "sky: the heavy stretches held under the target (mean %.1f ms)",
	      heavy_sum / heavy_n);
}

int main(void)
{
	/* every dynamic case under several jitter sequences: its checks hold
	 * for the governor, not for one sequence (one of them alone let a case
	 * on the edge of a line pass: the climb's, below) */
	static const uint32_t seqs[] = { 12345, 1, 2, 3, 4, 5, 6, 7 };
	for (size_t i = 0; i < sizeof(seqs) / sizeof(seqs[0]); i++) {
		rng = seqs[i];
		printf("-- jitter sequence %u\n", seqs[i]);
		cases();
	}

	/* the ladder: monotone, in the documented order */
	for (int i = 1; i < GOVERNOR_LEVELS; i++) {
		struct governor_quality a = governor_level(i - 1), c = governor_level(i);
		CHECK(c.render_scale <= a.render_scale && c.gen_budget <= a.gen_budget && c.ao_rays <= a.ao_rays &&
			      c.shadow_steps <= a.shadow_steps && c.far_octaves_drop >= a.far_octaves_drop &&
			      c.view_distance <= a.view_distance && c.framing <= a.framing && c.smoothing <= a.smoothing &&
			      c.detail <= a.detail && c.near_lod <= a.near_lod,
		      "ladder step %d only lowers quality", i);
		CHECK(c.near_lod == 1.0f || c.gen_budget == 0.25f, "step %d: the near LOD after the generation budget", i);
		CHECK(c.render_scale == 1.0f || c.near_lod < 1.0f, "step %d: the near LOD given up before the scale", i);
		CHECK(c.view_distance == 1.0f || c.render_scale == 0.5f, "step %d: view distance only after scale", i);
		CHECK(c.shadow_steps == 1.0f || c.ao_rays == 0.0f, "step %d: shadows only after AO", i);
		CHECK(c.render_scale == 1.0f || c.smoothing == 0.0f, "step %d: the upscale, not the smoothing, below scale 1", i);
		CHECK(c.render_scale == 1.0f || c.detail == 0.0f, "step %d: the close-up detail given up before the scale", i);
		CHECK(c.render_scale == 1.0f || c.gen_budget == 0.25f, "step %d: the generation budget given up before the scale",
		      i);
	}
	{
		struct governor_quality a = governor_level(0), c = governor_level(1);
		CHECK(a.smoothing == 1.0f && a.detail == 1.0f && c.smoothing == 0.0f && c.detail == 0.5f &&
			      c.render_scale == 1.0f && c.framing == 1.0f && c.gen_budget == 1.0f && c.ao_rays == 1.0f &&
			      c.shadow_steps == 1.0f && c.view_distance == 1.0f && c.near_lod == 1.0f,
		      "the first step gives up the edge smoothing and the close-up detail's finer scale alone");
		struct governor_quality d = governor_level(2);
		CHECK(d.detail == 0.0f && d.smoothing == 0.0f && d.render_scale == 1.0f && d.framing == 1.0f &&
			      d.gen_budget == 1.0f && d.ao_rays == 1.0f && d.shadow_steps == 1.0f && d.view_distance == 1.0f,
		      "the second step gives up the rest of the close-up detail alone");
	}
	CHECK(governor_level(GOVERNOR_LEVELS - 1).render_scale == 0.5f, "scale floor 0.5");
	{
		int s = 0; /* the first step of render scale */
		while (s < GOVERNOR_LEVELS && governor_level(s).render_scale == 1.0f)
			s++;
		CHECK(s > 0 && s < GOVERNOR_LEVELS && governor_level(s - 1).framing == 1.0f && governor_level(s).framing == 0.0f,
		      "the composed start is kept to the first step of render scale (level %d)", s);
	}
	/* the parameters that name a level reach the floor and no further */
	CHECK(params_find("quality")->hi == GOVERNOR_LEVELS - 1, "--quality's range ends at the floor (%g)",
	      params_find("quality")->hi);
	CHECK(params_find("low_power_quality")->hi == GOVERNOR_LEVELS - 1, "--low-power-quality's range ends at the floor");
	return tc_done("governor");
}
