/* isoterra — command line over the parameter table. */
#include "cli.h"
#include "core.h"
#include "platform.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <errno.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef ISOTERRA_VERSION
#define ISOTERRA_VERSION "0.1.0"
#endif

enum opt_kind { OPT_PARAM, OPT_NO_BOOL, OPT_SET, OPT_PRESET, OPT_CONFIG, OPT_HELP, OPT_VERSION, OPT_LIST_PRESETS,
	OPT_LIST_DEVICES };

struct opt {
	enum opt_kind kind;
	const struct param_info *pi; /* OPT_PARAM, OPT_NO_BOOL */
	const char *value;           /* NULL for flags */
};

static bool is_bool_word(const char *s)
{
	static const char *const words[] = { "1", "0", "true", "false", "on", "off", "yes", "no" };
	for (size_t i = 0; i < ARRAY_SIZE(words); i++)
		if (!strcmp(s, words[i]))
			return true;
	return false;
}

/* Option name between "--" and '=' with '-' folded to '_'; false if too long. */
static bool opt_key(const char *arg, char *key, size_t len)
{
	size_t n = strcspn(arg + 2, "=");
	if (n >= len)
		return false;
	for (size_t i = 0; i < n; i++)
		key[i] = arg[2 + i] == '-' ? '_' : arg[2 + i];
	key[n] = 0;
	return true;
}

/* -h, -D CARD (kmscube's -D: the DRM card): 1 handled, 0 not one of
 * them, -1 error. */
static int short_opt(const char *arg, int argc, char **argv, int *i, struct opt *o, char *err, size_t errlen)
{
	if (!strcmp(arg, "-h")) {
		o->kind = OPT_HELP;
		return 1;
	}
	if (strcmp(arg, "-D"))
		return 0;
	if (*i >= argc) {
		snprintf(err, errlen, "option '-D' needs a value");
		return -1;
	}
	o->kind = OPT_PARAM;
	o->pi = params_find("drm_device");
	o->value = argv[(*i)++];
	return 1;
}

/* What the option named key is (o->kind, o->pi); false when unknown.
 * *takes_value: it has a value; *optional_bool: a boolean whose value may
 * be left out. */
static bool classify(const char *key, struct opt *o, bool *takes_value, bool *optional_bool)
{
	static const struct {
		const char *name;
		enum opt_kind kind;
		bool value;
	} words[] = {
		{ "help", OPT_HELP, false },	 { "version", OPT_VERSION, false }, { "list_presets", OPT_LIST_PRESETS, false },
		{ "list_devices", OPT_LIST_DEVICES, false },
		{ "set", OPT_SET, true },	 { "preset", OPT_PRESET, true },    { "config", OPT_CONFIG, true },
	};
	*takes_value = true;
	*optional_bool = false;
	for (size_t k = 0; k < ARRAY_SIZE(words); k++)
		if (!strcmp(key, words[k].name)) {
			o->kind = words[k].kind;
			*takes_value = words[k].value;
			return true;
		}
	if ((o->pi = params_find(key)) != NULL) {
		o->kind = OPT_PARAM;
		*optional_bool = o->pi->type == PT_BOOL;
		return true;
	}
	if (!strncmp(key, "no_", 3) && (o->pi = params_find(key + 3)) && o->pi->type == PT_BOOL) {
		o->kind = OPT_NO_BOOL;
		*takes_value = false;
		return true;
	}
	return false;
}

/* The option's value: after '=', the next argument, or (an optional
 * boolean) "true". */
static int opt_value(const char *arg, const char *eq, bool optional_bool, int argc, char **argv, int *i, struct opt *o,
		     char *err, size_t errlen)
{
	if (eq) {
		o->value = eq + 1;
	} else if (optional_bool) {
		/* --flag alone means true; "--flag false" is accepted too. */
		if (*i < argc && is_bool_word(argv[*i]))
			o->value = argv[(*i)++];
		else
			o->value = "true";
	} else {
		if (*i >= argc || !strncmp(argv[*i], "--", 2)) {
			snprintf(err, errlen, "option '%s' needs a value", arg);
			return -1;
		}
		o->value = argv[(*i)++];
	}
	return 0;
}

