/* isoterra — the kiosk's autopilot: a fly-through that never enters rock
 * and never hovers.
 *
 * A fixed-step simulation (60 steps per second, so the same seed and time
 * always give the same flight).  The density function it reads is the CPU
 * mirror of the shader's (exactly the same terrain), and density behaves
 * roughly like a signed distance: negative is air, its gradient points
 * into the rock.
 *
 *  - Spawn: a column is scanned from the sky down to fly_height of air above
 *    the first surface met; where that finds no clearance (the endless
 *    caves, an overhang), shells of points around the origin are searched
 *    for the nearest one with room around it.
 *  - Plan (10 times a second): the heading wanders with slow seeded sines;
 *    a fan of directions around it is sampled ahead and the clearest one
 *    is steered to, as the chapter's dragonflies do, tilting up or down to
 *    hold fly_height of air ("up" is the planet's radius in planet mode, so
 *    the flight orbits the planet).
 *  - Move: every step travels fly_speed.  A step that would come within
 *    fly_clearance of rock slides along the surface instead (the heading's
 *    part into the rock removed), then tries straight away from the rock,
 *    then up; a step into more air is always allowed.
 *  - Progress: if the camera has not travelled one second's distance in two
 *    seconds (a dead end, a corner), it turns fast towards the longest free
 *    ray of a full sphere of directions and commits to it for a while. */
#include "world.h"
#include "core.h"
#include "terrain.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STEP (1.0 / 60.0)
#define PLAN_EVERY 6   /* steps between plans */
#define STUCK_S 2.0f   /* seconds without one second's travel: escape */
#define ESCAPE_S 3.0f  /* seconds an escape heading is held */
#define CALM_TURN 0.3f /* rad/s: a calm, cinematic turn */
#define FAST_TURN 2.0f /* rad/s: blocked or escaping */

static float dens(const struct autopilot *a, const float p[3])
{
	return density_ref(a->p, a->ns, a->ed, p[0], p[1], p[2]);
}

static float dot3(const float a[3], const float b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const float a[3], const float b[3], float o[3])
{
	o[0] = a[1] * b[2] - a[2] * b[1];
	o[1] = a[2] * b[0] - a[0] * b[2];
	o[2] = a[0] * b[1] - a[1] * b[0];
}

static float norm3(float v[3])
{
	float l = sqrtf(dot3(v, v));
	if (l > 1e-12f)
		for (int k = 0; k < 3; k++)
			v[k] /= l;
	return l;
}

/* v rotated by angle around the unit axis (Rodrigues). */
static void rotate3(float v[3], const float axis[3], float angle)
{
	float c = cosf(angle), s = sinf(angle), kx[3], kd = dot3(axis, v), o[3];
	cross3(axis, v, kx);
	for (int k = 0; k < 3; k++)
		o[k] = v[k] * c + kx[k] * s + axis[k] * kd * (1.0f - c);
	memcpy(v, o, sizeof(o));
}

/* Rotates v by the smallest rotation taking unit a to unit b. */
static void transport(float v[3], const float a[3], const float b[3])
{
	float axis[3];
	cross3(a, b, axis);
	float s = norm3(axis);
	if (s > 1e-7f)
		rotate3(v, axis, atan2f(s, dot3(a, b)));
}

/* Local up: away from the planet's centre, else +y. */
static void local_up(const struct autopilot *a, const float p[3], float up[3])
{
	if (a->p->shape == SHAPE_PLANET) {
		float v[3] = { p[0], p[1] + a->p->planet_radius, p[2] };
		if (norm3(v) > 1e-6f) {
			memcpy(up, v, sizeof(v));
			return;
		}
	}
	up[0] = 0.0f, up[1] = 1.0f, up[2] = 0.0f;
}

/* Unit gradient of the density (points into the rock). */
static void gradient(const struct autopilot *a, const float p[3], float g[3])
{
	const float h = 0.25f;
	for (int k = 0; k < 3; k++) {
		float q0[3] = { p[0], p[1], p[2] }, q1[3] = { p[0], p[1], p[2] };
		q0[k] -= h;
		q1[k] += h;
		g[k] = dens(a, q1) - dens(a, q0);
	}
	if (norm3(g) < 1e-12f)
		local_up(a, p, g), g[0] = -g[0], g[1] = -g[1], g[2] = -g[2];
}

