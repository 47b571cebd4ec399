/* isoterra — terrain editing with 3D Bézier curves (roads, rivers,
 * railways), after Nascimento (2020), see docs/CURVES.md:
 *
 *   polyline (file)  ->  chain of 3D cubic Béziers (handles with smoothing Ω)
 *                    ->  each cubic split at its XZ inflection (or t = 0.5)
 *                    ->  two 3D quadratic Béziers (handle intersection, Y averaged)
 *                    ->  lateral inclination from the XZ curvature
 *                    ->  uniform 2D spatial hash (pivot + index tables)
 *                    ->  SSBOs for the density function (shaders/curves.glsl)
 *
 * World axes: Y is up, curves are compared with samples in XZ. */
#ifndef ISOTERRA_CURVES_H
#define ISOTERRA_CURVES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "gpu.h"

/* Road, river and railway are surfaces: the ground is pulled to the curve's
 * height across its profile.  A tunnel is a tube through the rock with its
 * floor on the curve (the rock above stays), on an embankment in the open.
 * A bridge is a deck at the curve's height, added to the terrain: the
 * ground under it stays. */
enum curve_kind { CURVE_ROAD, CURVE_RIVER, CURVE_RAILWAY, CURVE_TUNNEL, CURVE_BRIDGE, CURVE_KIND_COUNT };
/* shaders/curves.glsl compares the kind with abi.h's CURVE_KIND_TUNNEL / _BRIDGE */
_Static_assert(CURVE_TUNNEL == CURVE_KIND_TUNNEL, "abi.h CURVE_KIND_TUNNEL is enum curve_kind's CURVE_TUNNEL");
_Static_assert(CURVE_BRIDGE == CURVE_KIND_BRIDGE, "abi.h CURVE_KIND_BRIDGE is enum curve_kind's CURVE_BRIDGE");
extern const char *const curve_kind_names[CURVE_KIND_COUNT]; /* "road", "river", "railway", "tunnel", "bridge" */

/* What a path's surface looks like in the shading (abi.h ROAD_SURFACE_*,
 * render.frag): 0 leaves the ground's own colours (rivers). */
enum curve_surface { SURFACE_NONE, SURFACE_ASPHALT, SURFACE_GRAVEL, SURFACE_DIRT, SURFACE_BALLAST, SURFACE_COUNT };
_Static_assert(SURFACE_ASPHALT == ROAD_SURFACE_ASPHALT && SURFACE_BALLAST == ROAD_SURFACE_BALLAST,
	       "abi.h ROAD_SURFACE_* are enum curve_surface");
extern const char *const curve_surface_names[SURFACE_COUNT]; /* "none", "asphalt", "gravel", "dirt", "ballast" */

/* An area (a GeoJSON Polygon's rings): flattened to its mean rim height
 * (plazas, fields, landuse), or water filled to its lowest rim height
 * (natural=water, water=*, waterway=riverbank, landuse=reservoir|basin). */
enum curve_area { AREA_NONE, AREA_FLAT, AREA_WATER };

/* What a file says of its coordinates (GeoJSON's "crs" member). */
enum curve_crs { CURVE_CRS_UNSAID, CURVE_CRS_WGS84, CURVE_CRS_OTHER };

/* One input polyline and its carving parameters. */
struct curve_path {
	int kind;              /* enum curve_kind */
	int surface;           /* enum curve_surface: the file's surface tag, else
				* its highway class's, else the kind's */
	int area;              /* enum curve_area: a ring of a polygon (GeoJSON),
				* not a curve: the edit state takes it out of the
				* curves (edits.c) and flattens or floods the
				* heightmap under it (areas.c) */
	int ring;              /* an area's ring: 0 the outer one, k > 0 its holes
				* (which follow it in the set) */
	float width;           /* w: full width of the flat part */
	float falloff;         /* λ: blend distance beyond w/2 */
	float inclination;     /* gain of the lateral inclination: tan α = gain · XZ curvature */
	float smoothing;       /* Ω in [0,1]: handle length, 0 = the polyline itself */
	int npts;
	float *pts;            /* npts * 3: world x, y (up), z */
	bool width_set;        /* width given by the file (a width or lanes property, */
	bool falloff_set;      /* a highway class, a CSV cell); else curves_road_widths */
	float width_rel;       /* lanes or highway class: width in units of road_width, 0 when none */
	bool follow_ground;    /* 2D input: y is taken from the terrain's surface
				* (curves_follow_ground; until then 0) */
	int crs;               /* enum curve_crs: what its file said (GeoJSON) */
	bool geo_rel;          /* GeoJSON that looks like lon/lat (the auto rule,
				* curves_geo_project): x and -z are degrees from
				* geo_origin (lon, lat), kept exact in double there */
	double geo_origin[2];
	char label[192];       /* where it came from, for messages ("roads.geojson: feature 2") */
};