/* Decodes argv[*i] (and its value argument) into o; advances *i. */
static int next_opt(int argc, char **argv, int *i, struct opt *o, char *err, size_t errlen)
{
	const char *arg = argv[*i];
	(*i)++;
	memset(o, 0, sizeof(*o));
	int s = short_opt(arg, argc, argv, i, o, err, errlen);
	if (s != 0)
		return s < 0 ? -1 : 0;
	if (arg[0] != '-' || !strcmp(arg, "-") || !strcmp(arg, "--")) {
		snprintf(err, errlen, "unexpected argument '%s' (options only, see --help)", arg);
		return -1;
	}
	char key[64];
	const char *eq = strchr(arg, '=');
	int optlen = eq ? (int)(eq - arg) : (int)strlen(arg);
	bool takes_value, optional_bool;
	if (arg[1] != '-' || !opt_key(arg, key, sizeof(key)) || !key[0] ||
	    !classify(key, o, &takes_value, &optional_bool)) {
		snprintf(err, errlen, "unknown option '%.*s' (see --help)", optlen, arg);
		return -1;
	}
	if (!takes_value) {
		if (eq) {
			snprintf(err, errlen, "option '%.*s' takes no value", optlen, arg);
			return -1;
		}
		return 0;
	}
	return opt_value(arg, eq, optional_bool, argc, argv, i, o, err, errlen);
}

static bool ends_with(const char *s, const char *suffix)
{
	size_t n = strlen(s), m = strlen(suffix);
	return n > m && strcasecmp(s + n - m, suffix) == 0;
}

int cli_parse_size(const char *s, int *w, int *h)
{
	long v[2];
	const char *c = s;
	for (int k = 0; k < 2; k++) {
		if (*c < '0' || *c > '9')
			return -1;
		char *end;
		v[k] = strtol(c, &end, 10);
		if (end - c > 6 || v[k] < 16 || v[k] > 16384)
			return -1;
		c = end;
		if (k == 0 && *c++ != 'x')
			return -1;
	}
	if (*c)
		return -1;
	*w = (int)v[0];
	*h = (int)v[1];
	return 0;
}

int cli_numbered_name(const char *pattern, int n, char *buf, size_t len)
{
	const char *pc = strchr(pattern, '%');
	if (!pc) {
		if (strlen(pattern) >= len)
			return -2;
		memcpy(buf, pattern, strlen(pattern) + 1);
		return 0;
	}
	/* %d, %Nd, %0Nd: printf's zero flag (any number of them) and width */
	const char *q = pc + 1;
	bool zero = false;
	while (*q == '0') {
		zero = true;
		q++;
	}
	int width = 0;
	for (; *q >= '0' && *q <= '9'; q++) {
		width = width * 10 + (*q - '0');
		if (width > CLI_NAME_WIDTH_MAX)
			return -1;
	}
	if (*q != 'd' || strchr(q + 1, '%') || n < 0)
		return -1;
	char num[16];
	int nd = snprintf(num, sizeof(num), "%d", n);
	size_t pre = (size_t)(pc - pattern), pad = width > nd ? (size_t)(width - nd) : 0, post = strlen(q + 1);
	if (pre + pad + (size_t)nd + post >= len)
		return -2;
	memcpy(buf, pattern, pre);
	memset(buf + pre, zero ? '0' : ' ', pad);
	memcpy(buf + pre + pad, num, (size_t)nd);
	memcpy(buf + pre + pad + (size_t)nd, q + 1, post + 1);
	return 1;
}

