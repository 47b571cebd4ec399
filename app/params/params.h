/* isoterra — the parameter table.
 *
 * Every tunable lives in one table (params.def): name, type, range, default
 * and help.  The table drives the command line (--name value), the config
 * file (name = value), the shader uniforms (u_name, for P_SHADER entries) and
 * the GPIO knobs (app/controls.c). */
#ifndef ISOTERRA_PARAMS_H
#define ISOTERRA_PARAMS_H

#include <stddef.h>
#include <stdbool.h>
#include <stdio.h>

#include "params_enums.h" /* enum param_<name>: generated from params.def */

enum param_type { PT_FLOAT, PT_INT, PT_BOOL, PT_ENUM, PT_STRING };

enum param_flags {
	P_SHADER = 1 << 0, /* exposed to GLSL as "uniform <type> u_<name>;" */
	P_APP = 1 << 1,    /* application option (size, out, ...) */
	P_LIVE = 1 << 2,   /* sensible to change live (knobs) */
	P_SPECIALIZE = 1 << 3, /* P_SHADER that selects code paths: compiled in as a
	                        * constant (#define u_name V) where the host asks,
	                        * so drivers need not run every branch */
	P_TERM = 1 << 4,       /* P_SHADER number whose 0 turns a term off: the
	                        * specialization carries TERM_<NAME> 0|1 and the
	                        * term's code is compiled only under TERM_<NAME>;
	                        * the value stays a uniform while the term is on
	                        * (a knob moving within "on" never recompiles) */
	P_DRAW = 1 << 5,       /* P_SHADER read by the draw's shaders only (the
	                        * terrain's, sky's, water's): no compute pass
	                        * reads it, so a change makes no world block
	                        * again (params_same_blocks) */
};

#define PARAM_STR_MAX 256

/* The autopilot's first heading, radians from +x towards +z (the flight
 * starts at fly_x, fly_z on it: scene/autopilot.c; a georeferenced map's
 * fit aims it across the map: edit/map_fit.c). */
#define FLY_START_HEADING 0.3f

struct params {
#define PF(name, def, lo, hi, flags, help) float name;
#define PI(name, def, lo, hi, flags, help) int name;
#define PB(name, def, flags, help) bool name;
#define PE(name, def, choices, flags, help) int name;
#define PS(name, def, flags, help) char name[PARAM_STR_MAX];
#include "params.def"
#undef PF
#undef PI
#undef PB
#undef PE
#undef PS
};

struct param_info {
	const char *name;
	enum param_type type;
	size_t offset;
	double def, lo, hi;   /* numeric default and inclusive range */
	const char *def_str;  /* PT_STRING default */
	const char *choices;  /* PT_ENUM: "a|b|c", index = value */
	unsigned flags;
	const char *help;
};

extern const struct param_info param_table[];
extern const size_t param_count;

void params_defaults(struct params *p);
const struct param_info *params_find(const char *name);
/* Accepts '-' for '_' in names.  Returns 0, or -1 with a one-line message in err. */
int params_set(struct params *p, const char *name, const char *value, char *err, size_t errlen);
/* Value as text ("0.5", "true", "alu", ...). */
void params_format(const struct params *p, const struct param_info *pi, char *buf, size_t len);
/* Numeric value of a FLOAT/INT/BOOL/ENUM entry. */
double params_get_number(const struct params *p, const struct param_info *pi);
void params_set_number(struct params *p, const struct param_info *pi, double v);
/* Enum index -> its choice's name (the number itself when out of range). */
void params_enum_name(const struct param_info *pi, int idx, char *buf, size_t len);
/* Enum choice name -> index, or -1. */
int params_enum_index(const struct param_info *pi, const char *choice);
/* Help text: one entry a line (or two), for --help. */
void params_print_help(FILE *f, unsigned flag_mask);
/* GLSL declarations of every P_SHADER entry and enum constants, and for
 * every P_TERM entry "#define TERM_<NAME> 1" unless the program's
 * specialization set it (an unspecialized program keeps every term: its
 * uniform checks decide), NUL-terminated; returns the number of bytes
 * written (excluding NUL) or -1 if buf too small. */
int params_glsl_decls(char *buf, size_t len);
/* The shader variant key: "#define u_name V\n" for every P_SPECIALIZE entry
 * and "#define TERM_<NAME> 0|1\n" (value != 0) for every P_TERM entry;
 * returns bytes written or -1 if buf is too small. */
int params_glsl_specialization(const struct params *p, char *buf, size_t len);
/* True when two parameter sets give the same terrain (all P_SHADER equal). */
bool params_same_terrain(const struct params *a, const struct params *b);
/* True when two parameter sets give the same world blocks: the P_SHADER
 * entries equal but the P_DRAW ones (the light's ambient and sun strength,
 * the surface's colours, snow, fog, water, the AO's strength; a sun
 * direction is baked into the vertices' shadows and counts). */
bool params_same_blocks(const struct params *a, const struct params *b);
/* True when the volume scene's extraction of a and of b is the same mesh:
 * every entry equal (numbers and strings) but the P_DRAW ones, and time
 * too unless the field scrolls (scroll_speed, the one term time moves).
 * The camera's entries count: conservative, they change rarely. */
bool params_same_extraction(const struct params *a, const struct params *b);

/* Presets: named key=value lists applied over the defaults. */
struct preset {
	const char *name;
	const char *help;
	const char *settings; /* "key=value;key=value;..." */
};
extern const struct preset presets[];
extern const size_t preset_count;
int params_apply_preset(struct params *p, const char *name, char *err, size_t errlen);
/* Parse "key = value" config text (# comments, blank lines).  On error, err
 * gets "FILE:LINE: message". */
int params_load_config_text(struct params *p, const char *text, const char *fname, char *err, size_t errlen);
int params_load_config_file(struct params *p, const char *path, char *err, size_t errlen);

/* the command line over the table */
#include "cli.h"
/* the video wall's geometry */
#include "wall.h"

#endif