/* Length of air (need of clearance kept) along a ray, up to len, in n
 * samples. */
static float free_length(const struct autopilot *a, const float from[3], const float dir[3], float len, int n, float need)
{
	for (int i = 1; i <= n; i++) {
		float t = len * (float)i / (float)n, q[3];
		for (int k = 0; k < 3; k++)
			q[k] = from[k] + dir[k] * t;
		if (dens(a, q) > -need)
			return len * (float)(i - 1) / (float)n;
	}
	return len;
}

/* A unit direction tilted from the tangent t towards up. */
static void tilted(const float t[3], const float up[3], float tilt, float out[3])
{
	for (int k = 0; k < 3; k++)
		out[k] = t[k] * cosf(tilt) + up[k] * sinf(tilt);
}

/* The heading's part in the tangent plane (any tangent if it has none). */
static void tangent_of(const float dir[3], const float up[3], float t[3])
{
	float d = dot3(dir, up);
	for (int k = 0; k < 3; k++)
		t[k] = dir[k] - up[k] * d;
	if (norm3(t) < 1e-4f) {
		const float x[3] = { 1.0f, 0.0f, 0.0f }, z[3] = { 0.0f, 0.0f, 1.0f };
		cross3(up, fabsf(up[0]) < 0.9f ? x : z, t);
		norm3(t);
	}
}

/* fly_height of air above the first surface met coming down the column at
 * (x, z) from above the highest rock; false where that has no clearance. */
static bool spawn_column(struct autopilot *a, float x, float z)
{
	const struct params *p = a->p;
	float pos[3] = { x, 2.0f * p->noise_amp + p->warp_amp + 4.0f * p->fly_height, z };
	if (dens(a, pos) > -2.0f * p->fly_clearance)
		return false; /* no sky above (caves) */
	for (int i = 0; i < 8000 && dens(a, pos) < -2.0f * p->fly_height; i++)
		pos[1] -= 0.25f;
	while (dens(a, pos) > -2.0f * p->fly_clearance && pos[1] < 1e5f)
		pos[1] += 0.25f; /* came down onto an overhang: back up into air */
	memcpy(a->pos, pos, sizeof(pos));
	return true;
}

/* The nearest point around the origin with room around it (shells of a
 * lattice, growing). */
static bool spawn_shells(struct autopilot *a)
{
	const float need = -3.0f * a->p->fly_clearance, st = 1.5f;
	for (int r = 0; r <= 40; r++) {
		float best = need, at[3] = { 0, 0, 0 };
		for (int i = -r; i <= r; i++)
			for (int j = -r; j <= r; j++)
				for (int k = -r; k <= r; k++) {
					if (abs(i) != r && abs(j) != r && abs(k) != r)
						continue;
					float q[3] = { (float)i * st, (float)j * st, (float)k * st };
					float d = dens(a, q);
					if (d < best)
						best = d, memcpy(at, q, sizeof(at));
				}
		if (best < need) {
			memcpy(a->pos, at, sizeof(at));
			return true;
		}
	}
	return false;
}

/* The first heading: along x, turned towards z (params.h) */
#define START_HEADING FLY_START_HEADING

/* Air all along the segment from p to q (its last tenth may touch rock). */
static bool clear_sight(const struct autopilot *a, const float p[3], const float q[3])
{
	for (int i = 1; i < 58; i++) {
		float s = (float)i / 64.0f, r[3] = { p[0] + (q[0] - p[0]) * s, p[1] + (q[1] - p[1]) * s,
						     p[2] + (q[2] - p[2]) * s };
		if (dens(a, r) > 0.0f)
			return false;
	}
	return true;
}

/* A landing pad (flat_spot): start back from it along the first heading,
 * where the pad's centre can be seen over the ground between. */
