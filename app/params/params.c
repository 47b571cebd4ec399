/* isoterra — parameter table, setters, config file and presets. */
#include "params.h"
#include "core.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

const struct param_info param_table[] = {
#define PF(n, d, l, h, f, hp) { #n, PT_FLOAT, offsetof(struct params, n), d, l, h, NULL, NULL, f, hp },
#define PI(n, d, l, h, f, hp) { #n, PT_INT, offsetof(struct params, n), d, l, h, NULL, NULL, f, hp },
#define PB(n, d, f, hp) { #n, PT_BOOL, offsetof(struct params, n), d, 0, 1, NULL, NULL, f, hp },
#define PE(n, d, c, f, hp) { #n, PT_ENUM, offsetof(struct params, n), d, 0, 0, NULL, c, f, hp },
#define PS(n, d, f, hp) { #n, PT_STRING, offsetof(struct params, n), 0, 0, 0, d, NULL, f, hp },
#include "params.def"
#undef PF
#undef PI
#undef PB
#undef PE
#undef PS
};
const size_t param_count = ARRAY_SIZE(param_table);

static void *field_ptr(const struct params *p, const struct param_info *pi)
{
	return (char *)p + pi->offset;
}

static int enum_count(const struct param_info *pi)
{
	int n = 1;
	for (const char *c = pi->choices; *c; c++)
		n += *c == '|';
	return n;
}

int params_enum_index(const struct param_info *pi, const char *choice)
{
	const char *c = pi->choices;
	size_t len = strlen(choice);
	for (int i = 0; c; i++) {
		const char *bar = strchr(c, '|');
		size_t n = bar ? (size_t)(bar - c) : strlen(c);
		if (n == len && strncmp(c, choice, n) == 0)
			return i;
		c = bar ? bar + 1 : NULL;
	}
	return -1;
}

void params_enum_name(const struct param_info *pi, int idx, char *buf, size_t len)
{
	const char *c = pi->choices;
	for (int i = 0; c; i++) {
		const char *bar = strchr(c, '|');
		size_t n = bar ? (size_t)(bar - c) : strlen(c);
		if (i == idx) {
			snprintf(buf, len, "%.*s", (int)n, c);
			return;
		}
		c = bar ? bar + 1 : NULL;
	}
	snprintf(buf, len, "%d", idx);
}

double params_get_number(const struct params *p, const struct param_info *pi)
{
	void *f = field_ptr(p, pi);
	switch (pi->type) {
	case PT_FLOAT: return *(float *)f;
	case PT_INT:
	case PT_ENUM: return *(int *)f;
	case PT_BOOL: return *(bool *)f;
	default: return 0;
	}
}

void params_set_number(struct params *p, const struct param_info *pi, double v)
{
	void *f = field_ptr(p, pi);
	switch (pi->type) {
	case PT_FLOAT:
		if (v < pi->lo) v = pi->lo;
		if (v > pi->hi) v = pi->hi;
		*(float *)f = (float)v;
		break;
	case PT_INT:
		if (v < pi->lo) v = pi->lo;
		if (v > pi->hi) v = pi->hi;
		*(int *)f = (int)lround(v);
		break;
	case PT_ENUM: {
		int n = enum_count(pi), i = (int)lround(v);
		*(int *)f = ((i % n) + n) % n;
		break;
	}
	case PT_BOOL: *(bool *)f = v != 0; break;
	default: break;
	}
}

void params_defaults(struct params *p)
{
	memset(p, 0, sizeof(*p));
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (pi->type == PT_STRING)
			snprintf((char *)field_ptr(p, pi), PARAM_STR_MAX, "%s", pi->def_str);
		else
			params_set_number(p, pi, pi->def);
	}
}

const struct param_info *params_find(const char *name)
{
	char key[64];
	size_t n = strlen(name);
	if (n >= sizeof(key))
		return NULL;
	for (size_t i = 0; i <= n; i++)
		key[i] = name[i] == '-' ? '_' : name[i];
	for (size_t i = 0; i < param_count; i++)
		if (strcmp(param_table[i].name, key) == 0)
			return &param_table[i];
	return NULL;
}

