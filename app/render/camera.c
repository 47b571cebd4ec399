/* isoterra — orbit camera and 4x4 matrices (column-major, GL style). */
#include "render.h"

#include <math.h>
#include <string.h>

void mat4_mul(float out[16], const float a[16], const float b[16])
{
	float r[16];
	for (int c = 0; c < 4; c++)
		for (int row = 0; row < 4; row++) {
			float s = 0.0f;
			for (int k = 0; k < 4; k++)
				s += a[k * 4 + row] * b[c * 4 + k];
			r[c * 4 + row] = s;
		}
	memcpy(out, r, sizeof(r));
}

static void look_at(float m[16], const float eye[3], const float at[3], const float upv[3])
{
	float f[3] = { at[0] - eye[0], at[1] - eye[1], at[2] - eye[2] };
	float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
	for (int i = 0; i < 3; i++)
		f[i] /= fl;
	float up[3] = { upv[0], upv[1], upv[2] };
	float s[3] = { f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0] };
	float sl = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
	if (sl < 1e-6f) { /* looking along up: any side vector */
		s[0] = 1.0f, s[1] = s[2] = 0.0f;
		sl = 1.0f;
	}
	for (int i = 0; i < 3; i++)
		s[i] /= sl;
	float u[3] = { s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0] };
	float v[16] = {
		s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
		-(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]),
		-(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]),
		f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2], 1,
	};
	memcpy(m, v, sizeof(v));
}

static void perspective(float m[16], float fovy_deg, float aspect, float zn, float zf)
{
	float f = 1.0f / tanf(fovy_deg * (float)M_PI / 360.0f);
	memset(m, 0, sizeof(float) * 16);
	m[0] = f / aspect;
	m[5] = f;
	m[10] = (zf + zn) / (zn - zf);
	m[11] = -1.0f;
	m[14] = 2.0f * zf * zn / (zn - zf);
}

void camera_orbit(struct camera *c, const struct params *p, const struct grid *g, float t, float aspect)
{
	float size = g->cell * (float)g->nx;
	float center[3] = { g->origin[0] + 0.5f * size, g->origin[1] + 0.5f * g->cell * (float)g->ny,
			    g->origin[2] + 0.5f * g->cell * (float)g->nz };
	float yaw = (p->cam_yaw + p->cam_spin * t) * (float)M_PI / 180.0f;
	float pitch = p->cam_pitch * (float)M_PI / 180.0f;
	float dist = p->cam_dist * size;
	c->eye[0] = center[0] + dist * cosf(pitch) * cosf(yaw);
	c->eye[1] = center[1] + dist * sinf(pitch);
	c->eye[2] = center[2] + dist * cosf(pitch) * sinf(yaw);
	/* aim a little below the centre: terrain sits in the lower half (a
	 * planet: at its centre, the whole sphere in the middle of the frame) */
	float below = p->shape == SHAPE_PLANET ? 0.0f : 0.16f * size;
	float at[3] = { center[0], center[1] - below, center[2] };
	static const float up[3] = { 0.0f, 1.0f, 0.0f };
	look_at(c->view, c->eye, at, up);
	perspective(c->proj, p->fov, aspect, 0.01f * size, 8.0f * size + dist);
	mat4_mul(c->viewproj, c->proj, c->view);
}

void camera_look(struct camera *c, const float eye[3], const float at[3], float fov, float aspect, float zn, float zf)
{
	static const float up[3] = { 0.0f, 1.0f, 0.0f };
	camera_look_up(c, eye, at, up, fov, aspect, zn, zf);
}

void camera_look_up(struct camera *c, const float eye[3], const float at[3], const float up[3], float fov, float aspect,
		    float zn, float zf)
{
	memcpy(c->eye, eye, sizeof(c->eye));
	look_at(c->view, eye, at, up);
	perspective(c->proj, fov, aspect, zn, zf);
	mat4_mul(c->viewproj, c->proj, c->view);
}

float camera_box_distance(const struct camera *c, const float lo[3], const float hi[3])
{
	float d2 = 0;
	for (int a = 0; a < 3; a++) {
		float v = c->eye[a] < lo[a] ? lo[a] - c->eye[a] : c->eye[a] > hi[a] ? c->eye[a] - hi[a] : 0.0f;
		d2 += v * v;
	}
	return sqrtf(d2);
}

void camera_window(struct camera *c, const struct wall_view *v)
{
	if (!v || !v->on)
		return;
	/* the frame's rectangle of the whole screen's clip space stretched
	 * over the frame: x' = (2x - (x0 + x1) w) / (x1 - x0), the same in y
	 * (an off-axis frustum, exactly the whole screen's for those pixels) */
	float sx = 2.0f / (v->ndc[2] - v->ndc[0]), ox = -(v->ndc[0] + v->ndc[2]) / (v->ndc[2] - v->ndc[0]);
	float sy = 2.0f / (v->ndc[3] - v->ndc[1]), oy = -(v->ndc[1] + v->ndc[3]) / (v->ndc[3] - v->ndc[1]);
	for (int col = 0; col < 4; col++) {
		float *m = &c->proj[col * 4];
		m[0] = sx * m[0] + ox * m[3];
		m[1] = sy * m[1] + oy * m[3];
	}
	mat4_mul(c->viewproj, c->proj, c->view);
}

int mat4_invert(float out[16], const float m[16])
{
	float inv[16];
	inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
	inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
	inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
	inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
	inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
	inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
	inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
	inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
	inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
	inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
	inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
	inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
	inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
	inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
	inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
	inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
	float det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
	if (det == 0.0f)
		return -1;
	for (int i = 0; i < 16; i++)
		out[i] = inv[i] / det;
	return 0;
}