/* The longest note (curve_set_note) and the most a set keeps. */
#define CURVE_NOTE_MAX 480
#define CURVE_NOTES_MAX 16

struct curve_set {
	struct curve_path *paths;
	int npaths;
	/* What a reader (or curves_geo_project) noticed and did instead of
	 * refusing the file: features skipped, lon/lat assumed, 3D taken as
	 * 2D.  One line each, for the loader to log as warnings (edits.c);
	 * freed with the set, not copied by curve_set_copy. */
	char (*notes)[CURVE_NOTE_MAX];
	int nnotes;
	/* lon/lat input without a crs member (the reader's rule, geo_rel):
	 * its span in degrees (lon, lat), for curves_geo_project's note */
	double geo_span[2];
	char source[96];       /* the file's name, for notes */
};

/* Defaults of the per-path parameters by kind (w, λ, inclination gain, Ω). */
void curve_path_defaults(struct curve_path *p, int kind);
void curve_set_free(struct curve_set *s);
/* Appends a note (one line, printf format, cut at CURVE_NOTE_MAX; at most
 * CURVE_NOTES_MAX kept).  0, or -1 when out of memory. */
int curve_set_note(struct curve_set *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Deep copy; 0 or -1 (out of memory). */
int curve_set_copy(struct curve_set *dst, const struct curve_set *src);
/* Appends a path (deep copy of pts); 0 or -1. */
int curve_set_add(struct curve_set *s, const struct curve_path *p);
/* Influence distance of a path: w/2 + λ. */
float curve_path_reach(const struct curve_path *p);
/* Same kind, parameters and points (bitwise floats). */
bool curve_path_equal(const struct curve_path *a, const struct curve_path *b);

/* ---- curve pipeline ------------------------------------------------------ */

struct cubic3 {
	float p[4][3];
};
struct quad3 {
	float p[3][3];
};

/* Drops repeated points (closer than 1e-6 of the path's extent).  Returns
 * the number of points left. */
int curve_path_dedup(struct curve_path *p);
/* Polyline -> npts-1 cubics (thesis §5.1): at an inner anchor the tangent is
 * the normalised sum of the unit vectors of the two segments, handle length
 * 0.5 · min(adjacent segment lengths) · Ω on both sides (C1); the end
 * handles are the neighbouring handles projected onto the end segments.
 * out must hold npts-1 cubics. */
void curve_path_cubics(const struct curve_path *p, struct cubic3 *out);
/* XZ inflection of a planar cubic in (0,1) (Eq. 5.11: 3(b×a)t² + 3(c×a)t +
 * (c×b) = 0), the root nearest 0.5, or -1 when none. */
float cubic_xz_inflection(const struct cubic3 *c);
/* de Casteljau split at t. */
void cubic_split(const struct cubic3 *c, float t, struct cubic3 *left, struct cubic3 *right);
/* Sub-cubic A,B,C,D -> quadratic A,E,D (thesis §5.2): E.xz = intersection of
 * the lines A->B and D->C; E.y = (B.y + C.y)/2.  Degenerate cases: a straight
 * sub-curve (all points within 1e-5 of the chord) gives the chord's midpoint;
 * zero-length handles take the next control point as direction; parallel
 * lines, an intersection behind an anchor or farther than 4 chords away fall
 * back to the least-squares degree reduction (3(B+C) - (A+D))/4.
 * Returns 0 for the intersection, 1 for straight, 2 for the fallback. */
int cubic_to_quad(const struct cubic3 *c, struct quad3 *q);

/* The GPU layout (thesis Fig. 6.1): control points stored sequentially as
 * vec4 (x, y, z, inclination I = tan α); consecutive quadratics of one path
 * share their anchors, so quadratic k is ctrl[first[k] .. first[k]+2].
 * prm[first[k]] = (w/2, λ, kind, surface) for that quadratic. */
struct curve_quads {
	float (*ctrl)[4];
	float (*prm)[4];
	int nctrl;
	int *first;    /* per quadratic: index of its first control point */
	int *path;     /* per quadratic: its path */
	float (*box)[4]; /* per quadratic: exact XZ bounds (xmin, zmin, xmax, zmax), unpadded */
	int nquads;
};
/* The most bytes one curve table (control points, hash index) may take:
 * the shader storage block size every GL ES 3.1 driver allows.  Tables are
 * sized from the input and refused before they are built. */
#define CURVE_TABLE_MAX_BYTES (1L << 27)
/* The most points a curve file may hold: their control points (4 per
 * segment, 16 bytes each) fit that table.  The readers count them before
 * building anything. */
#define CURVE_MAX_POINTS ((CURVE_TABLE_MAX_BYTES / 16 - 1) / 4)
/* Runs the whole curve pipeline.  0, or -1 with err (out of memory, a path
 * with fewer than two distinct points, or more segments than the tables
 * may hold: checked before anything is built). */
int curves_build(const struct curve_set *s, struct curve_quads *q, char *err, size_t errlen);
void curve_quads_free(struct curve_quads *q);
/* Quadratic k's control points (x, y, z, I). */
void curve_quads_get(const struct curve_quads *q, int k, float out[3][4]);
/* Signed XZ curvature (C' x C'') / |C'|^3 of a quadratic at t. */
float quad_xz_curvature(const float p0[3], const float p1[3], const float p2[3], float t);

/* ---- spatial hash (thesis ch. 6) ---------------------------------------- */

/* Uniform dim x dim grid over the minimal rectangle around the padded boxes
 * of all quadratics; each quadratic is listed in every cell its exact XZ box,
 * padded by w/2 + λ (+ a small epsilon against rounding), overlaps.
 *   pivot[cell] = (start, count) into index[] (cell = cx + cy * dim)
 *   index[start .. start+count-1] = first control point of each quadratic
 * index[] is followed by a list of every quadratic (the no-hash baseline):
 * index[all_offset + k] = first[k]. */
struct curve_hash {
	int dim;
	float origin[2];   /* x, z of the grid's corner */
	float size[2];     /* extent in x, z */
	float cell[2];     /* size / dim */
	int32_t *pivot;    /* 2 * dim * dim */
	int32_t *index;
	int nindex;        /* entries in cells */
	int all_offset;    /* == nindex */
	int nall;          /* == number of quadratics */
	int max_per_cell;
};
/* 0, or -1 with err: out of memory, or an index larger than
 * CURVE_TABLE_MAX_BYTES (its size is counted from the boxes first, before
 * any cell is filled). */
int curve_hash_build(const struct curve_quads *q, int dim, struct curve_hash *h, char *err, size_t errlen);
/* The most curve pieces one hash cell should list.  A pass that carves
 * walks a cell's list per sample (twice with tunnels or bridges), and the
 * density pass takes 32 samples an invocation: a software rasterizer
 * (Mesa's gallivm: llvmpipe, lavapipe) ends an invocation's loops after
 * 65535 iterations in all, and the samples after that are lost.  dim 0
 * (auto) makes the grid finer until no cell lists more (up to 1024 cells a
 * side); the edit state warns when a cell still does. */
#define CURVE_CELL_MAX 192
void curve_hash_free(struct curve_hash *h);
/* Cell of (x, z), or -1 outside the grid (same arithmetic as the shader). */
int curve_hash_cell(const struct curve_hash *h, float x, float z);
/* Padded XZ box of quadratic k (xmin, zmin, xmax, zmax), as inserted. */
void curve_hash_padded_box(const struct curve_quads *q, int k, float box[4]);

/* ---- edits -------------------------------------------------------------- */

/* World-space XZ region (xmin, zmin, xmax, zmax) changed between two curve
 * sets: the union of the padded boxes (w/2 + λ around the polyline's
 * convex hull of control points) of every path that was removed, added or
 * modified.  Paths are matched by position in the set.  Returns false
 * (and an empty box) when nothing changed. */
bool curves_affected_bounds(const struct curve_set *old_set, const struct curve_set *new_set, float out_aabb[4]);
/* Padded XZ box of a whole path (its control polygon after the cubic
 * construction plus w/2 + λ). */
void curve_path_padded_box(const struct curve_path *p, float box[4]);

/* ---- input files (curves_io.c) -------------------------------------------- */

/* GeoJSON (FeatureCollection / Feature / LineString / MultiLineString with
 * positions [x east, y north] (2D: the curve follows the ground) or [x east,
 * y north, z up] -> world (x, z_up, -y), in degrees until
 * curves_geo_project; other geometries skipped with a note), GPX
 * (curves_parse_gpx) or CSV (header line,
 * columns path,x,y,z[,kind,width,falloff,inclination,smoothing,surface], y up).
 * The format is chosen by the extension (.geojson/.json, .gpx, .csv).
 * Errors name file:line and the feature.  0 or -1 with err; s->notes
 * holds what was skipped or assumed instead of refused. */
int curves_load(const char *path, struct curve_set *s, char *err, size_t errlen);
int curves_parse_geojson(const char *text, size_t len, const char *fname, struct curve_set *s, char *err,
			 size_t errlen);
int curves_parse_csv(const char *text, size_t len, const char *fname, struct curve_set *s, char *err, size_t errlen);
/* GPX 1.0 / 1.1 (.gpx): every track segment (trk/trkseg/trkpt) and route
 * (rte/rtept) a path of kind road; lat/lon WGS84 (crs CURVE_CRS_WGS84,
 * degrees from the centroid, projected by curves_geo_project like GeoJSON
 * lon/lat), <ele> metres as the height, or the path follows the ground
 * when its points lack <ele>.  Errors (malformed XML, a point without lat
 * or lon, a latitude beyond +-90, a DTD) name file:line.  0 or -1 with
 * err. */
int curves_parse_gpx(const char *text, size_t len, const char *fname, struct curve_set *s, char *err, size_t errlen);

/* The widths a file left open (curve_params.c): a path with width_rel
 * (lanes, an OSM highway class) gets width_rel * road_width, a road
 * without width or width_rel road_width; a road without a falloff
 * road_falloff.  Other kinds keep their defaults. */
void curves_road_widths(struct curve_set *s, float road_width, float road_falloff);

/* ---- geographic input (curves_geo.c) ------------------------------------------ */

/* curves_crs: how a file's coordinates are read. */
enum curves_crs_mode { CURVES_CRS_AUTO, CURVES_CRS_LONLAT, CURVES_CRS_LOCAL, CURVES_CRS_NAMED };
/* The parameter's text (auto, lonlat, local, EPSG:CODE) as a mode.  0, or
 * -1 with err. */
int curves_crs_parse(const char *text, int *mode, char *err, size_t errlen);
/* Transforms n (x east, y north) pairs of the CRS crs to WGS84 lon/lat in
 * place; name gets the CRS's name.  0, or -1 with err. */
typedef int (*curves_to_lonlat_fn)(const char *crs, double *xy, size_t n, char *name, size_t namelen, char *err,
				   size_t errlen);
/* Positions in the projected CRS crs (x east, y north: world x and -z,
 * relative degrees when the reader took them for lon/lat) made WGS84
 * lon/lat (geo_rel degrees from the first position), for
 * curves_geo_project with CURVES_CRS_LONLAT; the transform is to_lonlat's
 * (the GDAL module's: the core does not link GDAL).  0, or -1 with err. */
int curves_from_crs(struct curve_set *s, const char *crs, curves_to_lonlat_fn to_lonlat, char *name, size_t namelen,
		    char *err, size_t errlen);
/* The frame lon/lat goes into: a georeferenced heightmap's. */
struct curves_geo_frame {
	double lon0, lat0; /* the origin (the map's centre) */
	float yscale;      /* world units per metre of height (its
			      vertical_exaggeration included) */
};
/* Lon/lat or world units: mode CURVES_CRS_LONLAT / _LOCAL forces it;
 * CURVES_CRS_AUTO takes the file's "crs" member (WGS84 / CRS84 / EPSG:4326,
 * or a GPX file: lon/lat; any other: world units) and, without one,
 * lon/lat when every position lies in [-180, 180] x [-90, 90] (RFC 7946;
 * the reader applies this rule, geo_rel; a note when the data spans over
 * a degree, which world units could too).  Lon/lat positions are put in
 * the local east-north-up frame of WGS84 (geo_enu.h) at frame's origin,
 * or without a frame at their centroid: east and north of the ellipsoid's
 * point, in metres, then scaled by `scale` world units per metre (the up
 * coordinate by frame->yscale, else by scale too).  *lonlat tells which
 * was chosen, *why the rule (for the log), origin the frame's origin.
 * 0, or -1 with err. */
int curves_geo_project(struct curve_set *s, int mode, float scale, const struct curves_geo_frame *frame, bool *lonlat,
		       const char **why, double origin[2], char *err, size_t errlen);
/* The fraction of the curves' XZ length inside box (xmin, zmin, xmax,
 * zmax), and their XZ extent in ext (same order); 1 for no length. */
double curves_inside_fraction(const struct curve_set *s, const float box[4], float ext[4]);
/* The terrain's surface height under (x, z) for 2D curves; false when
 * there is none. */
typedef bool (*curve_ground_fn)(void *ctx, float x, float z, float *y);
/* 2D paths (follow_ground): points inserted so no segment is longer than
 * `step` in XZ, each point's y set to ground(x, z).  0, or -1 with err
 * naming the path and the position without ground. */
int curves_follow_ground(struct curve_set *s, float step, curve_ground_fn ground, void *ctx, char *err, size_t errlen);

#endif