int params_set(struct params *p, const char *name, const char *value, char *err, size_t errlen)
{
	const struct param_info *pi = params_find(name);
	if (!pi) {
		snprintf(err, errlen, "unknown parameter '%s' (see --help)", name);
		return -1;
	}
	void *f = field_ptr(p, pi);
	char *end;
	switch (pi->type) {
	case PT_FLOAT: {
		errno = 0;
		double v = strtod(value, &end);
		/* strtod skips leading white space: refuse it like any other stray character */
		if (end == value || *end || errno || !isfinite(v) || isspace((unsigned char)value[0])) {
			snprintf(err, errlen, "%s: '%s' is not a number", pi->name, value);
			return -1;
		}
		if (v < pi->lo || v > pi->hi) {
			snprintf(err, errlen, "%s: %s is out of range [%g, %g]", pi->name, value, pi->lo, pi->hi);
			return -1;
		}
		*(float *)f = (float)v;
		return 0;
	}
	case PT_INT: {
		errno = 0;
		long v = strtol(value, &end, 10);
		if (end == value || *end || errno || isspace((unsigned char)value[0])) {
			snprintf(err, errlen, "%s: '%s' is not an integer", pi->name, value);
			return -1;
		}
		if (v < pi->lo || v > pi->hi) {
			snprintf(err, errlen, "%s: %s is out of range [%g, %g]", pi->name, value, pi->lo, pi->hi);
			return -1;
		}
		*(int *)f = (int)v;
		return 0;
	}
	case PT_BOOL:
		if (!strcmp(value, "1") || !strcmp(value, "true") || !strcmp(value, "on") || !strcmp(value, "yes")) {
			*(bool *)f = true;
			return 0;
		}
		if (!strcmp(value, "0") || !strcmp(value, "false") || !strcmp(value, "off") || !strcmp(value, "no")) {
			*(bool *)f = false;
			return 0;
		}
		snprintf(err, errlen, "%s: '%s' is not a boolean (true/false)", pi->name, value);
		return -1;
	case PT_ENUM: {
		int idx = params_enum_index(pi, value);
		if (idx < 0) {
			snprintf(err, errlen, "%s: '%s' is not one of %s", pi->name, value, pi->choices);
			return -1;
		}
		*(int *)f = idx;
		return 0;
	}
	case PT_STRING:
		if (strlen(value) >= PARAM_STR_MAX) {
			snprintf(err, errlen, "%s: value longer than %d characters", pi->name, PARAM_STR_MAX - 1);
			return -1;
		}
		snprintf((char *)f, PARAM_STR_MAX, "%s", value);
		return 0;
	}
	snprintf(err, errlen, "%s: bad parameter type", pi->name);
	return -1;
}

void params_format(const struct params *p, const struct param_info *pi, char *buf, size_t len)
{
	const void *f = field_ptr(p, pi);
	switch (pi->type) {
	case PT_FLOAT: snprintf(buf, len, "%g", *(const float *)f); break;
	case PT_INT: snprintf(buf, len, "%d", *(const int *)f); break;
	case PT_BOOL: snprintf(buf, len, "%s", *(const bool *)f ? "true" : "false"); break;
	case PT_ENUM: params_enum_name(pi, *(const int *)f, buf, len); break;
	case PT_STRING: snprintf(buf, len, "%s", (const char *)f); break;
	}
}

void params_print_help(FILE *out, unsigned flag_mask)
{
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (flag_mask && !(pi->flags & flag_mask))
			continue;
		char opt[80], range[96];
		snprintf(opt, sizeof(opt), "--%s", pi->name);
		for (char *c = opt + 2; *c; c++)
			if (*c == '_')
				*c = '-';
		switch (pi->type) {
		case PT_FLOAT: snprintf(range, sizeof(range), "float [%.10g..%.10g], default %.10g", pi->lo, pi->hi, pi->def); break;
		case PT_INT: snprintf(range, sizeof(range), "int [%.10g..%.10g], default %.10g", pi->lo, pi->hi, pi->def); break;
		case PT_BOOL: snprintf(range, sizeof(range), "bool, default %s", pi->def ? "true" : "false"); break;
		case PT_ENUM: {
			char d[32];
			params_enum_name(pi, (int)pi->def, d, sizeof(d));
			snprintf(range, sizeof(range), "%s, default %s", pi->choices, d);
			break;
		}
		case PT_STRING: snprintf(range, sizeof(range), "text, default \"%s\"", pi->def_str); break;
		}
		fprintf(out, "  %-22s %s\n  %-22s   (%s)\n", opt, pi->help, "", range);
	}
}

