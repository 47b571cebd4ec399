/* isoterra — parameter table, config files, presets and the command line. */
#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "params.h"
#include "tcheck.h"

static char tmpdir[] = "/tmp/isoterra-test-params.XXXXXX";

/* cli_parse over a NULL-terminated argument list (argv[0] added). */
static enum cli_result parse(struct params *p, char *err, size_t errlen, ...)
{
	char *argv[64] = { "isoterra" };
	int argc = 1;
	va_list ap;
	va_start(ap, errlen);
	for (char *a; (a = va_arg(ap, char *)) != NULL && argc < 63;)
		argv[argc++] = a;
	va_end(ap);
	argv[argc] = NULL;
	err[0] = 0;
	return cli_parse(argc, argv, p, err, errlen);
}

#define PARSE(p, err, ...) parse(p, err, sizeof(err), __VA_ARGS__, (char *)NULL)

/* Expect cli_parse to fail with exactly msg. */
#define PARSE_FAILS(msg, ...)                                                              \
	do {                                                                               \
		struct params q_;                                                          \
		char e_[512];                                                              \
		enum cli_result r_ = PARSE(&q_, e_, __VA_ARGS__);                          \
		CHECK(r_ == CLI_ERROR && strcmp(e_, msg) == 0, "got %d '%s', want '%s'", r_, e_, msg); \
	} while (0)

/* Run f with stdout sent to /dev/null (help, version, list). */
static enum cli_result quiet_parse(const char *opt)
{
	struct params p;
	char err[256];
	fflush(stdout);
	int saved = dup(1), null = open("/dev/null", O_WRONLY);
	if (saved >= 0 && null >= 0)
		dup2(null, 1);
	enum cli_result r = PARSE(&p, err, "--grid", "7", opt);
	fflush(stdout);
	if (saved >= 0) {
		dup2(saved, 1);
		close(saved);
	}
	if (null >= 0)
		close(null);
	return r;
}

static void write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	CHECK(f != NULL, "cannot create %s", path);
	if (f) {
		fputs(text, f);
		fclose(f);
	}
}

static void test_defaults(void)
{
	struct params p;
	params_defaults(&p);
	CHECK(p.grid == 128, "grid %d", p.grid);
	CHECK(p.count == 1, "count %d", p.count);
	CHECK(!strcmp(p.size, "1280x720"), "size %s", p.size);
	CHECK(!strcmp(p.out, "isoterra.png"), "out %s", p.out);
	CHECK(!strcmp(p.platform, "auto"), "platform %s", p.platform);
	CHECK(p.export_mesh[0] == 0, "export_mesh %s", p.export_mesh);
	CHECK(p.iso == 0.0f && p.octaves == 9 && !p.verbose && p.compaction == 0, "misc defaults");
	CHECK_NEAR(p.lacunarity, 1.98, 1e-6, "lacunarity");
	CHECK_NEAR(p.vol_y, params_find("vol_y")->def, 0, "vol_y");
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (pi->type == PT_FLOAT || pi->type == PT_INT)
			CHECK(pi->def >= pi->lo && pi->def <= pi->hi, "%s default outside its range", pi->name);
		CHECK(pi->help && pi->help[0], "%s has no help", pi->name);
		CHECK(params_find(pi->name) == pi, "find %s", pi->name);
	}
}

static void expect_set_error(const char *name, const char *value, const char *msg)
{
	struct params p;
	char err[256] = "";
	params_defaults(&p);
	int rc = params_set(&p, name, value, err, sizeof(err));
	CHECK(rc == -1 && !strcmp(err, msg), "set %s=%s: rc %d '%s', want '%s'", name, value, rc, err, msg);
}

