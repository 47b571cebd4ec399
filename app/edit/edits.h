/* isoterra — terrain edits: the curves (roads, rivers, railways) and the
 * heightmap that the density function uses, their CPU data (loaded from
 * the files named by the curves / heightmap parameters, or set through the
 * API), the GL resources (curves_gl.c) and the CPU mirror of the shader
 * code (carve_ref.c).  See docs/CURVES.md.
 *
 * The edit state is an object owned by whoever creates it (the volume run,
 * the streaming world's owner, a test): the terrain field that carves it on
 * the GPU (app/terrain/terrain.h) and the CPU reference borrow it.  Its GL
 * objects belong to the context current when they were made; edits_destroy()
 * deletes them, edits_gl_release() earlier (the next bind uploads again). */
#ifndef ISOTERRA_EDITS_H
#define ISOTERRA_EDITS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <GLES3/gl31.h>

#include "curves.h"
#include "params.h"

/* ---- heightmap (heightmap.c) ---------------------------------------------- */

/* A georeferenced heightmap's place on the earth: its samples lie on the
 * local east-north-up grid of WGS84 at (lon0, lat0) (app/edit/geo_enu.h),
 * sample (i, j) at east (i - (w-1)/2) cell, north ((h-1)/2 - j) cell
 * metres, sample v at elevation zmin + v (zmax - zmin) / 65535 metres. */
struct heightmap_geo {
	bool on;
	double cell, lon0, lat0;
	double lonlat[4];   /* the raster's box: west, south, east, north */
	double zmin, zmax;  /* metres */
	int src_w, src_h;   /* the raster's own size and spacing (metres) */
	double src_res[2];
	int epsg;           /* 0: none known */
	bool projected;
	char crs[96], unit[32];
};

struct heightmap {
	int w, h;
	float *v; /* w*h samples 0..65535 as floats, x fastest, row z = 0 first */
	struct heightmap_geo geo; /* GeoTIFF with a geotransform and a CRS */
};
/* 16-bit (or 8-bit, scaled) grayscale PNG, or GeoTIFF (.tif/.tiff) through
 * GDAL when built with it (band 1, valid range mapped onto 0..65535,
 * no-data at the minimum; georeferenced: resampled onto the ENU grid,
 * hm->geo; a raster of colours refused; refused with a message without
 * GDAL).  0 or -1 with err. */
int heightmap_load(const char *path, struct heightmap *hm, char *err, size_t errlen);
/* The map's one-line description for the log: size, CRS, extent in metres
 * and lon/lat, elevation range (georeferenced maps). */
void heightmap_describe(const struct heightmap *hm, const char *path, char *line, size_t len);
/* A georeferenced map's placement in world units (app/edit/map_fit.c):
 * heightmap_scale / _base / _height from its cell and elevations, world =
 * metres x curves_geo_scale, heights x vertical_exaggeration too; with
 * p->fit the volume (vol_*), the camera's distance and the water (sea
 * level when the map spans it, else none) too, each only where p holds
 * the parameter's default.  Nothing for other maps. */
void heightmap_fit(const struct heightmap *hm, struct params *p);
/* heightmap_fit for the heightmap p names (field=heightmap): the map read
 * once here for its georeference.  0, or -1 with err (the loader's). */
int heightmap_fit_file(struct params *p, char *err, size_t errlen);
void heightmap_free(struct heightmap *hm);
/* A grayscale PNG (8 or 16 bits) as samples 0..65535, 2x2 to
 * HEIGHTMAP_MAX_SIDE on a side (refused from the header, before decoding);
 * what names the file in messages ("heightmap", "control map").  The
 * heightmap's PNG path, and the control map's.  0, or -1 with err. */
int heightmap_read_png(const char *path, const char *what, struct heightmap *hm, char *err, size_t errlen);

/* ---- the edit state (edits.c) ---------------------------------------------- */

/* A file the state was loaded from: reloaded when any of this changes. */
struct edits_file {
	char path[PARAM_STR_MAX];
	long long size, mtime_ns;
};

