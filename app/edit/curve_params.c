/* isoterra — what the curve file readers share: kinds and per-path
 * parameters by name, with the same range checks in every format; the
 * widths a file leaves open (OSM highway classes, lanes, the road_width /
 * road_falloff defaults). */
#include "curves_internal.h"

#include <math.h>
#include <string.h>

const char *const curve_param_names[CURVE_NPARAMS] = { "width", "falloff", "inclination", "smoothing" };

int curve_kind_parse(const char *s)
{
	for (int k = 0; k < CURVE_KIND_COUNT; k++)
		if (!strcmp(s, curve_kind_names[k]))
			return k;
	return -1;
}

const char *curve_param_check(const char *name, double v)
{
	if (!isfinite(v))
		return "is not a finite number";
	if (!strcmp(name, "width") && !(v > 0.0 && v <= 1e6))
		return "must be in (0, 1e6]";
	if (!strcmp(name, "falloff") && !(v >= 0.0 && v <= 1e6))
		return "must be in [0, 1e6]";
	if (!strcmp(name, "smoothing") && !(v >= 0.0 && v <= 1.0))
		return "must be in [0, 1]";
	if (!strcmp(name, "inclination") && !(fabs(v) <= 1e6))
		return "must be in [-1e6, 1e6]";
	return NULL;
}

float *curve_param_slot(struct curve_path *p, int i)
{
	return i == 0 ? &p->width : i == 1 ? &p->falloff : i == 2 ? &p->inclination : &p->smoothing;
}


void curve_param_set(struct curve_path *p, int i, float v)
{
	*curve_param_slot(p, i) = v;
	if (i == 0)
		p->width_set = true;
	else if (i == 1)
		p->falloff_set = true;
}

/* OSM highway=* classes (wiki "Key:highway"): typical carriageway widths
 * in lanes of half a default road: a motorway's six, a residential
 * street's two, a footway's half. */
static const struct {
	const char *cls;
	float rel;
} highway_widths[] = {
	{ "motorway", 3.0f },      { "trunk", 2.5f },        { "primary", 2.0f },       { "secondary", 1.5f },
	{ "tertiary", 1.25f },     { "unclassified", 1.0f }, { "residential", 1.0f },   { "road", 1.0f },
	{ "motorway_link", 1.0f }, { "trunk_link", 1.0f },   { "primary_link", 1.0f },  { "secondary_link", 1.0f },
	{ "tertiary_link", 0.75f }, { "living_street", 0.75f }, { "pedestrian", 0.75f }, { "service", 0.75f },
	{ "busway", 0.75f },       { "track", 0.5f },        { "bridleway", 0.35f },    { "cycleway", 0.3f },
	{ "path", 0.25f },         { "footway", 0.25f },     { "steps", 0.25f },
};

float curve_highway_width(const char *cls)
{
	for (size_t i = 0; i < sizeof(highway_widths) / sizeof(highway_widths[0]); i++)
		if (!strcmp(cls, highway_widths[i].cls))
			return highway_widths[i].rel;
	return -1.0f;
}

/* OSM surface=* values (wiki "Key:surface") by look. */
static const struct {
	const char *tag;
	int surface;
} osm_surfaces[] = {
	{ "paved", SURFACE_ASPHALT },        { "concrete", SURFACE_ASPHALT },      { "concrete:plates", SURFACE_ASPHALT },
	{ "concrete:lanes", SURFACE_ASPHALT }, { "paving_stones", SURFACE_ASPHALT }, { "sett", SURFACE_ASPHALT },
	{ "cobblestone", SURFACE_ASPHALT },  { "unhewn_cobblestone", SURFACE_ASPHALT }, { "chipseal", SURFACE_ASPHALT },
	{ "metal", SURFACE_ASPHALT },        { "wood", SURFACE_ASPHALT },          { "bricks", SURFACE_ASPHALT },
	{ "fine_gravel", SURFACE_GRAVEL },   { "compacted", SURFACE_GRAVEL },      { "unpaved", SURFACE_GRAVEL },
	{ "pebblestone", SURFACE_GRAVEL },   { "rock", SURFACE_GRAVEL },           { "shells", SURFACE_GRAVEL },
	{ "ground", SURFACE_DIRT },          { "earth", SURFACE_DIRT },            { "grass", SURFACE_DIRT },
	{ "sand", SURFACE_DIRT },            { "mud", SURFACE_DIRT },              { "soil", SURFACE_DIRT },
	{ "woodchips", SURFACE_DIRT },       { "grass_paver", SURFACE_DIRT },
};

int curve_surface_of_tag(const char *v)
{
	for (size_t i = 0; i < sizeof(osm_surfaces) / sizeof(osm_surfaces[0]); i++)
		if (!strcmp(v, osm_surfaces[i].tag))
			return osm_surfaces[i].surface;
	/* our own names, which OSM shares for asphalt, gravel and dirt */
	for (int k = 0; k < SURFACE_COUNT; k++)
		if (!strcmp(v, curve_surface_names[k]))
			return k;
	return -1;
}

int curve_surface_of_highway(const char *cls)
{
	if (!strcmp(cls, "track"))
		return SURFACE_GRAVEL;
	if (!strcmp(cls, "path") || !strcmp(cls, "footway") || !strcmp(cls, "bridleway") || !strcmp(cls, "steps"))
		return SURFACE_DIRT;
	return SURFACE_ASPHALT;
}

void curves_road_widths(struct curve_set *s, float road_width, float road_falloff)
{
	for (int i = 0; i < s->npaths; i++) {
		struct curve_path *p = &s->paths[i];
		if (!p->width_set && p->width_rel > 0.0f)
			p->width = p->width_rel * road_width;
		else if (!p->width_set && p->kind == CURVE_ROAD)
			p->width = road_width;
		if (!p->falloff_set && p->kind == CURVE_ROAD)
			p->falloff = road_falloff;
	}
}

int curves_flat_zero(struct curve_set *s, long n, const char *axis)
{
	for (int i = 0; i < s->npaths; i++)
		s->paths[i].follow_ground = true;
	return curve_set_note(s, "%s: the %s of all %ld 3D positions is 0, which would carve at height 0: taken as 2D, "
			      "the curves follow the ground", s->source, axis, n);
}