static void test_set(void)
{
	struct params p;
	char err[256];
	params_defaults(&p);
	CHECK(params_set(&p, "grid", "64", err, sizeof(err)) == 0 && p.grid == 64, "grid 64");
	CHECK(params_set(&p, "max-triangles", "1000", err, sizeof(err)) == 0 && p.max_triangles == 1000, "dashes");
	CHECK(params_set(&p, "iso", "-1.5", err, sizeof(err)) == 0 && p.iso == -1.5f, "iso");
	CHECK(params_set(&p, "fractal", "ridged", err, sizeof(err)) == 0 && p.fractal == 3, "enum");
	CHECK(params_set(&p, "verbose", "yes", err, sizeof(err)) == 0 && p.verbose, "bool");
	CHECK(params_set(&p, "out", "a b.png", err, sizeof(err)) == 0 && !strcmp(p.out, "a b.png"), "string");

	expect_set_error("grid", "1", "grid: 1 is out of range [2, 512]");
	expect_set_error("grid", "513", "grid: 513 is out of range [2, 512]");
	expect_set_error("grid", "12x", "grid: '12x' is not an integer");
	expect_set_error("iso", "abc", "iso: 'abc' is not a number");
	expect_set_error("iso", "nan", "iso: 'nan' is not a number");
	expect_set_error("gain", "1.5", "gain: 1.5 is out of range [0, 1]");
	expect_set_error("verbose", "maybe", "verbose: 'maybe' is not a boolean (true/false)");
	expect_set_error("fractal", "bogus", "fractal: 'bogus' is not one of geiss|fbm|turbulence|ridged|multifractal|hetero|worley|hybrid|slope_damped|abs_multifractal");
	expect_set_error("compaction", "", "compaction: '' is not one of hp|atomic|none");
	expect_set_error("nonexistent", "1", "unknown parameter 'nonexistent' (see --help)");
	char longv[PARAM_STR_MAX + 8];
	memset(longv, 'a', sizeof(longv) - 1);
	longv[sizeof(longv) - 1] = 0;
	expect_set_error("out", longv, "out: value longer than 255 characters");
}

/* Every entry: format -> set -> format gives the same text and value. */
static void test_round_trip(void)
{
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		struct params a, b;
		char err[256], t1[PARAM_STR_MAX], t2[PARAM_STR_MAX];
		params_defaults(&a);
		/* a non-default value */
		switch (pi->type) {
		case PT_FLOAT:
		case PT_INT:
			params_set_number(&a, pi, pi->lo + (pi->hi - pi->lo) * 0.37);
			break;
		case PT_BOOL:
			params_set_number(&a, pi, !pi->def);
			break;
		case PT_ENUM:
			params_set_number(&a, pi, pi->def + 1);
			break;
		case PT_STRING:
			snprintf((char *)&a + pi->offset, PARAM_STR_MAX, "x-%s.png", pi->name);
			break;
		}
		for (int round = 0; round < 2; round++) {
			params_defaults(&b);
			if (round == 0)
				params_defaults(&a);
			params_format(&a, pi, t1, sizeof(t1));
			int rc = params_set(&b, pi->name, t1, err, sizeof(err));
			CHECK(rc == 0, "%s: set '%s': %s", pi->name, t1, err);
			params_format(&b, pi, t2, sizeof(t2));
			CHECK(!strcmp(t1, t2), "%s: '%s' -> '%s'", pi->name, t1, t2);
			if (pi->type == PT_STRING) {
				CHECK(!strcmp((char *)&a + pi->offset, (char *)&b + pi->offset), "%s string", pi->name);
			} else {
				double va = params_get_number(&a, pi), vb = params_get_number(&b, pi);
				CHECK(fabs(va - vb) <= 1e-5 * fmax(1.0, fabs(va)), "%s: %g -> %g", pi->name, va, vb);
			}
			if (round == 0) /* restore the non-default value for round 1 */
				switch (pi->type) {
				case PT_FLOAT:
				case PT_INT: params_set_number(&a, pi, pi->lo + (pi->hi - pi->lo) * 0.37); break;
				case PT_BOOL: params_set_number(&a, pi, !pi->def); break;
				case PT_ENUM: params_set_number(&a, pi, pi->def + 1); break;
				case PT_STRING: snprintf((char *)&a + pi->offset, PARAM_STR_MAX, "x-%s.png", pi->name); break;
				}
		}
	}
}

