/* isoterra — the frame-time governor (governor.h). */
#include "governor.h"

#include <math.h>

/* The ladder: each row one step down from the one before, in the order the
 * user notices least: first what is finer than a few pixels, the edge
 * smoothing after the frame (the filter a software rasterizer runs instead
 * of multisampling: about a tenth of a 640x480 world frame on llvmpipe; on
 * a GPU, which multisamples, it changes nothing) and the close-up detail's
 * finer scale (the grain within 6.25 units: the meshes beyond that are
 * drawn without it whatever the level, so it saves its texture taps only
 * where a mesh comes that close, the flight skimming the ground; a step of
 * its own saved nothing in a flight, and cost the heavy views a step more
 * to come down, render.c), then the rest of the close-up detail (the near
 * meshes drawn with the far ones' program: the grain of the rock and the
 * grass within 25 units, faint at the flight's height, gone; about 8 % of
 * a 640x480 world frame on llvmpipe), then how fast new blocks arrive
 * (half, a quarter of the budget: the finer levels come in later, the
 * coarser ones stand in meanwhile; before the scale, whose steps down cost
 * the whole picture and could never be taken back while the budget, below
 * them, had to come back first), then the finer levels of detail's range
 * (two thirds of lod_distance: the coarser level's surface nearer the eye,
 * its cells twice as large; a frame of a software rasterizer is bound by
 * the triangles it sets up and bins, not only its pixels, and a low flight
 * draws most of them in the finer levels: 281 000 triangles against
 * 162 000 in test_world's low view; the rung leaves the whole picture
 * sharp, where a step of the scale blurs it), then resolution (upscaled
 * with a filter that keeps edges; the upscale replaces the smoothing),
 * and with its first step the autopilot's composed start (the view tilted down onto the
 * land for a flight's first seconds: land filling the frame is the frame's
 * whole cost on a software rasterizer), then the blocks' AO, then their
 * sun shadows (half the steps, then none), then the far blocks' finest
 * octaves, and only then how far one sees.  AO and shadows are baked into
 * new blocks: what they save is generation time. */
static const struct governor_quality ladder[GOVERNOR_LEVELS] = {
	/* scale, budget, AO, shadows, far octaves dropped, view, framing, smoothing, detail, near LOD, level */
	{ 1.00f, 1.00f, 1.00f, 1.00f, 0, 1.00f, 1.00f, 1.00f, 1.00f, 1.00f, 0 },
	{ 1.00f, 1.00f, 1.00f, 1.00f, 0, 1.00f, 1.00f, 0.00f, 0.50f, 1.00f, 1 },
	{ 1.00f, 1.00f, 1.00f, 1.00f, 0, 1.00f, 1.00f, 0.00f, 0.00f, 1.00f, 2 },
	{ 1.00f, 0.50f, 1.00f, 1.00f, 0, 1.00f, 1.00f, 0.00f, 0.00f, 1.00f, 3 },
	{ 1.00f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 1.00f, 0.00f, 0.00f, 1.00f, 4 },
	{ 1.00f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 1.00f, 0.00f, 0.00f, 0.67f, 5 },
	{ 0.85f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 6 },
	{ 0.75f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 7 },
	{ 0.66f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 8 },
	{ 0.58f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 9 },
	{ 0.50f, 0.25f, 1.00f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 10 },
	{ 0.50f, 0.25f, 0.50f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 11 },
	{ 0.50f, 0.25f, 0.00f, 1.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 12 },
	{ 0.50f, 0.25f, 0.00f, 0.50f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 13 },
	{ 0.50f, 0.25f, 0.00f, 0.00f, 0, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 14 },
	{ 0.50f, 0.25f, 0.00f, 0.00f, 1, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 15 },
	{ 0.50f, 0.25f, 0.00f, 0.00f, 2, 1.00f, 0.00f, 0.00f, 0.00f, 0.67f, 16 },
	{ 0.50f, 0.25f, 0.00f, 0.00f, 2, 0.75f, 0.00f, 0.00f, 0.00f, 0.67f, 17 },
	{ 0.50f, 0.25f, 0.00f, 0.00f, 2, 0.55f, 0.00f, 0.00f, 0.00f, 0.67f, 18 },
};

