/* isoterra — camera and the lit draw of the extracted mesh into an
 * offscreen (multisampled) framebuffer. */
#ifndef ISOTERRA_RENDER_H
#define ISOTERRA_RENDER_H

#include <stddef.h>
#include "params.h"
#include "grid.h"
#include "image.h"
#include "pipeline.h"

struct camera {
	float eye[3];
	float view[16], proj[16], viewproj[16]; /* column-major */
};

/* Orbit camera around the volume: yaw/pitch/dist from the parameters, the
 * yaw advancing cam_spin degrees per second of time t. */
void camera_orbit(struct camera *c, const struct params *p, const struct grid *g, float t, float aspect);
void mat4_mul(float out[16], const float a[16], const float b[16]);

struct renderer;
struct renderer *renderer_create(int width, int height, char *err, size_t errlen);
void renderer_destroy(struct renderer *r);
/* Draws the pipeline's mesh with its indirect command.  0 or -1. */
int renderer_draw(struct renderer *r, const struct pipeline_draw *d, const struct camera *c, const struct params *p);
/* Resolves and reads the last frame (top row first).  0 or -1. */
int renderer_read(struct renderer *r, struct image *img);

/* Resolves the last frame and blits it to the default framebuffer (the
 * window surface), scaled to w x h.  0 or -1. */
int renderer_blit_to_default(struct renderer *r, int w, int h);

/* Renders p->count frames with the current context and returns the last
 * one (tests, tools).  0 or -1 with err. */
int render_to_image(const struct params *p, struct image *img, char *err, size_t errlen);

/* The main job: render p->count frames headless, write p->out (and the mesh
 * to p->export_mesh).  Returns the process exit code. */
int run_headless(const struct params *p);

#endif