static bool spawn_before_pad(struct autopilot *a)
{
	const struct params *p = a->p;
	static const float back[] = { 1.2f, 1.6f, 2.2f, 3.0f };
	const float pad[3] = { p->flat_x, p->flat_y + 0.5f, p->flat_z };
	for (size_t i = 0; i < ARRAY_SIZE(back); i++) {
		float d = back[i] * fmaxf(p->flat_outer, 4.0f);
		if (spawn_column(a, p->flat_x - d * cosf(START_HEADING), p->flat_z - d * sinf(START_HEADING)) &&
		    clear_sight(a, a->pos, pad))
			return true;
	}
	return false;
}

static void spawn(struct autopilot *a)
{
	if (a->p->flat_spot && a->p->shape == SHAPE_GROUND && spawn_before_pad(a))
		return;
	for (int i = 0; i < 16; i++) {
		float ang = (float)i * 2.4f, rad = 6.0f * sqrtf((float)i);
		if (spawn_column(a, a->p->fly_x + rad * cosf(ang), a->p->fly_z + rad * sinf(ang)))
			return;
	}
	if (!spawn_shells(a))
		a->pos[0] = a->pos[1] = a->pos[2] = 0.0f; /* solid rock everywhere: nowhere better */
}

/* Caves: the level heading with the longest run of air from the spawn
 * point (24 headings, marched in steps of 0.5 up to 60 units), so the
 * first frame looks down a passage instead of at the nearest wall. */
static void open_heading(const struct autopilot *a, float out[3])
{
	float best = -1.0f;
	for (int i = 0; i < 24; i++) {
		float ang = 0.3f + (float)i * (6.2831853f / 24.0f), d[3] = { cosf(ang), 0.0f, sinf(ang) }, run = 0.0f;
		for (; run < 60.0f; run += 0.5f) {
			float q[3] = { a->pos[0] + d[0] * run, a->pos[1], a->pos[2] + d[2] * run };
			if (dens(a, q) > -a->p->fly_clearance)
				break;
		}
		if (run > best) {
			best = run;
			memcpy(out, d, sizeof(d));
		}
	}
}

/* The view's tilt below the heading: over open ground (shape ground, a
 * heightmap) as far down as the ground below is high, so the centre of the
 * frame falls on the ground VIEW_AHEAD fly_heights ahead (28 units at the
 * default 7; a map's flight, a twentieth of the map up, looks a fifth of
 * it ahead) and the land fills it, the horizon in its upper third: high
 * over a valley it looks down into it, low over a plain it looks out over
 * it (tan 0.15 .. 0.6, 8.5 .. 31 degrees), for the flight's first three
 * seconds, then eased up to the cruise's 8.5 degrees.  Caves look level
 * ahead, a planet and a landing pad have their own (autopilot_camera). */
