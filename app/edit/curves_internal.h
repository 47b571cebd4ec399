/* isoterra — what the curve file readers (geojson.c, gpx.c, csv_curves.c) share:
 * kinds and per-path parameters by name, with the same range checks in
 * both formats.  Defined in curve_params.c; not part of the curves API. */
#ifndef ISOTERRA_CURVES_INTERNAL_H
#define ISOTERRA_CURVES_INTERNAL_H

#include "curves.h"

/* The per-path parameters in file order: "width", "falloff", "inclination",
 * "smoothing". */
#define CURVE_NPARAMS 4
extern const char *const curve_param_names[CURVE_NPARAMS];

/* enum curve_kind of "road", "river" or "railway"; -1 for anything else. */
int curve_kind_parse(const char *s);
/* Range check of parameter `name`; NULL when fine, else the reason. */
const char *curve_param_check(const char *name, double v);
/* The field of p that parameter i (curve_param_names order) sets. */
float *curve_param_slot(struct curve_path *p, int i);
/* Sets parameter i of p to v, noting a width or falloff as the file's own
 * (width_set, falloff_set: curves_road_widths leaves them). */
void curve_param_set(struct curve_path *p, int i, float v);
/* An OSM highway class's width in units of road_width (a lane is 1/2:
 * the default road has two), or -1 for a class not in the table. */
float curve_highway_width(const char *cls);
/* enum curve_surface of an OSM surface=* value (or one of
 * curve_surface_names), -1 when unknown; of an OSM highway class (tracks
 * gravel, paths dirt, the rest asphalt). */
int curve_surface_of_tag(const char *v);
int curve_surface_of_highway(const char *cls);
/* 3D input whose every height is 0 (n positions; axis names it): an
 * export's placeholder, not a road at altitude 0.  Every path follows the
 * ground instead, said in a note.  0, or -1 when out of memory. */
int curves_flat_zero(struct curve_set *s, long n, const char *axis);
/* Lanes of a road: 1 to CURVE_LANES_MAX. */
#define CURVE_LANES_MAX 16

#endif
