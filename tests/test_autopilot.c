/* isoterra — the autopilot flies every terrain preset, 4 seeds, 3 speeds,
 * 120 s each, with the CPU density function as the judge: it starts in air,
 * no point of its path (every step, and between steps) lies in rock, and in no 5 s window does it hover
 * (stay within one second's travel, or 10 units at high speed, of where the
 * window began: the size of a cave chamber it may turn around in).  CPU only:
 * the flights are independent and fly on one thread per CPU, their verdicts
 * printed and checked in order afterwards.  --seed-from S flies seeds
 * S..S+3 instead (a sweep by hand, docs/WORLD.md). */
#include "density_ref.h"
#include "noise.h"
#include "params.h"
#include "world.h"
#include "tcheck.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define SAMPLE 0.1                    /* seconds between judged samples */
#define WINDOW 50                     /* samples in the 5 s hover window */
#define FLIGHT 120.0                  /* seconds per flight */
#define NSAMP 1200                    /* samples per flight: FLIGHT / SAMPLE */
#define REACH 10.0f                   /* units: a cave chamber's size */
#define STEPS 6                       /* simulation steps per sample (60 per second) */

struct verdict {
	bool init_ok;     /* autopilot_init succeeded */
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
	float (*hist)[3] = malloc(sizeof(float[NSAMP + 1][3]));
	v->init_ok = hist && autopilot_init(&ap, p, NULL) == 0;
	if (!v->init_ok) {
		free(hist);
		return;
	}
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
	free(hist);
}

struct flight {
	size_t preset;
	struct params p;
	struct verdict v;
};

struct pool {
	struct flight *f;
	size_t n;
	atomic_size_t next;
};

static void *fly_worker(void *arg)
{
	struct pool *pool = arg;
	for (size_t i; (i = atomic_fetch_add(&pool->next, 1)) < pool->n;) {
		struct noise_set ns;
		noise_set_init(&ns, pool->f[i].p.seed);
		fly(&pool->f[i].p, &ns, &pool->f[i].v);
	}
	return NULL;
}

static void preset_params(size_t i, struct params *p)
{
	char err[256];
	params_defaults(p);
	CHECK(params_apply_preset(p, presets[i].name, err, sizeof(err)) == 0, "%s", err);
}

int main(int argc, char **argv)
{
	static int seeds[] = { 10, 1, 77, 12345 };
	static const float speeds[] = { 3.0f, 12.0f, 40.0f }; /* the default (fly_speed) first: --speeds 1 */
	int flights = 0, bad = 0;
	size_t nseeds = sizeof(seeds) / sizeof(seeds[0]), nspeeds = sizeof(speeds) / sizeof(speeds[0]);
	const char *only = NULL; /* one preset only (debugging) */
	for (int a = 1; a < argc; a++) {
		if (!strcmp(argv[a], "--seeds") && a + 1 < argc) { /* the first N seeds (sanitizer builds) */
			int k = atoi(argv[++a]);
			CHECK(k >= 1 && (size_t)k <= nseeds, "--seeds %s: want 1..%zu", argv[a], nseeds);
			if (k >= 1 && (size_t)k <= nseeds)
				nseeds = (size_t)k;
		} else if (!strcmp(argv[a], "--seed-from") && a + 1 < argc) { /* seeds S..S+3 instead (a sweep, by hand) */
			int s0 = atoi(argv[++a]);
			for (size_t k = 0; k < sizeof(seeds) / sizeof(seeds[0]); k++)
				seeds[k] = s0 + (int)k;
		} else if (!strcmp(argv[a], "--speeds") && a + 1 < argc) { /* the first N speeds (sanitizer builds) */
			int k = atoi(argv[++a]);
			CHECK(k >= 1 && (size_t)k <= nspeeds, "--speeds %s: want 1..%zu", argv[a], nspeeds);
			if (k >= 1 && (size_t)k <= nspeeds)
				nspeeds = (size_t)k;
		} else {
			only = argv[a];
		}
	}
	struct flight *f = calloc(preset_count * nseeds * nspeeds, sizeof(*f));
	CHECK(f != NULL, "out of memory");
	if (!f)
		return tc_done("autopilot");
	size_t n = 0;
	for (size_t pi = 0; pi < preset_count; pi++) {
		if (strstr(presets[pi].settings, "field=")) /* the test fields are no terrain */
			continue;
		if (only && strcmp(only, presets[pi].name))
			continue;
		for (size_t si = 0; si < nseeds; si++)
			for (size_t vi = 0; vi < nspeeds; vi++) {
				f[n].preset = pi;
				preset_params(pi, &f[n].p);
				f[n].p.scene = SCENE_WORLD;
				f[n].p.seed = seeds[si];
				f[n].p.fly_speed = speeds[vi];
				n++;
			}
	}
	struct pool pool = { .f = f, .n = n };
	atomic_init(&pool.next, 0);
	long cpus = sysconf(_SC_NPROCESSORS_ONLN);
	size_t nthreads = cpus < 1 ? 1 : cpus > 8 ? 8 : (size_t)cpus;
	pthread_t th[8];
	size_t started = 0;
	for (; started < nthreads; started++)
		if (pthread_create(&th[started], NULL, fly_worker, &pool) != 0)
			break;
	if (started == 0)
		fly_worker(&pool); /* no thread could start: fly them here */
	for (size_t t = 0; t < started; t++)
		pthread_join(th[t], NULL);
	for (size_t i = 0; i < n; i++) {
		const struct params *p = &f[i].p;
		const struct verdict *v = &f[i].v;
		const char *name = presets[f[i].preset].name;
		flights++;
		CHECK(v->init_ok, "%s seed %d speed %g: autopilot_init", name, p->seed, (double)p->fly_speed);
		if (!v->init_ok) {
			bad++;
			continue;
		}
		bool ok = v->min_air > 0.0f && v->hover_at < 0.0;
		bad += !ok;
		printf("%-12s seed %5d speed %4.0f: least air %6.2f, least 5 s reach %7.2f%s\n", name, p->seed,
		       (double)p->fly_speed, (double)v->min_air, (double)v->min_travel, ok ? "" : "  <-- FAIL");
		CHECK(v->min_air > 0.0f, "%s seed %d speed %g: in rock (air %g)", name, p->seed, (double)p->fly_speed,
		      (double)v->min_air);
		CHECK(v->hover_at < 0.0, "%s seed %d speed %g: hovered (5 s reach %g < %g) at %.1f s", name, p->seed,
		      (double)p->fly_speed, (double)v->min_travel, (double)fminf(p->fly_speed, REACH), v->hover_at);
	}
	free(f);
	printf("autopilot: %d flights of %.0f s, %d failed\n", flights, FLIGHT, bad);
	return tc_done("autopilot");
}
