/* isoterra — the autopilot flies every terrain preset, 4 seeds, 3 speeds,
 * 120 s each, with the CPU density function as the judge: it starts in air,
 * no point of its path (every step, and between steps) lies in rock, and in no 5 s window does it hover
 * (stay within one second's travel, or 10 units at high speed, of where the
 * window began: the size of a cave chamber it may turn around in).  CPU only. */
#include "density_ref.h"
#include "noise.h"
#include "params.h"
#include "world.h"
#include "tcheck.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define SAMPLE 0.1                    /* seconds between judged samples */
#define WINDOW 50                     /* samples in the 5 s hover window */
#define FLIGHT 120.0                  /* seconds per flight */
#define NSAMP 1200                    /* samples per flight: FLIGHT / SAMPLE */
#define REACH 10.0f                   /* units: a cave chamber's size */
#define STEPS 6                       /* simulation steps per sample (60 per second) */

struct verdict {
	float min_air;    /* least air seen (-density) */
	float min_travel; /* least net travel over 5 s */
	double hover_at;  /* first time it hovered (or -1) */
};

/* Least air along the segment a-b (sampled every 0.1 units and at b). */
static float air_along(const struct params *p, const struct noise_set *ns, const float a[3], const float b[3])
{
	float d[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] }, least = 1e30f;
	int n = 1 + (int)(sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / 0.1f);
	for (int i = 1; i <= n; i++) {
		float f = (float)i / (float)n;
		least = fminf(least, -density_ref(p, ns, NULL, a[0] + d[0] * f, a[1] + d[1] * f, a[2] + d[2] * f));
	}
	return least;
}

static void fly(const struct params *p, const struct noise_set *ns, struct verdict *v)
{
	struct autopilot ap;
	static float hist[NSAMP + 1][3];
	CHECK(autopilot_init(&ap, p, NULL) == 0, "autopilot_init");
	v->min_air = -density_ref(p, ns, NULL, ap.pos[0], ap.pos[1], ap.pos[2]);
	v->min_travel = 1e30f;
	v->hover_at = -1.0;
	float reach = fminf(p->fly_speed, REACH);
	float prev[3];
	memcpy(prev, ap.pos, sizeof(prev));
	for (int i = 0; i <= NSAMP; i++) {
		for (int s = 1; s <= STEPS; s++) { /* every simulation step, and the path between */
			autopilot_advance(&ap, (i - 1) * SAMPLE + s * SAMPLE / STEPS);
			v->min_air = fminf(v->min_air, air_along(p, ns, prev, ap.pos));
			memcpy(prev, ap.pos, sizeof(prev));
		}
		memcpy(hist[i], ap.pos, sizeof(ap.pos));
		if (i >= WINDOW) {
			float d = 0.0f; /* farthest it got from where the window began */
			for (int j = i - WINDOW + 1; j <= i; j++) {
				float d2 = 0.0f;
				for (int k = 0; k < 3; k++)
					d2 += (hist[j][k] - hist[i - WINDOW][k]) * (hist[j][k] - hist[i - WINDOW][k]);
				d = fmaxf(d, sqrtf(d2));
			}
			v->min_travel = fminf(v->min_travel, d);
			if (d < reach && v->hover_at < 0.0)
				v->hover_at = i * SAMPLE;
		}
	}
	autopilot_free(&ap);
}

static void preset_params(size_t i, struct params *p)
{
	char err[256];
	params_defaults(p);
	CHECK(params_apply_preset(p, presets[i].name, err, sizeof(err)) == 0, "%s", err);
}

int main(int argc, char **argv)
{
	static const int seeds[] = { 10, 1, 77, 12345 };
	static const float speeds[] = { 3.0f, 12.0f, 40.0f };
	int flights = 0, bad = 0;
	size_t nseeds = sizeof(seeds) / sizeof(seeds[0]);
	const char *only = NULL; /* one preset only (debugging) */
	for (int a = 1; a < argc; a++) {
		if (!strcmp(argv[a], "--seeds") && a + 1 < argc) { /* the first N seeds (sanitizer builds) */
			int k = atoi(argv[++a]);
			CHECK(k >= 1 && (size_t)k <= nseeds, "--seeds %s: want 1..%zu", argv[a], nseeds);
			if (k >= 1 && (size_t)k <= nseeds)
				nseeds = (size_t)k;
		} else {
			only = argv[a];
		}
	}
	for (size_t pi = 0; pi < preset_count; pi++) {
		if (strstr(presets[pi].settings, "field=")) /* the test fields are no terrain */
			continue;
		if (only && strcmp(only, presets[pi].name))
			continue;
		for (size_t si = 0; si < nseeds; si++)
			for (size_t vi = 0; vi < sizeof(speeds) / sizeof(speeds[0]); vi++) {
				struct params p;
				preset_params(pi, &p);
				p.scene = SCENE_WORLD;
				p.seed = seeds[si];
				p.fly_speed = speeds[vi];
				struct noise_set ns;
				noise_set_init(&ns, p.seed);
				struct verdict v;
				fly(&p, &ns, &v);
				flights++;
				bool ok = v.min_air > 0.0f && v.hover_at < 0.0;
				bad += !ok;
				printf("%-12s seed %5d speed %4.0f: least air %6.2f, least 5 s reach %7.2f%s\n",
				       presets[pi].name, p.seed, (double)p.fly_speed, (double)v.min_air,
				       (double)v.min_travel, ok ? "" : "  <-- FAIL");
				CHECK(v.min_air > 0.0f, "%s seed %d speed %g: in rock (air %g)", presets[pi].name, p.seed,
				      (double)p.fly_speed, (double)v.min_air);
				CHECK(v.hover_at < 0.0, "%s seed %d speed %g: hovered (5 s reach %g < %g) at %.1f s",
				      presets[pi].name, p.seed, (double)p.fly_speed, (double)v.min_travel,
				      (double)fminf(p.fly_speed, REACH), v.hover_at);
			}
	}
	printf("autopilot: %d flights of %.0f s, %d failed\n", flights, FLIGHT, bad);
	return tc_done("autopilot");
}