int cli_check_dest(const char *what, const char *pattern, int last, char *err, size_t errlen)
{
	char name[PATH_MAX];
	int numbered = cli_numbered_name(pattern, last, name, sizeof(name));
	if (numbered == -1) {
		snprintf(err, errlen, "%s: '%s': at most one %%d (or %%0Nd, N up to %d) in the name", what, pattern,
			 CLI_NAME_WIDTH_MAX);
		return -1;
	}
	const char *slash = strrchr(pattern, '/');
	size_t dlen = slash ? (size_t)(slash - pattern) : 0;
	char dir[PATH_MAX];
	snprintf(dir, sizeof(dir), "%.*s", (int)(slash ? (dlen ? dlen : 1) : 1), slash ? pattern : ".");
	long name_max = pathconf(dir, _PC_NAME_MAX);
	if (name_max <= 0)
		name_max = NAME_MAX;
	/* the temp file beside it is ATOMIC_TMP_EXTRA longer */
	if (numbered == -2 || strlen(name) + ATOMIC_TMP_EXTRA >= PATH_MAX ||
	    (long)strlen(name + (slash ? dlen + 1 : 0)) + ATOMIC_TMP_EXTRA > name_max) {
		snprintf(err, errlen, "%s: '%s' is too long a file name%s (at most %ld bytes in a name, %d in a path, "
			 "with %d to spare for the temp file)", what, pattern, numbered ? " for the last frame's number" : "",
			 name_max, PATH_MAX - 1, ATOMIC_TMP_EXTRA);
		return -1;
	}
	struct stat st;
	if (stat(dir, &st) < 0) {
		snprintf(err, errlen, "%s: cannot write '%s': directory '%s': %s", what, pattern, dir, strerror(errno));
		return -1;
	}
	if (!S_ISDIR(st.st_mode)) {
		snprintf(err, errlen, "%s: cannot write '%s': '%s' is not a directory", what, pattern, dir);
		return -1;
	}
	if (access(dir, W_OK | X_OK) < 0) {
		snprintf(err, errlen, "%s: cannot write '%s': directory '%s': %s", what, pattern, dir, strerror(errno));
		return -1;
	}
	if (!numbered && stat(pattern, &st) == 0 && S_ISDIR(st.st_mode)) {
		snprintf(err, errlen, "%s: cannot write '%s': it is a directory", what, pattern);
		return -1;
	}
	return 0;
}

int cli_parse_out(const char *out, enum cli_out_kind *kind, char *err, size_t errlen)
{
	bool y4m = !strcmp(out, "-") || ends_with(out, ".y4m");
	if (!y4m && !ends_with(out, ".png")) {
		snprintf(err, errlen, "out: '%s' must end in .png or .y4m (or be - for a Y4M stream on stdout)", out);
		return -1;
	}
	char name[PATH_MAX];
	int numbered = cli_numbered_name(out, 0, name, sizeof(name));
	if (numbered == -1) {
		snprintf(err, errlen, "--out '%s': only one %%d (or %%0Nd, N up to %d) is allowed in the file name", out,
			 CLI_NAME_WIDTH_MAX);
		return -1;
	}
	*kind = y4m ? CLI_OUT_Y4M : numbered ? CLI_OUT_PNG_SEQUENCE : CLI_OUT_PNG;
	return 0;
}

