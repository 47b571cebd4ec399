/* isoterra — a georeferenced heightmap placed in the world (edits.h
 * heightmap_fit): true scale, world units = metres x curves_geo_scale,
 * and by default the volume, the camera and the water fitted to its
 * extent and relief. */
#include "edits.h"
#include "core.h"

#include <math.h>
#include <stdio.h>

/* p's value of name is still its default: a fitted parameter left open */
static bool open_param(const struct params *p, const char *name)
{
	const struct param_info *pi = params_find(name);
	return pi && params_get_number(p, pi) == (double)(float)pi->def;
}

static void set_open(struct params *p, const char *name, double v)
{
	const struct param_info *pi = params_find(name);
	if (pi && open_param(p, name))
		params_set_number(p, pi, v < pi->lo ? pi->lo : v > pi->hi ? pi->hi : v);
}

void heightmap_fit(const struct heightmap *hm, struct params *p)
{
	const struct heightmap_geo *g = &hm->geo;
	if (!g->on)
		return;
	double k = p->curves_geo_scale, kz = k * p->vertical_exaggeration;
	p->heightmap_scale = (float)(g->cell * k);
	p->heightmap_base = (float)(g->zmin * kz);
	p->heightmap_height = (float)((g->zmax - g->zmin) * kz);
	if (!p->fit)
		return;
	/* the volume: the map's square (the shorter side; the longer one
	 * cropped: nothing is made up beyond the samples), its height the
	 * relief and a twentieth of it above and below, at least the
	 * smallest vol_height */
	double ex = g->cell * (hm->w - 1) * k, ez = g->cell * (hm->h - 1) * k, size = fmin(ex, ez);
	double lo = g->zmin * kz, hi = g->zmax * kz, pad = 0.05 * (hi - lo) + 0.005 * size;
	double tall = (hi - lo) + 2.0 * pad;
	double frac = tall / size < 0.05 ? 0.05 : tall / size > 1.0 ? 1.0 : tall / size;
	set_open(p, "vol_size", size);
	set_open(p, "vol_x", 0.0);
	set_open(p, "vol_z", 0.0);
	set_open(p, "vol_height", frac);
	set_open(p, "vol_y", 0.5 * (lo + hi));
	/* the shading's lengths, made for the default 96-unit volume, scaled
	 * to this one (textures, fog, waves); snow on the top quarter, but
	 * not below 1500 m (no snow-capped hills by the sea) */
	double r = 96.0 / size;
	const struct param_info *pi;
	if ((pi = params_find("tex_scale")) && open_param(p, "tex_scale"))
		set_open(p, "tex_scale", pi->def * r);
	if ((pi = params_find("fog_height")) && open_param(p, "fog_height"))
		set_open(p, "fog_height", pi->def * r);
	if ((pi = params_find("water_freq")) && open_param(p, "water_freq"))
		set_open(p, "water_freq", pi->def * r);
	set_open(p, "snow_line", fmax(lo + 0.75 * (hi - lo), 1500.0 * kz));
	/* the streaming world over the map: a finest cell a quarter of a
	 * sample (block_size 8 samples), the whole map within view; the
	 * autopilot starts over the map's edge and crosses it through its
	 * centre on its first heading (FLY_START_HEADING), a
	 * twentieth of the map above the ground, in a minute; its clearance
	 * scaled as the block (the defaults' 1.5 of air for a block of 4) */
	double bs = 8.0 * g->cell * k;
	set_open(p, "block_size", bs);
	set_open(p, "view_distance", 1.5 * fmax(ex, ez));
	set_open(p, "fly_height", size / 20.0);
	set_open(p, "fly_speed", size / 60.0);
	set_open(p, "fly_clearance", 1.5 * bs / 4.0);
	set_open(p, "fly_x", -0.42 * size * cos(FLY_START_HEADING));
	set_open(p, "fly_z", -0.42 * size * sin(FLY_START_HEADING));
	/* the sea where the map reaches below sea level, else no water */
	if (open_param(p, "water_level")) {
		if (g->zmin < 0.0 && g->zmax > 0.0)
			p->water_level = 0.0f;
		else
			p->water = false;
	}
}

int heightmap_fit_file(struct params *p, char *err, size_t errlen)
{
	if (p->field != FIELD_HEIGHTMAP || !p->heightmap[0])
		return 0;
	struct heightmap hm;
	if (heightmap_load(p->heightmap, &hm, err, errlen) < 0)
		return -1;
	heightmap_fit(&hm, p);
	heightmap_free(&hm);
	return 0;
}