static void test_glsl(void)
{
	static char buf[16384];
	int n = params_glsl_decls(buf, sizeof(buf));
	CHECK(n > 0 && (size_t)n == strlen(buf), "glsl decls length %d", n);
	CHECK(strstr(buf, "uniform float u_iso;\n") != NULL, "u_iso missing");
	CHECK(strstr(buf, "uniform int u_octaves;\n") != NULL, "u_octaves missing");
	CHECK(strstr(buf, "uniform int u_fractal;\n") != NULL, "u_fractal missing");
	CHECK(strstr(buf, "#define FRACTAL_RIDGED 3\n") != NULL, "FRACTAL_RIDGED missing");
	CHECK(strstr(buf, "u_grid") == NULL, "app parameter in GLSL");
	char small[32];
	CHECK(params_glsl_decls(small, sizeof(small)) == -1, "small buffer");

	struct params a, b;
	params_defaults(&a);
	params_defaults(&b);
	CHECK(params_same_terrain(&a, &b), "same");
	b.grid = 64;
	CHECK(params_same_terrain(&a, &b), "grid is not terrain");
	b.iso = 0.25f;
	CHECK(!params_same_terrain(&a, &b), "iso is terrain");
	/* the world's blocks: the draw's own parameters change no block */
	params_defaults(&b);
	b.ambient = 0.7f;
	b.fog = 0.9f;
	b.snow_line = -3.0f;
	b.water_level = 4.0f;
	CHECK(params_same_blocks(&a, &b) && !params_same_terrain(&a, &b), "light, fog, snow, water: the same blocks");
	b.noise_amp = 7.0f;
	CHECK(!params_same_blocks(&a, &b), "noise_amp: other blocks");
	params_defaults(&b);
	b.light_az = a.light_az + 30.0f; /* baked into the vertices' shadows */
	CHECK(!params_same_blocks(&a, &b), "the sun's direction: other blocks");
	params_defaults(&b);
	b.ao_rays = 2;
	CHECK(!params_same_blocks(&a, &b), "AO rays: other blocks");
}

static void test_presets_config(void)
{
	struct params p;
	char err[512];
	params_defaults(&p);
	CHECK(params_apply_preset(&p, "alpine", err, sizeof(err)) == 0, "alpine: %s", err);
	{
		/* the preset's settings string, applied by hand, gives the same values */
		struct params q;
		params_defaults(&q);
		CHECK(p.fractal == 3, "alpine is ridged (%d)", p.fractal);
		const char *set = NULL;
		for (size_t i = 0; i < preset_count; i++)
			if (!strcmp(presets[i].name, "alpine"))
				set = presets[i].settings;
		char buf[512];
		snprintf(buf, sizeof(buf), "%s", set ? set : "");
		for (char *save = NULL, *kv = strtok_r(buf, ";", &save); kv; kv = strtok_r(NULL, ";", &save)) {
			char *eq = strchr(kv, '=');
			if (eq) {
				*eq = 0;
				CHECK(params_set(&q, kv, eq + 1, err, sizeof(err)) == 0, "alpine %s: %s", kv, err);
			}
		}
		CHECK(params_same_terrain(&p, &q) && p.octaves == q.octaves, "alpine values");
	}
	for (size_t i = 0; i < preset_count; i++) {
		params_defaults(&p);
		CHECK(params_apply_preset(&p, presets[i].name, err, sizeof(err)) == 0, "preset %s: %s",
		      presets[i].name, err);
	}
	CHECK(params_apply_preset(&p, "nope", err, sizeof(err)) == -1 &&
	      !strncmp(err, "unknown preset 'nope' (one of: default alpine", 45), "err '%s'", err);

	params_defaults(&p);
	const char *ok = "# comment\n\n  grid = 64  # trailing\niso=0.5\nout = \"my file.png\"\npreset = caves\nverbose = on\n";
	CHECK(params_load_config_text(&p, ok, "a.conf", err, sizeof(err)) == 0, "config: %s", err);
	CHECK(p.grid == 64 && p.iso == 0.5f && !strcmp(p.out, "my file.png") && p.shape == 2 && p.verbose,
	      "config values");
	CHECK(params_load_config_text(&p, "grid = 64\n\ngrid = 999\n", "b.conf", err, sizeof(err)) == -1 &&
	      !strcmp(err, "b.conf:3: grid: 999 is out of range [2, 512]"), "err '%s'", err);
	CHECK(params_load_config_text(&p, "iso 3\n", "c.conf", err, sizeof(err)) == -1 &&
	      !strcmp(err, "c.conf:1: expected 'name = value', got 'iso 3'"), "err '%s'", err);
	CHECK(params_load_config_text(&p, "x\n\nbogus = 1", "d.conf", err, sizeof(err)) == -1 &&
	      !strcmp(err, "d.conf:1: expected 'name = value', got 'x'"), "err '%s'", err);
	CHECK(params_load_config_text(&p, "\nbogus = 1", "d.conf", err, sizeof(err)) == -1 &&
	      !strcmp(err, "d.conf:2: unknown parameter 'bogus' (see --help)"), "err '%s'", err);

	char path[256];
	snprintf(path, sizeof(path), "%s/t.conf", tmpdir);
	write_file(path, "grid = 48\nfractal = fbm\n");
	params_defaults(&p);
	CHECK(params_load_config_file(&p, path, err, sizeof(err)) == 0 && p.grid == 48 && p.fractal == 1,
	      "config file: %s", err);
	char missing[300], want[400];
	snprintf(missing, sizeof(missing), "%s/missing.conf", tmpdir);
	snprintf(want, sizeof(want), "cannot open config file '%s': No such file or directory", missing);
	CHECK(params_load_config_file(&p, missing, err, sizeof(err)) == -1 && !strcmp(err, want), "err '%s'", err);
}

