/* isoterra — what the frame loop tells the governor a frame's work was
 * (app/run.c, scene_frame.last_work_ms): the frame's whole time, its
 * scene and its sinks (a present's copy is work), less the frame cap's
 * sleep and what the sinks say they spent waiting for the display (a
 * vertical blank, a page flip).  A scene that records what it is told and
 * burns a known CPU time; a sink that, frame by frame, burns CPU (work),
 * sleeps and says so (a wait), or sleeps and says nothing (a blocking
 * present that waited uncounted: work as far as the loop can know).  The
 * expectations are the times the test's scene and sink themselves took,
 * measured by them (wall clock: a loaded machine's preemption is in both;
 * a waiting sink says the wait it measured, as the display sink does, so
 * a nap that oversleeps under load is not taken for the loop's work); the
 * margin for the loop's own steps (20 ms) is under the wait taken out
 * (60 ms), so a wait counted as work fails. */
#include "app.h"
#include "gpu_fixture.h"
#include "tcheck.h"

#include <stdio.h>
#include <string.h>
#include <time.h>

#define FRAMES 12
#define SCENE_MS 6.0
#define SINK_MS 60.0
#define MARGIN_MS 20.0

enum { SINK_WORKS, SINK_WAITS, SINK_SLEEPS_UNSAID };

struct work_scene {
	struct scene base;
	double told[FRAMES]; /* last_work_ms as each frame was told */
	double took[FRAMES]; /* wall ms each frame's scene took */
};

struct work_sink {
	struct sink base;
	int kind[FRAMES];
	double worked[FRAMES]; /* wall ms each frame's sink worked (0: it slept) */
};

static void burn(double ms) /* CPU, not sleep */
{
	double t = clock_thread_cpu_ms();
	volatile unsigned x = 1;
	while (clock_thread_cpu_ms() - t < ms)
		for (int i = 0; i < 1000; i++)
			x = x * 1664525u + 1013904223u;
}

static void nap(double ms)
{
	struct timespec ts = { 0, (long)(ms * 1e6) };
	while (nanosleep(&ts, &ts) != 0)
		;
}

static int scene_frame_fn(struct scene *s, struct params *p, const struct scene_frame *fr, char *err, size_t errlen)
{
	(void)p;
	(void)err;
	(void)errlen;
	struct work_scene *ws = (struct work_scene *)s;
	double t = clock_ms();
	burn(SCENE_MS);
	if (fr->index < FRAMES) {
		ws->told[fr->index] = fr->last_work_ms;
		ws->took[fr->index] = clock_ms() - t;
	}
	return 0;
}

static int scene_counts_fn(struct scene *s, struct scene_counts *c)
{
	(void)s;
	memset(c, 0, sizeof(*c));
	return 0;
}

static void scene_destroy_fn(struct scene *s)
{
	(void)s;
}

static const struct scene_ops work_scene_ops = { .frame = scene_frame_fn, .counts = scene_counts_fn,
						 .destroy = scene_destroy_fn };

static int sink_frame_fn(struct sink *base, struct sink_frame *fr, char *err, size_t errlen)
{
	(void)err;
	(void)errlen;
	struct work_sink *s = (struct work_sink *)base;
	int k = fr->index < FRAMES ? s->kind[fr->index] : SINK_WORKS;
	if (k == SINK_WORKS) {
		double t = clock_ms();
		burn(SINK_MS);
		if (fr->index < FRAMES)
			s->worked[fr->index] = clock_ms() - t;
	} else {
		/* a display sink says the wait it measured: a loaded machine
		 * oversleeps, and the oversleep is the display's too */
		double t = clock_ms();
		nap(SINK_MS);
		if (k == SINK_WAITS)
			fr->wait_ms += clock_ms() - t;
	}
	return 0;
}

static int sink_finish_fn(struct sink *base, const struct sink_end *end, char *err, size_t errlen)
{
	(void)base;
	(void)end;
	(void)err;
	(void)errlen;
	return 0;
}

static void sink_destroy_fn(struct sink *base)
{
	(void)base;
}

static const struct sink_ops work_sink_ops = { .frame = sink_frame_fn, .finish = sink_finish_fn,
					       .destroy = sink_destroy_fn };

/* One run of FRAMES frames with the sink doing kinds[] and the frame cap
 * max_fps (0: none). */