struct edits_gl; /* curves_gl.c */
struct edits;

/* The terrain's surface height under (x, z) for parameters p, before any
 * edit (the field or the heightmap alone); false when there is none. */
typedef bool (*edits_ground_fn)(void *ctx, const struct params *p, const struct edits *ed, float x, float z,
				float *y);

struct edits {
	/* read freely; changed only through the functions below */
	struct curve_set curves;   /* the current curves (input form) */
	struct curve_quads quads;  /* after the curve pipeline */
	struct curve_hash hash;    /* over quads */
	bool curves_from_file;
	struct heightmap hm;       /* w == 0: none; with areas, edited (areas.c) */
	struct curve_set areas;    /* the curves file's polygons' rings (curves.h enum curve_area) */
	float (*lakes)[5];         /* per water area: x0, z0, x1, z1 of its rim, its level */
	int nlakes;
	struct heightmap control;  /* the control map, samples 0..65535; w == 0: none */
	unsigned curves_gen, hm_gen; /* bumped on every change (GPU re-upload) */
	unsigned control_gen;
	/* private: the files loaded, the hash size, the region changed since
	 * the last edits_take_changes(), the GL side (NULL until first bound) */
	struct edits_file curves_file, hm_file, control_file;
	int hash_dim;
	unsigned curves_hm_gen; /* the heightmap the file's curves were put on */
	bool changed;
	float changed_box[4];
	struct edits_gl *gl;
	edits_ground_fn ground; /* edits_set_ground: 2D curves follow it */
	void *ground_ctx;
	float *hm_pristine;     /* the heightmap's w x h samples before the areas (NULL: none applied;
				 * dropped with the map it was taken of) */
};

/* Areas on the heightmap (areas.c): the samples under ed->areas flattened
 * (to the rim's mean height) or flooded (the rim's lowest less 2 m), blended
 * over road_falloff (at least 1.5 samples) beyond the rim; the water areas
 * listed in ed->lakes.  Restores the samples first; nothing without a
 * heightmap field.  0, or -1 with err (out of memory). */
int areas_apply(struct edits *ed, const struct params *p, char *err, size_t errlen);
/* The heightmap's own samples back (the areas undone). */
void areas_restore(struct edits *ed);

/* An empty edit state (no curves, no heightmap); NULL when out of memory. */
struct edits *edits_create(void);
/* Frees the CPU data and deletes the GL objects (their context must be
 * current if any were made).  NULL is fine. */
void edits_destroy(struct edits *ed);
/* Brings the state in line with p: loads the curves file (p->curves) and
 * the heightmap (p->heightmap) when their names, sizes or modification
 * times changed, rebuilds the hash when p->curve_hash_dim changed; an empty
 * name drops what was loaded from a file (curves set through the API stay).
 * field=heightmap needs a heightmap.  0, or -1 with one clear message
 * (file:line, feature). */
int edits_load(struct edits *ed, const struct params *p, char *err, size_t errlen);
/* Replaces the curves (an editor, the streaming world): runs the curve
 * pipeline and rebuilds the hash.  0 or -1 with err. */
int edits_set_curves(struct edits *ed, const struct curve_set *s, int hash_dim, char *err, size_t errlen);
/* The world-space XZ region (xmin, zmin, xmax, zmax) whose terrain changed
 * since the last call (union of curves_affected_bounds of every curve
 * change; a heightmap change reports the whole plane as +-FLT_MAX).
 * Returns false when nothing changed; clears the record. */
bool edits_take_changes(struct edits *ed, float aabb[4]);
/* Drops the curves and the heightmap (the GL objects stay, re-uploaded on
 * the next bind). */
void edits_clear(struct edits *ed);
/* The ground that 2D curves follow (the terrain provider sets it; NULL
 * drops it: 2D curves are then refused). */
void edits_set_ground(struct edits *ed, edits_ground_fn fn, void *ctx);
/* The edit state holds a curve of kind tunnel (the carve's 3D part). */
bool edits_has_tunnels(const struct edits *ed);