static void test_cli(void)
{
	struct params p;
	char err[512];
	char conf[256], bad_conf[256], msg[512];
	snprintf(conf, sizeof(conf), "%s/cli.conf", tmpdir);
	snprintf(bad_conf, sizeof(bad_conf), "%s/bad.conf", tmpdir);
	write_file(conf, "grid = 32\nnoise_amp = 7\noctaves = 5\n");
	write_file(bad_conf, "grid = 32\ngrid = 1\n");

	CHECK(PARSE(&p, err, "--grid", "7") == CLI_RUN && p.grid == 7, "--grid 7: %s", err);
	CHECK(PARSE(&p, err, "--grid=9", "--count", "3") == CLI_RUN && p.grid == 9 && p.count == 3, "%s", err);
	CHECK(PARSE(&p, err, "--max-triangles", "5", "--max_vertices=6") == CLI_RUN &&
	      p.max_triangles == 5 && p.max_vertices == 6, "%s", err);
	CHECK(PARSE(&p, err, "--vol-y", "-5") == CLI_RUN && p.vol_y == -5.0f, "negative value: %s", err);
	CHECK(PARSE(&p, err, "--verbose") == CLI_RUN && p.verbose, "--verbose: %s", err);
	CHECK(PARSE(&p, err, "--verbose", "--no-verbose") == CLI_RUN && !p.verbose, "--no-verbose: %s", err);
	CHECK(PARSE(&p, err, "--verbose", "false", "--grid", "8") == CLI_RUN && !p.verbose && p.grid == 8, "%s", err);
	CHECK(PARSE(&p, err, "--flat-spot=on") == CLI_RUN && p.flat_spot, "%s", err);
	CHECK(PARSE(&p, err, "--set", "iso=0.5", "--set=seed=7") == CLI_RUN && p.iso == 0.5f && p.seed == 7, "%s", err);
	CHECK(PARSE(&p, err, "--fractal", "worley", "--size", "640x480", "--out", "x.PNG", "--export-mesh", "m.ply") ==
	      CLI_RUN && p.fractal == 6 && !strcmp(p.size, "640x480") && !strcmp(p.export_mesh, "m.ply"), "%s", err);
	/* preset first, then config, then explicit options, whatever the order */
	CHECK(PARSE(&p, err, "--octaves", "3", "--config", conf, "--preset", "alpine") == CLI_RUN, "%s", err);
	CHECK(p.octaves == 3 && p.grid == 32 && p.noise_amp == 7.0f && p.fractal == 3, "order: oct %d grid %d amp %g frac %d",
	      p.octaves, p.grid, (double)p.noise_amp, p.fractal);
	CHECK(PARSE(&p, err, "--preset=caves") == CLI_RUN && p.shape == 2, "%s", err);
	/* defaults are restored for every parse */
	CHECK(PARSE(&p, err, "--count", "2") == CLI_RUN && p.grid == 128 && p.shape == 0, "defaults");

	PARSE_FAILS("unknown option '--foo' (see --help)", "--foo");
	PARSE_FAILS("unknown option '--foo' (see --help)", "--foo=1");
	PARSE_FAILS("unknown option '-x' (see --help)", "-x");
	PARSE_FAILS("unknown option '--no-grid' (see --help)", "--no-grid");
	PARSE_FAILS("option '--grid' needs a value", "--grid");
	PARSE_FAILS("option '--grid' needs a value", "--grid", "--count", "2");
	PARSE_FAILS("option '--out' needs a value", "--grid", "4", "--out");
	PARSE_FAILS("option '--no-verbose' takes no value", "--no-verbose=1");
	PARSE_FAILS("option '--help' takes no value", "--help=1");
	PARSE_FAILS("unexpected argument 'foo' (options only, see --help)", "foo");
	PARSE_FAILS("unexpected argument 'foo' (options only, see --help)", "--grid", "4", "foo");
	PARSE_FAILS("unexpected argument '--' (options only, see --help)", "--");
	PARSE_FAILS("grid: 1 is out of range [2, 512]", "--grid", "1");
	PARSE_FAILS("grid: 'x' is not an integer", "--grid=x");
	PARSE_FAILS("fractal: 'x' is not one of geiss|fbm|turbulence|ridged|multifractal|hetero|worley|hybrid|slope_damped|abs_multifractal", "--fractal", "x");
	PARSE_FAILS("size: '10x10' is not WxH with W and H in 16..16384", "--size", "10x10");
	PARSE_FAILS("size: '640' is not WxH with W and H in 16..16384", "--size", "640");
	PARSE_FAILS("size: '640x480x2' is not WxH with W and H in 16..16384", "--size", "640x480x2");
	PARSE_FAILS("size: '20000x480' is not WxH with W and H in 16..16384", "--size=20000x480");
	PARSE_FAILS("out: 'x.jpg' must end in .png or .y4m (or be - for a Y4M stream on stdout)", "--out", "x.jpg");
	PARSE_FAILS("out: '.png' must end in .png or .y4m (or be - for a Y4M stream on stdout)", "--out", ".png");
	PARSE_FAILS("export_mesh: 'm.obj' must end in .ply", "--export-mesh", "m.obj");
	PARSE_FAILS("option '--set' needs NAME=VALUE, got 'iso'", "--set", "iso");
	PARSE_FAILS("unknown parameter 'bogus' (see --help)", "--set", "bogus=1");
	snprintf(msg, sizeof(msg), "%s:2: grid: 1 is out of range [2, 512]", bad_conf);
	PARSE_FAILS(msg, "--config", bad_conf);
	CHECK(PARSE(&p, err, "--preset", "nope") == CLI_ERROR && !strncmp(err, "unknown preset 'nope'", 21), "%s", err);

	int w = 0, h = 0;
	CHECK(cli_parse_size("1280x720", &w, &h) == 0 && w == 1280 && h == 720, "size");
	CHECK(cli_parse_size("16x16384", &w, &h) == 0 && w == 16 && h == 16384, "size limits");
	const char *bad[] = { "", "x", "15x16", "16x16385", "+16x16", "16x-16", " 16x16", "16x16 ", "16X16", "0016x16x" };
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
		CHECK(cli_parse_size(bad[i], &w, &h) == -1, "size '%s' accepted", bad[i]);

	/* a width no file name can hold is refused, not padded out (found by
	 * tests/fuzz/fuzz_cli: printf spent seconds writing 620 M zeros) */
	char name[64];
	CHECK(cli_numbered_name("f%04d.png", 7, name, sizeof(name)) == 1 && !strcmp(name, "f0007.png"), "%s", name);
	CHECK(cli_numbered_name("f%0620531529d.png", 0, name, sizeof(name)) == -1, "huge %%d width refused");
	CHECK(cli_numbered_name("f%64d.png", 0, name, sizeof(name)) == -2, "a name wider than the buffer is refused, never cut");
	CHECK(PARSE(&p, err, "--out=f%0620531529d.png") == CLI_ERROR && strstr(err, "--out"), "--out: %s", err);

	CHECK(quiet_parse("--help") == CLI_EXIT_OK, "--help");
	CHECK(quiet_parse("-h") == CLI_EXIT_OK, "-h");
	CHECK(quiet_parse("--version") == CLI_EXIT_OK, "--version");
	CHECK(quiet_parse("--list-presets") == CLI_EXIT_OK, "--list-presets");
}