/* "TERM_<NAME>" of a P_TERM entry. */
static void term_name(const struct param_info *pi, char *buf, size_t len)
{
	size_t j = 0;
	for (const char *c = "TERM_"; *c && j + 1 < len; c++)
		buf[j++] = *c;
	for (const char *q = pi->name; *q && j + 1 < len; q++)
		buf[j++] = (char)toupper((unsigned char)*q);
	buf[j] = 0;
}

int params_glsl_decls(char *buf, size_t len)
{
	size_t used = 0;
	buf[0] = 0;
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (!(pi->flags & P_SHADER))
			continue;
		const char *ty = pi->type == PT_FLOAT ? "float" : "int";
		int n;
		if (pi->flags & P_SPECIALIZE)
			n = snprintf(buf + used, len - used, "#ifndef u_%s\nuniform %s u_%s;\n#endif\n", pi->name, ty,
				     pi->name);
		else
			n = snprintf(buf + used, len - used, "uniform %s u_%s;\n", ty, pi->name);
		if (n < 0 || (size_t)n >= len - used)
			return -1;
		used += (size_t)n;
		if (pi->flags & P_TERM) {
			char t[80];
			term_name(pi, t, sizeof(t));
			n = snprintf(buf + used, len - used, "#ifndef %s\n#define %s 1\n#endif\n", t, t);
			if (n < 0 || (size_t)n >= len - used)
				return -1;
			used += (size_t)n;
		}
		if (pi->type == PT_ENUM) {
			const char *c = pi->choices;
			for (int k = 0; c; k++) {
				const char *bar = strchr(c, '|');
				size_t cn = bar ? (size_t)(bar - c) : strlen(c);
				char up[64];
				size_t j = 0;
				for (const char *q = pi->name; *q && j < sizeof(up) - 1; q++)
					up[j++] = (char)toupper((unsigned char)*q);
				up[j++] = '_';
				for (size_t q = 0; q < cn && j < sizeof(up) - 1; q++)
					up[j++] = (char)toupper((unsigned char)c[q]);
				up[j] = 0;
				n = snprintf(buf + used, len - used, "#define %s %d\n", up, k);
				if (n < 0 || (size_t)n >= len - used)
					return -1;
				used += (size_t)n;
				c = bar ? bar + 1 : NULL;
			}
		}
	}
	return (int)used;
}

int params_glsl_specialization(const struct params *p, char *buf, size_t len)
{
	size_t used = 0;
	buf[0] = 0;
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		int n;
		if ((pi->flags & P_TERM) && pi->type != PT_STRING) {
			char t[80];
			term_name(pi, t, sizeof(t));
			n = snprintf(buf + used, len - used, "#define %s %d\n", t, params_get_number(p, pi) != 0);
		} else if ((pi->flags & P_SPECIALIZE) && pi->type != PT_FLOAT && pi->type != PT_STRING) {
			n = snprintf(buf + used, len - used, "#define u_%s %d\n", pi->name, (int)params_get_number(p, pi));
		} else {
			continue;
		}
		if (n < 0 || (size_t)n >= len - used)
			return -1;
		used += (size_t)n;
	}
	return (int)used;
}

/* Every entry with all of the flags `with` and none of `without` equal in
 * a and b (numbers by value, strings by their text), time left out where
 * skip_time. */
static bool same_entries(const struct params *a, const struct params *b, unsigned with, unsigned without,
			 bool skip_time)
{
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if ((pi->flags & with) != with || (pi->flags & without) ||
		    (skip_time && pi->offset == offsetof(struct params, time)))
			continue;
		if (pi->type == PT_STRING) {
			if (strcmp((const char *)a + pi->offset, (const char *)b + pi->offset) != 0)
				return false;
		} else if (params_get_number(a, pi) != params_get_number(b, pi)) {
			return false;
		}
	}
	return true;
}

bool params_same_terrain(const struct params *a, const struct params *b)
{
	return same_entries(a, b, P_SHADER, 0, false);
}

bool params_same_blocks(const struct params *a, const struct params *b)
{
	return same_entries(a, b, P_SHADER, P_DRAW, false);
}

bool params_same_extraction(const struct params *a, const struct params *b)
{
	return same_entries(a, b, 0, P_DRAW, a->scroll_speed == 0.0f && b->scroll_speed == 0.0f);
}