static struct work_sink sk = { .base = { &work_sink_ops, NULL } };

static int run(struct work_scene *sc, const int kinds[FRAMES], float max_fps, struct renderer *r)
{
	struct params p;
	params_defaults(&p);
	p.count = FRAMES;
	p.max_fps = max_fps;
	memcpy(sk.kind, kinds, sizeof(sk.kind));
	memset(sk.worked, 0, sizeof(sk.worked));
	memset(sc->told, 0, sizeof(sc->told));
	struct sink_set sinks = { .n = 0 };
	sinks_add(&sinks, &sk.base);
	struct frame_loop lp = { .p = &p, .scene = &sc->base, .sinks = &sinks, .r = r, .w = 64, .h = 48 };
	char err[256] = "";
	int rc = frame_loop_run(&lp, err, sizeof(err));
	CHECK(rc == 0 && lp.frames == FRAMES, "the loop ran %d frames: %s", lp.frames, err);
	return rc;
}

int main(void)
{
	struct platform *plat = fixture_open();
	char err[256] = "";
	struct renderer *r = renderer_create(64, 48, ANTIALIAS_OFF, err, sizeof(err));
	CHECK(r != NULL, "renderer: %s", err);
	static struct work_scene sc = { .base = { &work_scene_ops } };

	/* every second frame the sink works, the others it waits and says so */
	int kinds[FRAMES];
	for (int i = 0; i < FRAMES; i++)
		kinds[i] = i % 2 ? SINK_WAITS : SINK_WORKS;
	if (r && run(&sc, kinds, 0.0f, r) == 0) {
		CHECK(sc.told[0] < 0, "the first frame is told no frame before it (%.1f)", sc.told[0]);
		for (int i = 1; i < FRAMES; i++) {
			double t = sc.told[i], want = sc.took[i - 1] + sk.worked[i - 1];
			printf("frame %2d told %.1f ms; the frame before: scene %.1f ms, sink %s %.1f ms\n", i, t, sc.took[i - 1],
			       kinds[i - 1] == SINK_WORKS ? "working" : "waiting", kinds[i - 1] == SINK_WORKS ? sk.worked[i - 1] : SINK_MS);
			if (kinds[i - 1] == SINK_WORKS)
				CHECK(t >= want - 0.5 && t < want + MARGIN_MS,
				      "frame %d: the sink's work is the frame's (%.1f ms; scene and sink %.1f)", i, t, want);
			else
				CHECK(t >= want - 0.5 && t < want + MARGIN_MS,
				      "frame %d: the display's wait is not the frame's work (%.1f ms; scene %.1f, wait %.0f)", i, t,
				      want, SINK_MS);
		}
	}

	/* a present that blocked without saying so counts (the loop cannot
	 * tell it from work): the negative control of the waits above */
	for (int i = 0; i < FRAMES; i++)
		kinds[i] = SINK_SLEEPS_UNSAID;
	if (r && run(&sc, kinds, 0.0f, r) == 0)
		CHECK(sc.told[FRAMES - 1] >= sc.took[FRAMES - 2] + SINK_MS - 0.5,
		      "an unsaid wait is counted (%.1f ms): the waits above were taken out because they were said",
		      sc.told[FRAMES - 1]);

	/* the frame cap's sleep is not work: 8 fps, 125 ms a frame, the work
	 * 66 ms of it */
	for (int i = 0; i < FRAMES; i++)
		kinds[i] = SINK_WORKS;
	if (r && run(&sc, kinds, 8.0f, r) == 0) {
		int off = 0;
		for (int i = 2; i < FRAMES; i++) {
			double want = sc.took[i - 1] + sk.worked[i - 1];
			off += !(sc.told[i] >= want - 0.5 && sc.told[i] < want + MARGIN_MS);
		}
		printf("capped at 8 fps: frame %d told %.1f ms, its scene and sink %.1f\n", FRAMES - 1, sc.told[FRAMES - 1],
		       sc.took[FRAMES - 2] + sk.worked[FRAMES - 2]);
		CHECK(off == 0, "capped at 8 fps: the cap's sleep (59 ms of the 125) is not the frame's work (%d frames off)",
		      off);
	}
	renderer_destroy(r);
	platform_close(plat);
	return tc_done("frame_work");
}