/* The draw's own parameters (params_same_blocks) are read by no pass that
 * makes a block: their uniforms appear only in the draw's shaders (the
 * terrain's, the sky's and the water's fragment and vertex shaders, and
 * shade.glsl, which only those and its own test include).  Checked against
 * the sources (ISOTERRA_SRC). */
static char *slurp(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	char *buf = NULL;
	size_t n = 0, cap = 0, got;
	char chunk[4096];
	while ((got = fread(chunk, 1, sizeof(chunk), f)) > 0) {
		if (n + got + 1 > cap) {
			cap = (n + got + 1) * 2;
			char *nb = realloc(buf, cap);
			if (!nb) {
				free(buf);
				fclose(f);
				return NULL;
			}
			buf = nb;
		}
		memcpy(buf + n, chunk, got);
		n += got;
	}
	fclose(f);
	if (buf)
		buf[n] = 0;
	return buf;
}

static bool word_in(const char *text, const char *word)
{
	size_t n = strlen(word);
	for (const char *q = strstr(text, word); q; q = strstr(q + 1, word)) {
		char before = q == text ? ' ' : q[-1], after = q[n];
		bool id_b = before == '_' || (before >= 'a' && before <= 'z') || (before >= 'A' && before <= 'Z') ||
			    (before >= '0' && before <= '9');
		bool id_a = after == '_' || (after >= 'a' && after <= 'z') || (after >= 'A' && after <= 'Z') ||
			    (after >= '0' && after <= '9');
		if (!id_b && !id_a)
			return true;
	}
	return false;
}