#define VIEW_AHEAD 4.0f
#define VIEW_DOWN_MIN 0.15f
#define VIEW_DOWN_MAX 0.6f
#define VIEW_DOWN_S 1.5 /* the tilt follows the ground this slowly (time constant) */
#define VIEW_FRAMED_S 3.0 /* the flight's first seconds framed so (a kiosk is judged in three) ... */
#define VIEW_EASE_S 2.0   /* ... then eased up to the cruise's VIEW_DOWN_MIN in these */
static float view_down_target(const struct autopilot *a)
{
	if (a->p->shape != SHAPE_GROUND)
		return VIEW_DOWN_MIN;
	/* the ground's depth below the camera's height in five columns along
	 * the heading, 0 .. VIEW_AHEAD ahead: their median (a floating rock
	 * under one of them does not tip the view) */
	float up[3], down[3], h[5], ahead = VIEW_AHEAD * a->p->fly_height;
	local_up(a, a->pos, up);
	for (int k = 0; k < 3; k++)
		down[k] = -up[k];
	for (int i = 0; i < 5; i++) {
		float at[3];
		for (int k = 0; k < 3; k++)
			at[k] = a->pos[k] + a->dir[k] * ahead * (float)i * 0.25f;
		h[i] = free_length(a, at, down, 2.0f * ahead, 32, 0.0f);
		if (a->p->water) /* the sea is the ground to frame, not its floor */
			h[i] = fminf(h[i], fmaxf(at[1] - a->p->water_level, 0.0f));
	}
	for (int i = 0; i < 5; i++) /* sorted: five values */
		for (int j = i + 1; j < 5; j++)
			if (h[j] < h[i]) {
				float t = h[i];
				h[i] = h[j];
				h[j] = t;
			}
	/* ... but never so far down that the end of the view (view_distance
	 * away, that far below) leaves the frame's upper part: the horizon
	 * stays 15 % under the frame's top edge or lower (a map's flight, high
	 * over a large map, would look at the ground only) */
	float fov = a->p->fov * 3.14159265f / 180.0f;
	float cap = tanf(atan2f(h[2], a->p->view_distance) + 0.35f * fov);
	float framed = fminf(fmaxf(fminf(h[2] / ahead, cap), VIEW_DOWN_MIN), VIEW_DOWN_MAX);
	/* The first seconds are the composed ones; then the view eases up to
	 * the cruise's tilt over VIEW_EASE_S: land filling the frame is the
	 * frame's whole cost on a software rasterizer (the world at 640x480,
	 * full quality: p50 22-25 ms looking 8.5 degrees down, 40 ms at tan
	 * 0.35, 52 ms at up to 0.6; docs/WORLD.md) */
	float e = (float)((a->t - VIEW_FRAMED_S) / VIEW_EASE_S);
	e = fminf(fmaxf(e, 0.0f), 1.0f);
	framed += (VIEW_DOWN_MIN - framed) * e * e * (3.0f - 2.0f * e);
	/* the governor's first step gives the framing up (governor.c) */
	return VIEW_DOWN_MIN + (framed - VIEW_DOWN_MIN) * fminf(fmaxf(a->framing, 0.0f), 1.0f);
}

int autopilot_init(struct autopilot *a, const struct params *p, const struct edits *ed)
{
	memset(a, 0, sizeof(*a));
	a->framing = 1.0f;
	a->p = p;
	a->ed = ed;
	a->ns = malloc(sizeof(*a->ns));
	if (!a->ns)
		return -1;
	noise_set_init(a->ns, p->seed);
	spawn(a);
	float up[3], t[3];
	local_up(a, a->pos, up);
	float start[3] = { cosf(START_HEADING), 0.0f, sinf(START_HEADING) };
	if (p->shape == SHAPE_CAVES)
		open_heading(a, start);
	tangent_of(start, up, t);
	memcpy(a->dir, t, sizeof(t));
	memcpy(a->goal, t, sizeof(t));
	memcpy(a->anchor, a->pos, sizeof(a->pos));
	a->yaw = atan2f(a->dir[2], a->dir[0]);
	a->pitch = asinf(fmaxf(-1.0f, fminf(1.0f, a->dir[1])));
	a->min_clearance_seen = -dens(a, a->pos);
	a->view_down = view_down_target(a); /* the first frame framed at once */
	return 0;
}

void autopilot_free(struct autopilot *a)
{
	free(a->ns);
	a->ns = NULL;
}

/* Tilt (towards up) that holds fly_height of air; caves: level. */
static float height_tilt(const struct autopilot *a)
{
	const struct params *p = a->p;
	if (p->shape == SHAPE_CAVES)
		return 0.0f;
	float here = dens(a, a->pos);
	if (here > -p->fly_height)
		return 0.35f;
	if (here < -2.5f * p->fly_height)
		return -0.3f;
	return 0.0f;
}