/* ---- GL (curves_gl.c) ------------------------------------------------------- */

/* edits_load(p), uploads what changed, binds the curve SSBOs
 * (BIND_CURVES) and the heightmap (TEX_HEIGHTMAP) and
 * sets the curve/heightmap uniforms of prog (which includes
 * shaders/carve.glsl or curves.glsl).  0, or -1 with err (left empty when
 * a GL error was logged). */
int edits_gl_bind(struct edits *ed, GLuint prog, const struct params *p, char *err, size_t errlen);
/* Deletes the GL objects (the context must be current); the next bind
 * uploads again. */
void edits_gl_release(struct edits *ed);

/* The curves' 2D displacement map (shaders/curve_bake.comp): res[0] x
 * res[1] texels over [origin, origin + size) in XZ, x fastest; each texel
 * Θ_closest · (h - H) at its centre, H the heightmap (bilinear) or 0.
 * By default only the 8x8 tiles that overlap a quadratic's padded box run
 * (the map is zeroed first); dense: every texel; iterative: the baseline
 * (32 line segments per curve, every curve, no hash).  The map stays in an
 * SSBO (BIND_AUX_OUT, explicit capacity); out != NULL gets a copy.  0 or -1
 * with err. */
struct bake_opts {
	int res[2];
	float origin[2], size[2];
	bool iterative; /* the baseline (implies dense) */
	bool dense;     /* every texel (the thesis's dispatch) instead of the
			   8x8 tiles over the padded boxes */
};
int curves_bake(struct edits *ed, const struct params *p, const struct bake_opts *o, float *out, char *err,
		size_t errlen);

/* The road map (curve_bake.comp with BAKE_MATERIAL, render.frag): an
 * RGBA16F texture over the curves' hash rectangle, per texel the closest
 * curve with a surface: R its paint (1 on the flat part, w/2), G the
 * surface (abi.h ROAD_SURFACE_*), B its height less y0; the shading paints
 * a fragment within tol of that height.  Made again when the curves change
 * (the caller has brought the state in line with p this frame:
 * edits_load, or a pass's edits_gl_bind); the texture belongs to the edit
 * state.  tex 0 when no curve has a surface.  0, or -1 with err. */
struct road_map {
	GLuint tex;
	float origin[2], size[2];
	float y0, tol;
};
int edits_road_map(struct edits *ed, const struct params *p, struct road_map *out, char *err, size_t errlen);

/* Test hook: runs shaders/curve_test.comp (mode 0: closest point on given
 * quadratics, 1: curve_eval + carve_density at points, 2: heightmap
 * height) on n inputs; see the shader.  in has 16 floats per item in mode
 * 0, else 4; out 4 per item. */
int curves_gpu_test(struct edits *ed, const struct params *p, int mode, const float *in, int n, float *out, char *err,
		    size_t errlen);

/* ---- CPU mirror of curves.glsl / heightmap.glsl / carve.glsl (carve_ref.c) -- */

float carve_ref_closest_t(const float p0[2], const float p1[2], const float p2[2], const float pos[2]);
/* (signed distance, t, height, inclination) of a quadratic given as 3
 * control points (x, y, z, I). */
void carve_ref_closest(const float c[3][4], const float pos[2], float out[4]);
/* (height, Θ closest, |d| closest, Σ Θ) at (x, z); iterative: the
 * baseline over every curve with 32 segments. */
void carve_ref_eval(const struct edits *e, const struct params *p, float x, float z, bool iterative, float out[4]);
float carve_ref_density(const struct edits *e, const struct params *p, float x, float y, float z, float d);
float carve_ref_theta(float d, float hw, float lam);
/* Heightmap height, bilinear (the fractal interpolation's detail on top:
 * heightmap_ref_height, app/terrain/density_ref.h). */
float heightmap_ref_base(const struct edits *e, const struct params *p, float x, float z);
/* CPU displacement map, as curves_bake(). */
void carve_ref_bake(const struct edits *e, const struct params *p, const struct bake_opts *o, float *out);

#endif