static int validate(const struct params *p, char *err, size_t errlen)
{
	int w, h;
	if (cli_parse_size(p->size, &w, &h) < 0) {
		snprintf(err, errlen, "size: '%s' is not WxH with W and H in 16..16384", p->size);
		return -1;
	}
	enum cli_out_kind kind;
	if (cli_parse_out(p->out, &kind, err, errlen) < 0)
		return -1;
	if (p->export_mesh[0] && !ends_with(p->export_mesh, ".ply")) {
		snprintf(err, errlen, "export_mesh: '%s' must end in .ply", p->export_mesh);
		return -1;
	}
	if (platform_device_check(p->device, err, errlen) < 0)
		return -1;
	struct wall_view wv;
	if (wall_view(p, w, h, 1, &wv, err, errlen) < 0 || wall_clock_realtime(p, err, errlen) < 0)
		return -1;
	if (p->rotate != ROTATE_0 && p->v4l2[0]) {
		snprintf(err, errlen, "rotate: the V4L2 output (--v4l2 %s) streams the upright picture; turn it at the "
			 "receiver, or drop --rotate", p->v4l2);
		return -1;
	}
	if (wv.on && p->governor == GOVERNOR_ON) {
		snprintf(err, errlen, "governor: on a %s wall every tile holds one quality (--quality N, the same on "
			 "every board), not a governor of its own", p->wall);
		return -1;
	}
	if (p->outputs[0] && strcmp(p->platform, "gbm") && strcmp(p->platform, "auto")) {
		snprintf(err, errlen, "outputs: '%s' names KMS connectors, which --platform gbm (or auto) drives, not '%s'",
			 p->outputs, p->platform);
		return -1;
	}
	if (p->outputs[0] && wv.on && strcmp(p->outputs, "all")) {
		/* a tile each along the row ("all": checked when the connectors are known) */
		int n = 1;
		for (const char *c = p->outputs; *c; c++)
			n += *c == ',';
		if (wall_view(p, w, h, n, &wv, err, errlen) < 0)
			return -1;
	}
	if (p->device[0] && strcmp(p->platform, "device") && strcmp(p->platform, "auto")) {
		snprintf(err, errlen, "device: '%s' names an EGL device of --platform device, not of '%s'%s", p->device,
			 p->platform, !strcmp(p->platform, "gbm") ? " (gbm's card: --drm-device)" : "");
		return -1;
	}
	return 0;
}

/* A heightmap is read only by field=heightmap: given without a field
 * (p->field still -1: no preset, config or option set one), it implies
 * that field, said in a note; given with another field, it would be
 * silently unused: a warning. */
static void heightmap_field(struct params *p, int field_default)
{
	bool given = p->field >= 0;
	if (!given)
		p->field = field_default;
	if (!p->heightmap[0] || p->field == FIELD_HEIGHTMAP)
		return;
	const struct param_info *fi = params_find("field");
	char name[32];
	params_enum_name(fi, p->field, name, sizeof(name));
	if (!given) {
		p->field = FIELD_HEIGHTMAP;
		log_info("heightmap %s given without a field: field = heightmap", p->heightmap);
	} else {
		log_warn("heightmap %s is not used: field = %s (only field = heightmap reads it)", p->heightmap, name);
	}
}

static void list_presets(void)
{
	printf("presets (--preset NAME, applied before --config and other options):\n");
	for (size_t i = 0; i < preset_count; i++)
		printf("  %-14s %s\n", presets[i].name, presets[i].help);
}