/* The clearest direction of a fan around the wandering wish. */
static void plan(struct autopilot *a)
{
	const struct params *p = a->p;
	float up[3], want[3];
	local_up(a, a->pos, up);
	tangent_of(a->dir, up, want);
	float t = (float)a->t, seedph = (float)(p->seed % 1000) * 0.137f;
	rotate3(want, up, 0.25f * sinf(0.11f * t + seedph) * (float)(STEP * PLAN_EVERY) * 6.0f);
	float look = fmaxf(4.0f, p->fly_speed * 2.5f), pref = height_tilt(a), best = 1e30f;
	static const float dy[] = { 0.0f, 0.35f, -0.35f, 0.7f, -0.7f, 1.2f, -1.2f, 2.0f, -2.0f, 3.14159f };
	static const float dp[] = { 0.0f, 0.35f, -0.35f, 0.7f, -0.7f };
	for (size_t i = 0; i < ARRAY_SIZE(dy); i++)
		for (size_t j = 0; j < ARRAY_SIZE(dp); j++) {
			float tg[3] = { want[0], want[1], want[2] }, d[3];
			rotate3(tg, up, dy[i]);
			tilted(tg, up, dp[j], d);
			float room = free_length(a, a->pos, d, look, 6, p->fly_clearance * 1.5f);
			/* prefer clear, then straight, then the height-holding tilt */
			float cost = (1.0f - room / look) * 10.0f + fabsf(dy[i]) * 0.5f + fabsf(dp[j] - pref) * 0.6f;
			if (cost < best)
				best = cost, memcpy(a->goal, d, sizeof(d));
		}
}

/* Stuck: head for the longest free ray of a sphere of directions. */
static void escape(struct autopilot *a)
{
	float up[3], t0[3], best = -1.0f, look = fmaxf(8.0f, a->p->fly_speed * 3.0f);
	local_up(a, a->pos, up);
	tangent_of(a->dir, up, t0);
	static const float tilts[] = { 0.0f, 0.4f, -0.4f, 0.9f, -0.9f, 1.5f };
	for (int i = 0; i < 12; i++)
		for (size_t j = 0; j < ARRAY_SIZE(tilts); j++) {
			float tg[3] = { t0[0], t0[1], t0[2] }, d[3];
			rotate3(tg, up, 0.5236f * (float)(i + 3)); /* sideways and back first */
			tilted(tg, up, tilts[j], d);
			float len = free_length(a, a->pos, d, look, 12, a->p->fly_clearance);
			if (len > best)
				best = len, memcpy(a->escape, d, sizeof(d));
		}
	memcpy(a->goal, a->escape, sizeof(a->goal));
	a->escape_until = a->t + ESCAPE_S;
}

/* Turns the heading towards the goal by at most rate * STEP. */
static void turn_to_goal(struct autopilot *a, float rate)
{
	float axis[3];
	cross3(a->dir, a->goal, axis);
	float s = norm3(axis), ang = atan2f(s, dot3(a->dir, a->goal));
	if (s < 1e-6f) {
		if (ang < 0.5f)
			return;
		local_up(a, a->pos, axis); /* straight behind: turn around up */
	}
	rotate3(a->dir, axis, fminf(ang, rate * (float)STEP));
	norm3(a->dir);
}

/* A step to next keeps need of clearance there (or gains air), and the
 * segment to it stays in air (sampled every 0.1 units: no wall crossed). */
static bool allowed(const struct autopilot *a, const float next[3], float here, float need)
{
	float d = dens(a, next);
	if (d > -need && d >= here)
		return false;
	float dx[3] = { next[0] - a->pos[0], next[1] - a->pos[1], next[2] - a->pos[2] };
	int n = (int)ceilf(sqrtf(dot3(dx, dx)) / 0.1f);
	for (int i = 1; i < n; i++) {
		float f = (float)i / (float)n, q[3] = { a->pos[0] + dx[0] * f, a->pos[1] + dx[1] * f, a->pos[2] + dx[2] * f };
		if (dens(a, q) >= 0.0f)
			return false;
	}
	return true;
}

/* One step of fly_speed: ahead, else sliding along the rock, else away
 * from it, else up; in a tight spot shorter steps, then with less of the
 * clearance kept (never less than a fifth of it).  A way other than ahead
 * becomes the heading.  Returns false when it had to deviate. */