#define OVER 1.00        /* step down above the target ... */
#define OVER_FOR_S 0.25  /* ... held this long */
#define UNDER 0.75       /* step up below target * UNDER (a step whose cost is not known yet) ... */
#define FIT 0.90         /* ... or when the level above is predicted under target * FIT */
#define COST_MIN 1.02    /* a step up's measured cost, clamped: it never makes the frame cheaper */
#define COST_MAX 2.0
#define LEARN_MAX 1.5    /* no cost learnt from a step taken while more than this times the target was held */
#define UP_WAIT_MIN_S 2.0 /* ... held this long at first */
#define UP_WAIT_MAX_S 32.0
#define SETTLE_S 0.5     /* after a step: let the average follow */
#define FAILED_UP_S 4.0  /* a step down this soon after a step up: that step up failed */
#define SURE_S 0.25      /* a sure climb (sure_steps) waits this long under its line */
#define SMOOTH 0.2       /* weight of the newest frame in the averages */

int governor_detail_scales(const struct governor_quality *q)
{
	return q->detail > 0.75f ? 2 : q->detail > 0.25f ? 1 : 0;
}

struct governor_quality governor_level(int level)
{
	if (level < 0)
		level = 0;
	if (level >= GOVERNOR_LEVELS)
		level = GOVERNOR_LEVELS - 1;
	return ladder[level];
}

void governor_init(struct governor *g, double target_ms)
{
	*g = (struct governor){ .target_ms = target_ms, .smooth_ms = -1, .over_since = -1, .under_since = -1,
				.settle_until = -1e300, .up_wait_s = UP_WAIT_MIN_S, .last_up_s = -1, .learn_from = -1 };
}

double governor_held_ms(const struct governor *g)
{
	return g->smooth_ms < 0 ? -1 : g->smooth_ms + sqrt(g->smooth_var);
}

static void step(struct governor *g, int dir, double now_s)
{
	g->learn_from = dir == 1 || dir == -1 ? g->level : -1; /* a jump's cost is no one step's */
	g->learn_held = governor_held_ms(g);
	g->level += dir;
	g->over_since = g->under_since = -1;
	g->settle_until = now_s + SETTLE_S;
	if (dir > 0) {
		g->steps_down++;
		/* the step up just before did not hold: wait twice as long next
		 * time (a sure climb that did not hold met a heavier view, not a
		 * cost it guessed wrong) */
		if (g->last_up_s >= 0 && !g->last_up_sure && now_s - g->last_up_s < FAILED_UP_S)
			g->up_wait_s = fmin(g->up_wait_s * 2, UP_WAIT_MAX_S);
		g->up_judged = true; /* the step up before, held or not, is judged */
	} else {
		g->steps_up++;
		g->last_up_s = now_s;
		g->up_judged = false;
	}
}

/* Settled after a step: what it cost, the time held at the upper of the
 * two levels over that at the lower, read a settle apart (the same view,
 * nearly), averaged with what the last step between them said. */
static void learn(struct governor *g)
{
	double now = governor_held_ms(g);
	int from = g->learn_from;
	g->learn_from = -1;
	/* a step down forced by a hitch or a jump of the view says nothing of the step */
	if (from < 0 || g->learn_held <= 0 || now <= 0 || g->learn_held > LEARN_MAX * g->target_ms)
		return;
	bool went_up = from > g->level;
	int lower = went_up ? from : g->level;
	double upper_ms = went_up ? now : g->learn_held, lower_ms = went_up ? g->learn_held : now;
	double c = fmin(fmax(upper_ms / lower_ms, COST_MIN), COST_MAX);
	g->up_cost[lower] = g->up_cost[lower] > 0 ? (float)(0.5 * (g->up_cost[lower] + c)) : (float)c;
}

/* Whether the level above fits: held times that step's cost under
 * target * FIT.  The cost is what was measured, at most what the fixed
 * line assumes (FIT / UNDER: up only under target * UNDER); a measure
 * can only let it climb sooner than that line, never hold it lower (a
 * step measured while the view grew heavier says too much). */
static bool above_fits(const struct governor *g, double held)
{
	double c = g->up_cost[g->level], line = FIT / UNDER;
	return held * (c > 0 && c < line ? c : line) < g->target_ms * FIT;
}

/* How many levels up are sure to fit: held times the fixed line's cost
 * for every one of them and for one more, under target * FIT (a view
 * lighter by that much, the sky or the land far below: a climb the
 * learnt costs need not be asked about, and no gamble to wait for).  At
 * 30 fps a frame held under 20.8 ms climbs one level, one under 7 ms
 * seven. */