void cli_print_help(const char *argv0)
{
	const char *slash = argv0 ? strrchr(argv0, '/') : NULL;
	const char *prog = slash ? slash + 1 : argv0 && argv0[0] ? argv0 : "isoterra";
	printf("usage: %s [options]\n"
	       "Procedural terrain on the GPU (OpenGL ES 3.1 compute, headless EGL).\n"
	       "\n"
	       "  --size WxH             output size, 16..16384 each (default 1280x720)\n"
	       "  --grid N               cells per axis of the extracted volume\n"
	       "  --count N              frames to render, then exit\n"
	       "  --out FILE.png         output image (%%d in the name: one file per frame);\n"
	       "                         FILE.y4m or - : a YUV4MPEG2 stream of every frame (pipe into ffmpeg)\n"
	       "  --export-mesh FILE.ply write the last frame's mesh as binary PLY\n"
	       "  --preset NAME          start from a preset (see --list-presets)\n"
	       "  --config FILE          'name = value' lines, applied after the preset\n"
	       "  --platform NAME        auto|gbm|wayland|x11|device|surfaceless (built: %s)\n"
	       "  --fullscreen           wayland/x11 fullscreen; --hide-cursor (wayland/x11)\n"
	       "  -D, --drm-device CARD  gbm: /dev/dri/cardN; --mode WxH[@Hz] the display mode\n"
	       "  --device N|PATH        device: the EGL device by index or DRM node (see --list-devices)\n"
	       "  --count 0              display platforms: run until closed / SIGINT / SIGTERM\n"
	       "  --fps-report SECONDS   print the frame rate every SECONDS (and on SIGUSR1)\n"
	       "  --shader-dir DIR       load shaders from DIR instead of the built-in copies\n"
	       "  --set NAME=VALUE       set any parameter below\n"
	       "  --help, --version, --list-presets, --list-devices (the EGL devices, then exit)\n"
	       "\n"
	       "Every parameter is --name VALUE or --name=VALUE ('-' or '_' in names);\n"
	       "booleans also --name / --no-name.  --preset and --config apply first, then\n"
	       "the other options in order, so explicit options win.\n"
	       "\n"
	       "Application:\n", prog, platform_backend_names());
	params_print_help(stdout, P_APP);
	printf("\nTerrain (shader uniforms):\n");
	params_print_help(stdout, P_SHADER);
}

enum cli_result cli_parse(int argc, char **argv, struct params *p, char *err, size_t errlen)
{
	struct opt o;
	char e[512];
	params_defaults(p);

	/* Pass 1: syntax, and the options that exit at once. */
	for (int i = 1; i < argc;) {
		if (next_opt(argc, argv, &i, &o, err, errlen) < 0)
			return CLI_ERROR;
		switch (o.kind) {
		case OPT_HELP:
			cli_print_help(argc > 0 ? argv[0] : NULL);
			return CLI_EXIT_OK;
		case OPT_VERSION:
			printf("isoterra %s\n", ISOTERRA_VERSION);
			return CLI_EXIT_OK;
		case OPT_LIST_PRESETS:
			list_presets();
			return CLI_EXIT_OK;
		case OPT_LIST_DEVICES:
			return CLI_LIST_DEVICES;
		default:
			break;
		}
	}
	/* Pass 2: presets, 3: config files, 4: everything else in order.  The
	 * field starts unset (-1) so that heightmap_field sees whether any of
	 * them gave one. */
	int field_default = p->field;
	p->field = -1;
	for (int pass = 2; pass <= 4; pass++) {
		for (int i = 1; i < argc;) {
			if (next_opt(argc, argv, &i, &o, err, errlen) < 0)
				return CLI_ERROR;
			int rc = 0;
			if (pass == 2 && o.kind == OPT_PRESET) {
				rc = params_apply_preset(p, o.value, e, sizeof(e));
			} else if (pass == 3 && o.kind == OPT_CONFIG) {
				rc = params_load_config_file(p, o.value, e, sizeof(e));
			} else if (pass == 4 && o.kind == OPT_PARAM) {
				rc = params_set(p, o.pi->name, o.value, e, sizeof(e));
			} else if (pass == 4 && o.kind == OPT_NO_BOOL) {
				rc = params_set(p, o.pi->name, "false", e, sizeof(e));
			} else if (pass == 4 && o.kind == OPT_SET) {
				const char *eq = strchr(o.value, '=');
				char name[64];
				if (!eq || eq == o.value || (size_t)(eq - o.value) >= sizeof(name)) {
					snprintf(err, errlen, "option '--set' needs NAME=VALUE, got '%s'", o.value);
					return CLI_ERROR;
				}
				snprintf(name, sizeof(name), "%.*s", (int)(eq - o.value), o.value);
				rc = params_set(p, name, eq + 1, e, sizeof(e));
			}
			if (rc < 0) {
				snprintf(err, errlen, "%s", e);
				return CLI_ERROR;
			}
		}
	}
	heightmap_field(p, field_default);
	return validate(p, err, errlen) < 0 ? CLI_ERROR : CLI_RUN;
}