static bool move(struct autopilot *a)
{
	float v = a->p->fly_speed * (float)STEP, here = dens(a, a->pos), n[3], up[3], next[3];
	float tries[4][3];
	memcpy(tries[0], a->dir, sizeof(a->dir));
	gradient(a, a->pos, n);
	float into = fmaxf(dot3(a->dir, n), 0.0f);
	for (int k = 0; k < 3; k++) {
		tries[1][k] = a->dir[k] - n[k] * (into + 0.3f);
		tries[2][k] = -n[k];
	}
	norm3(tries[1]);
	local_up(a, a->pos, up);
	memcpy(tries[3], up, sizeof(up));
	static const float keep[3] = { 1.0f, 0.5f, 0.2f }, len[3] = { 1.0f, 0.5f, 0.25f };
	for (int c = 0; c < 3; c++)
		for (int s = 0; s < 3; s++)
			for (int i = 0; i < 4; i++) {
				for (int k = 0; k < 3; k++)
					next[k] = a->pos[k] + tries[i][k] * v * len[s];
				if (allowed(a, next, here, a->p->fly_clearance * keep[c])) {
					memcpy(a->pos, next, sizeof(next));
					if (i > 0) { /* follow the way it went, not the wall */
						for (int k = 0; k < 3; k++)
							a->dir[k] += 2.0f * tries[i][k];
						norm3(a->dir);
						memcpy(a->goal, tries[i], sizeof(a->goal));
					}
					return i == 0 && s == 0 && c == 0;
				}
			}
	return false;
}

static void step_auto(struct autopilot *a)
{
	if (a->t >= a->escape_until && (a->tick++ % PLAN_EVERY == 0 || a->blocked))
		plan(a);
	turn_to_goal(a, a->blocked || a->t < a->escape_until ? FAST_TURN : CALM_TURN);
	float up0[3], up1[3];
	local_up(a, a->pos, up0);
	a->blocked = !move(a);
	if (a->blocked)
		a->escape_until = 0.0; /* an escape that meets rock is re-planned */
	/* planet: carry the heading over the curvature (parallel transport) */
	local_up(a, a->pos, up1);
	transport(a->dir, up0, up1);
	transport(a->goal, up0, up1);
	transport(a->escape, up0, up1);
	float dx[3] = { a->pos[0] - a->anchor[0], a->pos[1] - a->anchor[1], a->pos[2] - a->anchor[2] };
	if (sqrtf(dot3(dx, dx)) >= a->p->fly_speed * 1.0f) {
		memcpy(a->anchor, a->pos, sizeof(a->pos));
		a->anchor_t = a->t;
	} else if (a->t - a->anchor_t > STUCK_S) {
		escape(a);
		a->anchor_t = a->t;
	}
	a->yaw = atan2f(a->dir[2], a->dir[0]);
	a->pitch = asinf(fmaxf(-1.0f, fminf(1.0f, a->dir[1])));
	a->view_down += (view_down_target(a) - a->view_down) * (float)(1.0 - exp(-STEP / VIEW_DOWN_S));
}

static void heading(float yaw, float pitch, float out[3])
{
	out[0] = cosf(pitch) * cosf(yaw);
	out[1] = sinf(pitch);
	out[2] = cosf(pitch) * sinf(yaw);
}

/* Manual flight (camera=manual): the held input moves and turns the camera;
 * the same collision rule applies, so a developer cannot fly into rock
 * either: a move that would come within fly_clearance of rock is tried
 * without its vertical part, then horizontally only along each axis, and
 * otherwise not taken. */
static void step_manual(struct autopilot *a)
{
	const struct params *p = a->p;
	float rate = 1.2f * (float)STEP;
	a->yaw += a->in_turn[0] * rate;
	a->pitch = fmaxf(-1.4f, fminf(1.4f, a->pitch + a->in_turn[1] * rate));
	heading(a->yaw, a->pitch, a->dir);
	float right[3] = { -sinf(a->yaw), 0.0f, cosf(a->yaw) };
	float v = p->fly_speed * (float)STEP, mv[3];
	for (int k = 0; k < 3; k++)
		mv[k] = (a->dir[k] * a->in_move[0] + right[k] * a->in_move[1]) * v;
	mv[1] += a->in_move[2] * v;
	const float tries[4][3] = { { 1, 1, 1 }, { 1, 0, 1 }, { 1, 0, 0 }, { 0, 0, 1 } };
	float here = dens(a, a->pos);
	for (int i = 0; i < 4; i++) {
		float next[3];
		for (int k = 0; k < 3; k++)
			next[k] = a->pos[k] + mv[k] * tries[i][k];
		if (allowed(a, next, here, p->fly_clearance)) {
			memcpy(a->pos, next, sizeof(next));
			break;
		}
	}
}