/* ---- presets ------------------------------------------------------------ */
const struct preset presets[] = {
	{ "default", "GPU Gems style terrain: warped octaves, hard floor, an open landscape seen from above", "" },
	{ "alpine", "ridged multifractal mountains: sharp peaks and ridges, snow", "fractal=ridged;noise_amp=20;noise_freq=0.03;octaves=8;warp_amp=2;noise_y_scale=0.15;snow_line=3" },
	{ "canyon", "terraced canyon land with crisp shelves and a river", "terrace=pre;terrace_step=3;terrace_strength=4;warp_amp=2;soil=arid;snow_line=60;water_level=-5;cam_dist=1.1;cam_pitch=28" },
	{ "melting", "terraces on warped y: they sag with the terrain", "terrace=post;terrace_step=3;terrace_strength=4;warp_amp=6;soil=volcanic;snow_line=60;cam_dist=1.1;cam_pitch=28" },
	{ "alien", "strong domain warp: arches, hooks and tunnels", "warp_freq=0.07;warp_amp=12;noise_amp=14;snow_line=16;cam_dist=1;cam_pitch=15" },
	{ "caves", "endless caves (no ground plane), seen from inside a chamber along a tunnel",
	  "shape=caves;cave_bias=-2;noise_amp=16;noise_freq=0.04;vol_size=170;vol_height=0.6;floor_strength=0;water=false;snow_line=1000;ambient=0.4;"
	  "ao_strength=0.6;fov=65" },
	{ "planet", "a small planet with a round sea, framed whole (the world scene orbits high above it)",
	  "shape=planet;planet_radius=12;vol_size=34;vol_y=-12;vol_height=1;noise_amp=1.4;noise_freq=0.1;gain=0.38;"
	  "floor_strength=0;warp_amp=0.5;water_level=-0.2;water_wave=0.3;snow_line=2.2;cam_dist=1.5;cam_pitch=20;"
	  "fly_height=22;fog=0.4;lod_distance=6" },
	{ "plains", "height-damped multifractal: smooth green lowlands by a lake, rough peaks",
	  "fractal=hetero;noise_amp=10;noise_freq=0.02;noise_y_scale=0.1;mf_offset=0.8;warp_amp=0.5;floor_strength=0;"
	  "water_level=-5;snow_line=12" },
	{ "cells", "Worley F2-F1 cellular terrain: plates meeting at creases, stepped in shelves",
	  "fractal=worley;noise_amp=10;noise_freq=0.05;octaves=1;warp_amp=0;terrace=pre;terrace_step=2.5;terrace_strength=4" },
	{ "turbulence", "Perlin turbulence, Dembogurski's field", "fractal=turbulence;gain=0.56;lacunarity=2.0;octaves=7;noise_amp=16" },
	{ "fbm", "fractional Brownian motion: hills rough alike everywhere, cut by gorges",
	  "fractal=fbm;hurst=0.8;noise_amp=12;noise_freq=0.03;noise_y_scale=0.3;warp_amp=0;floor_strength=0;rotated_octaves=0;"
	  "water_level=-7;snow_line=8" },
	{ "multifractal", "multiplicative multifractal cascade: smooth green uplands under jagged peaks",
	  "fractal=multifractal;noise_amp=12;noise_freq=0.03;noise_y_scale=0.35;warp_amp=1;floor_strength=0;water_level=-7;"
	  "snow_line=7" },
	{ "landing", "terrain with a flat landing pad", "flat_spot=true;flat_y=-4;flat_inner=16;flat_outer=26;cam_pitch=50" },
	{ "diorama", "the default terrain as a closed block with cut walls, orbited from outside",
	  "closed=true;vol_size=32;vol_height=1;cam_dist=1.85;cam_pitch=24" },
	{ "torus", "test field: torus", "field=torus;vol_y=0;vol_size=2.4;vol_height=1;field_scale=1;closed=true;cam_dist=1.9;cam_pitch=26" },
	{ "bumps", "test field: sin(5x)cos(5z)/5", "field=bumps;vol_y=0;vol_size=2.4;vol_height=1;field_scale=1;closed=true;cam_dist=1.9;cam_pitch=26" },
	{ "ripple", "test field: sin(10(x^2+z^2))/10", "field=ripple;vol_y=0;vol_size=2.4;vol_height=1;field_scale=1;closed=true;cam_dist=1.9;cam_pitch=26" },
};
const size_t preset_count = ARRAY_SIZE(presets);

