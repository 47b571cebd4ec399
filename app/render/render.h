/* isoterra — camera and the lit draw of the extracted mesh into an
 * offscreen (multisampled, or smoothed after the frame) framebuffer. */
#ifndef ISOTERRA_RENDER_H
#define ISOTERRA_RENDER_H

#include <stddef.h>
#include "params.h"
#include "core.h"
#include "extract.h"

struct camera {
	float eye[3];
	float view[16], proj[16], viewproj[16]; /* column-major */
};

/* Orbit camera around the volume: yaw/pitch/dist from the parameters, the
 * yaw advancing cam_spin degrees per second of time t. */
void camera_orbit(struct camera *c, const struct params *p, const struct grid *g, float t, float aspect);
void mat4_mul(float out[16], const float a[16], const float b[16]);
/* A video wall's tile (params/wall.h): the camera, made with the whole
 * virtual screen's aspect (v->aspect), narrowed to the frame's rectangle of
 * it, an off-axis frustum.  No-op without a wall (v NULL or off). */
void camera_window(struct camera *c, const struct wall_view *v);
int mat4_invert(float out[16], const float m[16]);
/* Camera at eye looking at `at` (y up), vertical fov in degrees. */
void camera_look(struct camera *c, const float eye[3], const float at[3], float fov, float aspect, float zn, float zf);
/* The same with the given up direction (unit). */
void camera_look_up(struct camera *c, const float eye[3], const float at[3], const float up[3], float fov, float aspect,
		    float zn, float zf);

/* The eye's distance to the box lo .. hi (0 inside it). */
float camera_box_distance(const struct camera *c, const float lo[3], const float hi[3]);

/* The generated surface texture (albedo variation, bump slopes, height). */
GLuint surface_texture_create(void);

struct renderer;
/* A width x height target; antialias: an ANTIALIAS_* (params.def: auto is
 * 4x multisampling on a GPU, the filter after the frame on a software
 * rasterizer).  NULL with err. */
struct renderer *renderer_create(int width, int height, int antialias, char *err, size_t errlen);
void renderer_destroy(struct renderer *r);
/* The edge smoothing it uses (never ANTIALIAS_AUTO): a renderer made again
 * at another size (a window resized) keeps it. */
int renderer_antialias(const struct renderer *r);
/* The terrain's program for p built now, its base variant and the one
 * with the most in it (renderer_begin builds the base on the first frame
 * otherwise, a mesh the others when it asks): --probe checks them against
 * the GL limits with the other programs of the job.  0, or -1 (logged). */
int renderer_prepare(struct renderer *r, const struct params *p);
/* A frame in parts: begin (clear, program, camera), any number of meshes
 * drawn with their indirect commands (sink > 0 draws the mesh moved that
 * many world units along its normals into the rock: a level of detail
 * fading in or out hides behind the coarser one; dist: how near to the
 * eye the mesh comes, world units — from DETAIL_FINE_SHARE * DETAIL_RANGE
 * on it is shaded without the finer detail scale, from DETAIL_RANGE on
 * without the detail normals, which have faded out there), end. */
int renderer_begin(struct renderer *r, const struct camera *c, const struct params *p);
void renderer_draw_mesh(struct renderer *r, GLuint vbo, GLuint ibo, GLuint indirect, GLintptr offset, float sink,
			float dist);
int renderer_end(struct renderer *r);
/* The depth pre-pass of renderer_draw (the volume scene: one mesh in no
 * order): the mesh's depth laid down first, so each pixel is shaded once,
 * by its nearest surface, instead of once per layer drawn over it.  On by
 * default on a software rasterizer (every shaded fragment costs CPU time
 * there, and the second draw less) where the picture has at least a third
 * as many pixels as the mesh's capacity has triangles (a smaller picture
 * pays more for binning the mesh twice than it saves: renderer_draw),
 * off on a GPU (early depth tests there,
 * and vertex work twice on a tiler).  The world does not use it: its blocks
 * are drawn front to back already, and on llvmpipe its frames cost more
 * with it (640x480 governed fly-through under load, p50 38-41 ms without,
 * 46-55 with).  renderer_set_prepass: on or off for every picture size
 * (tests). */
void renderer_set_prepass(struct renderer *r, bool on);
bool renderer_prepass(const struct renderer *r);
/* renderer_draw's mesh in parts of at least `triangles` (more when its
 * capacity would need over 64 parts), each rasterized before the next is
 * binned; 0 draws it at once.  On a software rasterizer it is 16384 by
 * default: it bins a whole draw before it rasterizes any of it (llvmpipe:
 * 19.9 MB for the no-flag picture's 121 504 triangles, 2.8 MB in parts;
 * tests/test_parts.c).  Off on a GPU (a tiler would store and reload its
 * tiles at every part).  The picture is the same. */