static void test_draw_only_sources(void)
{
	const char *src = getenv("ISOTERRA_SRC");
	if (!src) {
		printf("SKIP draw-only parameters against the shaders: ISOTERRA_SRC is not set (meson test sets it)\n");
		return;
	}
	static const char *const draw_files[] = { "render.frag", "render.vert", "shade.glsl", "sky.frag", "sky.vert",
						  "water.frag", "water.vert" };
	char dir[1024];
	snprintf(dir, sizeof(dir), "%s/shaders", src);
	DIR *d = opendir(dir);
	CHECK(d != NULL, "%s: cannot open", dir);
	if (!d)
		return;
	/* the parameters whose change params_same_blocks lets pass: the
	 * P_DRAW ones, and they alone */
	const struct param_info *draw_params[64];
	int ndraw = 0, files = 0;
	struct params a;
	params_defaults(&a);
	for (size_t i = 0; i < param_count; i++) {
		const struct param_info *pi = &param_table[i];
		if (!(pi->flags & P_SHADER) || pi->type == PT_STRING)
			continue;
		struct params b = a;
		double v = params_get_number(&a, pi);
		params_set_number(&b, pi, v + 1.0); /* within its range: up, else down */
		if (params_get_number(&b, pi) == v)
			params_set_number(&b, pi, v - 1.0);
		if (params_get_number(&b, pi) == v)
			params_set_number(&b, pi, v * 0.5);
		CHECK(params_get_number(&b, pi) != v, "%s: cannot be changed for the check", pi->name);
		bool same = params_same_blocks(&a, &b);
		CHECK(same == ((pi->flags & P_DRAW) != 0), "%s: params_same_blocks %d, P_DRAW %d", pi->name, same,
		      (pi->flags & P_DRAW) != 0);
		if (same && ndraw < 64)
			draw_params[ndraw++] = pi;
	}
	CHECK(ndraw >= 10, "only %d draw-only parameters", ndraw);
	for (struct dirent *e; (e = readdir(d));) {
		size_t n = strlen(e->d_name);
		if (n < 6 || (strcmp(e->d_name + n - 5, ".comp") && strcmp(e->d_name + n - 5, ".glsl") &&
			      strcmp(e->d_name + n - 5, ".frag") && strcmp(e->d_name + n - 5, ".vert")))
			continue;
		bool draw = false;
		for (size_t k = 0; k < sizeof(draw_files) / sizeof(draw_files[0]); k++)
			draw = draw || !strcmp(e->d_name, draw_files[k]);
		char path[1300];
		snprintf(path, sizeof(path), "%s/%s", dir, e->d_name);
		char *text = slurp(path);
		CHECK(text != NULL, "%s: cannot read", path);
		if (!text)
			continue;
		files++;
		/* shade.glsl: the draw's and its own test's only */
		if (strstr(text, "#include \"shade.glsl\""))
			CHECK(draw || !strcmp(e->d_name, "shade_test.comp"), "%s includes shade.glsl (the draw's)", e->d_name);
		for (int k = 0; k < ndraw && !draw && strcmp(e->d_name, "shade_test.comp"); k++) {
			char u[80];
			snprintf(u, sizeof(u), "u_%s", draw_params[k]->name);
			CHECK(!word_in(text, u), "%s reads %s, which params_same_blocks counts as the draw's own", e->d_name, u);
		}
		free(text);
	}
	closedir(d);
	CHECK(files > 20, "only %d shader files in %s", files, dir);
}

int main(void)
{
	if (!mkdtemp(tmpdir)) {
		perror("mkdtemp");
		return 1;
	}
	test_defaults();
	test_set();
	test_round_trip();
	test_glsl();
	test_draw_only_sources();
	test_presets_config();
	test_cli();
	char cmd[300];
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		fprintf(stderr, "cannot remove %s\n", tmpdir);
	return tc_done("test_params");
}