static int apply_settings(struct params *p, const char *settings, const char *origin, char *err, size_t errlen)
{
	char buf[1024];
	snprintf(buf, sizeof(buf), "%s", settings);
	char *save = NULL;
	for (char *tok = strtok_r(buf, ";", &save); tok; tok = strtok_r(NULL, ";", &save)) {
		char *eq = strchr(tok, '=');
		if (!eq) {
			snprintf(err, errlen, "%s: '%s' is not key=value", origin, tok);
			return -1;
		}
		*eq = 0;
		char e[256];
		if (params_set(p, tok, eq + 1, e, sizeof(e)) < 0) {
			snprintf(err, errlen, "%s: %s", origin, e);
			return -1;
		}
	}
	return 0;
}

int params_apply_preset(struct params *p, const char *name, char *err, size_t errlen)
{
	for (size_t i = 0; i < preset_count; i++)
		if (!strcmp(presets[i].name, name))
			return apply_settings(p, presets[i].settings, name, err, errlen);
	char list[512] = "";
	for (size_t i = 0; i < preset_count; i++) {
		strncat(list, presets[i].name, sizeof(list) - strlen(list) - 2);
		if (i + 1 < preset_count)
			strncat(list, " ", sizeof(list) - strlen(list) - 1);
	}
	snprintf(err, errlen, "unknown preset '%s' (one of: %s)", name, list);
	return -1;
}

int params_load_config_text(struct params *p, const char *text, const char *fname, char *err, size_t errlen)
{
	int lineno = 0;
	const char *line = text;
	if (!strncmp(line, "\xEF\xBB\xBF", 3)) /* a UTF-8 byte order mark: not part of the first line */
		line += 3;
	while (line && *line) {
		const char *nl = strchr(line, '\n');
		size_t n = nl ? (size_t)(nl - line) : strlen(line);
		lineno++;
		char buf[1024];
		if (n >= sizeof(buf)) {
			snprintf(err, errlen, "%s:%d: line too long", fname, lineno);
			return -1;
		}
		memcpy(buf, line, n);
		buf[n] = 0;
		char *hash = strchr(buf, '#');
		if (hash)
			*hash = 0;
		char *s = str_trim(buf);
		if (*s) {
			char *eq = strchr(s, '=');
			if (!eq) {
				snprintf(err, errlen, "%s:%d: expected 'name = value', got '%s'", fname, lineno, s);
				return -1;
			}
			*eq = 0;
			char *key = str_trim(s), *val = str_trim(eq + 1);
			size_t vl = strlen(val);
			if (vl >= 2 && val[0] == '"' && val[vl - 1] == '"') {
				val[vl - 1] = 0;
				val++;
			}
			char e[384];
			int rc;
			if (!strcmp(key, "preset"))
				rc = params_apply_preset(p, val, e, sizeof(e));
			else
				rc = params_set(p, key, val, e, sizeof(e));
			if (rc < 0) {
				snprintf(err, errlen, "%s:%d: %s", fname, lineno, e);
				return -1;
			}
		}
		line = nl ? nl + 1 : NULL;
	}
	return 0;
}

int params_load_config_file(struct params *p, const char *path, char *err, size_t errlen)
{
	FILE *f = fopen(path, "rb");
	if (!f) {
		snprintf(err, errlen, "cannot open config file '%s': %s", path, strerror(errno));
		return -1;
	}
	char *text = NULL;
	size_t cap = 0, len = 0;
	for (;;) {
		if (len + 4096 + 1 > cap) {
			cap = cap ? cap * 2 : 8192;
			if (cap > (1u << 24)) {
				free(text);
				fclose(f);
				snprintf(err, errlen, "config file '%s' is too large", path);
				return -1;
			}
			char *nt = realloc(text, cap);
			if (!nt) {
				free(text);
				fclose(f);
				snprintf(err, errlen, "out of memory reading '%s'", path);
				return -1;
			}
			text = nt;
		}
		size_t r = fread(text + len, 1, cap - len - 1, f);
		len += r;
		if (r == 0)
			break;
	}
	int ferr = ferror(f);
	fclose(f);
	if (ferr) {
		free(text);
		snprintf(err, errlen, "error reading config file '%s'", path);
		return -1;
	}
	text[len] = 0;
	if (strlen(text) != len) {
		free(text);
		snprintf(err, errlen, "config file '%s' is not text (contains NUL bytes)", path);
		return -1;
	}
	int rc = params_load_config_text(p, text, path, err, errlen);
	free(text);
	return rc;
}