#define RENDER_PART_TRIANGLES 16384
void renderer_set_parts(struct renderer *r, uint32_t triangles);
uint32_t renderer_parts(const struct renderer *r);
/* Water plane over the world rectangle x0,z0 - x1,z1 (after the terrain). */
void renderer_water(struct renderer *r, const struct camera *c, const struct params *p, const float rect[4]);
/* The governor's render scale (0.5 .. 1): later frames are drawn at that
 * fraction of the size and upscaled (sharp bilinear, edges kept) at
 * renderer_end, so overlays and sinks still see the full size.  0, or -1
 * with err (the upscale pass could not be made). */
int renderer_set_scale(struct renderer *r, float scale, char *err, size_t errlen);
/* The edge smoothing after the frame (--antialias fxaa, auto's choice on a
 * software rasterizer) on or off from the next frame (the governor's first
 * step); multisampling is not touched.  On by default. */
void renderer_set_smoothing(struct renderer *r, bool on);
/* The close-up detail's scales (render.frag's DETAIL_NORMALS) from the
 * next mesh drawn: 2 (the default), 1 (the governor's first step, with
 * the edge smoothing: the finer scale left out, every near mesh drawn
 * with the program of those beyond DETAIL_FINE_SHARE * DETAIL_RANGE) or 0
 * (its second: every mesh drawn with the program of those beyond
 * DETAIL_RANGE). */
void renderer_set_detail(struct renderer *r, int scales);
/* Paint on the ground: an RGBA16F texture over the XZ rectangle origin ..
 * origin + size, per texel (paint weight, surface ROAD_SURFACE_*, height
 * less y0); a fragment within tol of that height takes the surface's
 * colours (the edit state's road map, edits_road_map).  tex 0: none, and
 * the terrain's program is built without the term. */
void renderer_set_road_map(struct renderer *r, GLuint tex, const float origin[2], const float size[2], float y0,
			   float tol);
/* Lakes: water surfaces of their own, n of them, each (x0, z0, x1, z1,
 * level) — the rectangle around its rim and its surface's height (the edit
 * state's water areas, edits.h lakes); drawn after the terrain like the
 * sea, whether or not the sea is on.  The array is borrowed until the next
 * call.  n 0: none. */
void renderer_set_lakes(struct renderer *r, const float (*lakes)[5], int n);
/* Draws the lakes (renderer_set_lakes) inside rect (x0, z0, x1, z1). */
void renderer_lakes(struct renderer *r, const struct camera *c, const struct params *p, const float rect[4]);
/* Background colour (tests paint it a colour the terrain never has). */
void renderer_set_clear(struct renderer *r, float red, float green, float blue);
/* Draws the pipeline's mesh with its indirect command.  0 or -1. */
int renderer_draw(struct renderer *r, const struct pipeline_draw *d, const struct camera *c, const struct params *p);
/* The framebuffer the frame is drawn into (multisampled or not) and its
 * size: overlays (OSD) draw into it, the V4L2 output resolves from it. */
void renderer_target(const struct renderer *r, unsigned *fbo, int *w, int *h);
/* The finished frame on the target now, kept (the attract playlist's last
 * frame of a show), and later drawn over the target's frame with weight
 * alpha in 0..1 (its crossfade; fade.frag).  0, or -1 with err. */
int renderer_keep_frame(struct renderer *r, char *err, size_t errlen);
int renderer_fade_kept(struct renderer *r, float alpha);
/* Resolves and reads the last frame (top row first).  0 or -1. */
int renderer_read(struct renderer *r, struct image *img);

/* A panel turned `quarter` quarter turns clockwise (--rotate): the renderer
 * draws the upright picture at its own size, and renderer_read and
 * renderer_blit_to_default give the turned frame (width and height swapped
 * for odd turns).  renderer_target stays the upright picture's (overlays
 * draw into it and turn with it). */
void renderer_set_rotation(struct renderer *r, int quarter);
int renderer_rotation(const struct renderer *r);
/* A renderer for an output of w x h turned `quarter` quarter turns: the
 * upright picture's size (swapped for odd turns), the rotation set.  NULL
 * with err. */
struct renderer *renderer_create_turned(int w, int h, int quarter, int antialias, char *err, size_t errlen);
/* Resolves the last frame and blits it to the default framebuffer (the
 * window surface), scaled to w x h (turned, with a rotation).  0 or -1. */
int renderer_blit_to_default(struct renderer *r, int w, int h);

/* the on-screen display */
#include "osd.h"

#endif