static int sure_steps(const struct governor *g, double held)
{
	double line = FIT / UNDER, x = held * line * line;
	int k = 0;
	while (k < g->level && x < g->target_ms * FIT) {
		k++;
		x *= line;
	}
	return k;
}

/* How many levels down a frame far over the target takes at once: while
 * the mean frame (not the deviation: a hitch's) is over LEARN_MAX times the
 * target, a level each, each assumed to save what the fixed line assumes
 * (FIT / UNDER).  Those steps would learn no cost (learn: LEARN_MAX), and
 * one at a time they left a view three times the target over it for 7-8 s
 * (test_governor's heavy load: ten steps, 0.75 s each); the last steps,
 * nearer the target, are taken one at a time and learnt. */
static int far_steps(const struct governor *g)
{
	double line = FIT / UNDER, x = g->smooth_ms;
	int k = 0;
	while (g->level + k < GOVERNOR_LEVELS - 1 && x > LEARN_MAX * g->target_ms) {
		k++;
		x /= line;
	}
	return k > 1 ? k : 1;
}

static void decide(struct governor *g, double now_s)
{
	double over = g->target_ms * OVER, held = governor_held_ms(g);
	int sure = sure_steps(g, held);
	if (held > over) {
		g->under_since = -1;
		if (g->over_since < 0)
			g->over_since = now_s;
		if (now_s - g->over_since >= OVER_FOR_S && g->level < GOVERNOR_LEVELS - 1)
			step(g, far_steps(g), now_s);
	} else if (g->level > 0 && (sure > 0 || above_fits(g, held))) {
		g->over_since = -1;
		if (g->under_since < 0)
			g->under_since = now_s;
		if (now_s - g->under_since >= (sure > 0 ? SURE_S : g->up_wait_s)) {
			step(g, sure > 0 ? -sure : -1, now_s);
			g->last_up_sure = sure > 0;
		}
	} else {
		g->over_since = g->under_since = -1;
		/* a long quiet spell at a level: trust steps up again */
		if (g->last_up_s >= 0 && now_s - g->last_up_s > 4 * UP_WAIT_MAX_S)
			g->up_wait_s = UP_WAIT_MIN_S;
	}
}

struct governor_quality governor_update(struct governor *g, double frame_ms, double now_s)
{
	if (!(frame_ms >= 0) || !isfinite(frame_ms))
		frame_ms = g->target_ms; /* a clock that jumped tells nothing */
	/* a frame far over the line (a hitch) moves the averages by at most
	 * what one 4 targets over the mean would */
	if (g->smooth_ms < 0) {
		g->smooth_ms = frame_ms;
		g->smooth_var = 0;
	} else {
		double d = fmin(frame_ms, g->smooth_ms + 4 * g->target_ms) - g->smooth_ms;
		g->smooth_ms += SMOOTH * d;
		/* the deviation's average, as the mean's (West's incremental form) */
		g->smooth_var = (1 - SMOOTH) * (g->smooth_var + SMOOTH * d * d);
	}
	if (now_s >= g->settle_until) {
		if (g->learn_from >= 0)
			learn(g);
		/* a step up that has held a while: the next try need not wait as long */
		if (g->last_up_s >= 0 && !g->up_judged && now_s - g->last_up_s >= FAILED_UP_S) {
			g->up_wait_s = fmax(g->up_wait_s / 2, UP_WAIT_MIN_S);
			g->up_judged = true;
		}
		decide(g, now_s);
	}
	struct governor_quality q = ladder[g->level];
	g->scale_sum += q.render_scale;
	g->view_sum += q.view_distance;
	g->near_sum += q.near_lod;
	g->frames++;
	return q;
}

void governor_apply(const struct governor_quality *q, const struct params *p, struct params *eff)
{
	*eff = *p;
	eff->gen_budget_ms = p->gen_budget_ms * q->gen_budget;
	eff->ao_rays = (int)lroundf((float)p->ao_rays * q->ao_rays);
	eff->shadow_steps = (int)lroundf((float)p->shadow_steps * q->shadow_steps);
	eff->view_distance = p->view_distance * q->view_distance;
	eff->lod_distance = p->lod_distance * q->near_lod;
}

double governor_mean_scale(const struct governor *g)
{
	return g->frames ? g->scale_sum / g->frames : 1.0;
}

double governor_mean_view(const struct governor *g)
{
	return g->frames ? g->view_sum / g->frames : 1.0;
}

double governor_mean_near_lod(const struct governor *g)
{
	return g->frames ? g->near_sum / g->frames : 1.0;
}