void autopilot_steer(struct autopilot *a, const float move_in[3], const float turn[2])
{
	a->manual = true;
	for (int k = 0; k < 3; k++)
		a->in_move[k] = fmaxf(-1.0f, fminf(1.0f, move_in[k]));
	for (int k = 0; k < 2; k++)
		a->in_turn[k] = fmaxf(-1.0f, fminf(1.0f, turn[k]));
}

void autopilot_resume(struct autopilot *a)
{
	a->manual = false;
	memcpy(a->goal, a->dir, sizeof(a->goal));
	memcpy(a->anchor, a->pos, sizeof(a->anchor));
	a->anchor_t = a->t;
	a->escape_until = 0;
	a->blocked = false;
}

void autopilot_advance(struct autopilot *a, double t)
{
	while (a->t + STEP * 0.5 < t) {
		if (a->manual)
			step_manual(a);
		else
			step_auto(a);
		a->min_clearance_seen = fminf(a->min_clearance_seen, -dens(a, a->pos));
		a->t += STEP;
	}
}

void autopilot_camera(const struct autopilot *a, struct camera *c, float fov, float aspect, float far)
{
	/* look along the heading, a little down, from the current position;
	 * over a planet down to 10 degrees under its horizon (the horizon
	 * dips by acos(radius / distance from the centre)) */
	float up[3], down = a->manual ? VIEW_DOWN_MIN : a->view_down;
	local_up(a, a->pos, up);
	if (a->p->shape == SHAPE_PLANET) {
		float cv[3] = { a->pos[0], a->pos[1] + a->p->planet_radius, a->pos[2] };
		float dist = sqrtf(dot3(cv, cv));
		if (dist > a->p->planet_radius) {
			/* high above a small planet (1.6 to 2.4 radii from its centre)
			 * the view turns down to its centre: the whole planet in frame */
			float th = fmaxf(acosf(a->p->planet_radius / dist) - 0.17f, 0.15f);
			float s = fminf(fmaxf((dist / a->p->planet_radius - 1.6f) / 0.8f, 0.0f), 1.0f);
			th += (1.52f - th) * s * s * (3.0f - 2.0f * s);
			down = tanf(th);
		}
	}
	const struct params *p = a->p;
	if (p->flat_spot && p->shape == SHAPE_GROUND) {
		/* a landing pad ahead and below: the view tips down towards its
		 * centre (fully within 1.5 outer radii, not beyond 3) */
		float to[3] = { p->flat_x - a->pos[0], 0.0f, p->flat_z - a->pos[2] };
		float dxz = sqrtf(to[0] * to[0] + to[2] * to[2]), r = fmaxf(p->flat_outer, 4.0f);
		float ahead = dxz > 1e-3f ? (to[0] * a->dir[0] + to[2] * a->dir[2]) / dxz : 0.0f;
		float near = fminf(fmaxf((3.0f * r - dxz) / (1.5f * r), 0.0f), 1.0f);
		float tip = fminf(fmaxf((a->pos[1] - p->flat_y) / fmaxf(dxz, 1.0f), 0.15f), 1.0f);
		float w = near * fminf(fmaxf((ahead - 0.3f) / 0.4f, 0.0f), 1.0f);
		down += (tip - down) * w * w * (3.0f - 2.0f * w);
	}
	float at[3];
	for (int k = 0; k < 3; k++)
		at[k] = a->pos[k] + (a->dir[k] - up[k] * down) * 10.0f;
	camera_look_up(c, a->pos, at, up, fov, aspect, 0.05f, far);
}
