/* isoterra — the kiosk's autopilot: a fly-through that never enters rock.
 *
 * A fixed-step simulation (60 steps per second, so the same seed and time
 * always give the same flight).  The heading wanders with slow seeded
 * sines; ahead of the camera the density function (the CPU mirror of the
 * shader's, so exactly the same terrain) is sampled along the heading and
 * along a fan of alternatives, and the clearest one is steered to, as the
 * chapter's dragonflies do.  Height is held near fly_height of air (density
 * behaves roughly like a signed distance), and a step that would bring the
 * camera within fly_clearance of rock is not taken: the camera climbs
 * instead. */
#include "world.h"
#include "util.h"
#include "density_ref.h"
#include "noise.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define STEP (1.0 / 60.0)

static float dens(const struct autopilot *a, const float p[3])
{
	return density_ref(a->p, a->ns, a->ed, p[0], p[1], p[2]);
}

/* Highest density (least clearance) along a ray of length len. */
static float worst_ahead(const struct autopilot *a, const float from[3], const float dir[3], float len)
{
	float worst = -1e30f;
	for (int i = 1; i <= 6; i++) {
		float t = len * (float)i / 6.0f, q[3];
		for (int k = 0; k < 3; k++)
			q[k] = from[k] + dir[k] * t;
		float d = dens(a, q);
		if (d > worst)
			worst = d;
	}
	return worst;
}

static void heading(float yaw, float pitch, float out[3])
{
	out[0] = cosf(pitch) * cosf(yaw);
	out[1] = sinf(pitch);
	out[2] = cosf(pitch) * sinf(yaw);
}

int autopilot_init(struct autopilot *a, const struct params *p, const struct edits *ed)
{
	memset(a, 0, sizeof(*a));
	a->p = p;
	a->ed = ed;
	a->ns = malloc(sizeof(*a->ns));
	if (!a->ns)
		return -1;
	noise_set_init(a->ns, p->seed);
	a->yaw = 0.3f;
	a->pitch = 0.0f;
	a->pos[0] = 0.0f;
	a->pos[2] = 0.0f;
	/* start in the open sky above the terrain and come down to fly_height
	 * of air above the first surface met (never inside a cave) */
	a->pos[1] = 2.0f * p->noise_amp + p->warp_amp + 4.0f * p->fly_height;
	for (int i = 0; i < 8000 && dens(a, a->pos) < -2.0f * p->fly_height; i++)
		a->pos[1] -= 0.25f;
	heading(a->yaw, a->pitch, a->dir);
	a->min_clearance_seen = 1e30f;
	return 0;
}

void autopilot_free(struct autopilot *a)
{
	free(a->ns);
	a->ns = NULL;
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
	for (int i = 0; i < 4; i++) {
		float next[3];
		for (int k = 0; k < 3; k++)
			next[k] = a->pos[k] + mv[k] * tries[i][k];
		if (dens(a, next) <= -p->fly_clearance || dens(a, next) < dens(a, a->pos)) {
			memcpy(a->pos, next, sizeof(next));
			break;
		}
	}
}

void autopilot_steer(struct autopilot *a, const float move[3], const float turn[2])
{
	a->manual = true;
	for (int k = 0; k < 3; k++)
		a->in_move[k] = fmaxf(-1.0f, fminf(1.0f, move[k]));
	for (int k = 0; k < 2; k++)
		a->in_turn[k] = fmaxf(-1.0f, fminf(1.0f, turn[k]));
}

static void step(struct autopilot *a)
{
	const struct params *p = a->p;
	if (a->manual) {
		step_manual(a);
		float margin = -dens(a, a->pos);
		if (margin < a->min_clearance_seen)
			a->min_clearance_seen = margin;
		a->t += STEP;
		return;
	}
	float t = (float)a->t;
	float seedph = (float)(p->seed % 1000) * 0.137f;
	/* wandering wish: slow, seeded, deterministic */
	float want_yaw = a->yaw + 0.25f * sinf(0.11f * t + seedph) * (float)STEP * 6.0f;
	float look = fmaxf(4.0f, p->fly_speed * 2.5f);
	float best_yaw = want_yaw, best_pitch = 0.0f, best = 1e30f;
	static const float dy[] = { 0.0f, 0.35f, -0.35f, 0.7f, -0.7f, 1.2f, -1.2f, 2.0f, -2.0f, 3.14159f };
	static const float dp[] = { 0.0f, 0.3f, 0.6f };
	for (size_t i = 0; i < ARRAY_SIZE(dy); i++)
		for (size_t j = 0; j < ARRAY_SIZE(dp); j++) {
			float d[3];
			heading(want_yaw + dy[i], dp[j], d);
			float wst = worst_ahead(a, a->pos, d, look);
			/* prefer clear, then straight, then level */
			float cost = fmaxf(wst + p->fly_clearance * 1.5f, 0.0f) * 100.0f + fabsf(dy[i]) * 0.5f + dp[j] * 0.3f;
			if (cost < best) {
				best = cost;
				best_yaw = want_yaw + dy[i];
				best_pitch = dp[j];
			}
		}
	/* hold height: density ~ -(height above ground) */
	float here = dens(a, a->pos);
	float climb = 0.0f;
	if (here > -p->fly_height)
		climb = 0.35f;
	else if (here < -2.5f * p->fly_height)
		climb = -0.25f;
	float rate = 0.3f * (float)STEP; /* rad per step: a calm, cinematic turn */
	float dyaw = remainderf(best_yaw - a->yaw, 2.0f * (float)M_PI);
	a->yaw += fmaxf(-rate, fminf(rate, dyaw));
	float tp = fmaxf(best_pitch, 0.0f) + climb;
	a->pitch += fmaxf(-rate, fminf(rate, tp - a->pitch));
	heading(a->yaw, a->pitch, a->dir);
	float next[3];
	for (int k = 0; k < 3; k++)
		next[k] = a->pos[k] + a->dir[k] * p->fly_speed * (float)STEP;
	if (dens(a, next) > -p->fly_clearance) {
		/* too close: do not move into it, climb straight up instead */
		next[0] = a->pos[0];
		next[2] = a->pos[2];
		next[1] = a->pos[1] + p->fly_speed * (float)STEP;
		if (dens(a, next) > dens(a, a->pos))
			next[1] = a->pos[1]; /* up is worse (overhang): hold */
	}
	memcpy(a->pos, next, sizeof(next));
	float margin = -dens(a, a->pos);
	if (margin < a->min_clearance_seen)
		a->min_clearance_seen = margin;
	a->t += STEP;
}

void autopilot_advance(struct autopilot *a, double t)
{
	while (a->t + STEP * 0.5 < t)
		step(a);
}

void autopilot_camera(const struct autopilot *a, struct camera *c, float fov, float aspect, float far)
{
	/* look along the heading, a little down, from the current position */
	float at[3] = { a->pos[0] + a->dir[0] * 10.0f, a->pos[1] + a->dir[1] * 10.0f - 1.5f,
			a->pos[2] + a->dir[2] * 10.0f };
	camera_look(c, a->pos, at, fov, aspect, 0.05f, far);
}
