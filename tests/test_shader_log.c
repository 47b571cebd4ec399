/* isoterra — the GLSL compiler's log read as file:line (app/gpu/shader_log.c)
 * for every vendor, from real logs: each sample names where it came from,
 * and the file and line it must map to are written down independently (for
 * this project's own logs: the line the test that broke the shader edited;
 * for the others: the place the log names, read by eye).  No GL. */
#include "shader_int.h"
#include "tcheck.h"

#include <stdio.h>
#include <string.h>

/* the file tables (source-string number -> file) of the programs the
 * samples came from: the loader's order (app/gpu/shader.c expand()) */
static const char *const density_files[] = {
	"<prelude>", "density.comp", "common.glsl", "block_bound.glsl", "mc_vertices.comp", "hp.glsl",
	"mc_status.glsl", "ao.glsl", "vertex.glsl", "density.glsl", "noise.glsl", "fractal.glsl",
};
static const char *const render_files[] = { "<prelude>", "render.frag", "shade.glsl" };
/* a program of one file, as in the logs of other projects (string 0) */
static const char *const one_file[] = { "app.frag" };
/* AMD's sample names string 2 */
static const char *const three_files[] = { "<prelude>", "osd_common.glsl", "osd_patch.glsl" };

#define FILES(t) t, (int)(sizeof(t) / sizeof(t[0]))

struct sample {
	const char *vendor;
	const char *where; /* the log's source */
	const char *log;
	size_t len; /* 0: strlen(log) */
	const char *const *files;
	int nfiles;
	const char *want; /* the report's start: "file:line: " and its severity */
	const char *msg;  /* a piece of the message it keeps */
};

static const struct sample samples[] = {
	/* ---- NVIDIA: "S(L) : error Cnnnn: ..." */
	{ "NVIDIA", "/work/shared/evidence/nvidia-h100-tests.log:387 (H100, driver 580.159.04): test_shader_watch "
		    "inserts \"this is not GLSL;\" above void main(), line 58 of shaders/render.frag",
	  "1(58) : error C0000: syntax error, unexpected reserved word \"this\" at token \"this\"\n", 0,
	  FILES(render_files), "render.frag:58: error C0000: ", "unexpected reserved word \"this\"" },
	{ "NVIDIA", "/work/shared/evidence/nvidia-h100-tests.log:402: tests/test_cli.sh inserts \"this is not glsl;\" "
		    "two lines below 'float density(vec3', line 149 of shaders/density.glsl",
	  "9(149) : error C0000: syntax error, unexpected reserved word \"this\" at token \"this\"\n", 0,
	  FILES(density_files), "density.glsl:149: error C0000: ", "at token \"this\"" },
	/* warnings before the error: the warning lines of
	 * https://github.com/emezeske/digbuild/issues/23 followed by the error
	 * lines of https://github.com/pioneerspacesim/pioneer/issues/2693 (two
	 * real NVIDIA logs, one after the other) */
	{ "NVIDIA", "github emezeske/digbuild#23 + pioneerspacesim/pioneer#2693",
	  "0(27) : warning C7555: 'varying' is deprecated, use 'in/out' instead\n"
	  "0(28) : warning C7555: 'varying' is deprecated, use 'in/out' instead\n"
	  "0(46) : warning C7533: global variable gl_MultiTexCoord0 is deprecated after version 120\n"
	  "0(98) : error C6013: Only arrays of texcoords may be indexed in this profile, and only with a loop index "
	  "variable\n"
	  "0(99) : error C6013: Only arrays of texcoords may be indexed in this profile, and only with a loop index "
	  "variable\n",
	  0, FILES(one_file), "app.frag:98: error C6013: ", "Only arrays of texcoords" },
	/* an error that names no string ("(0)") beats a warning that does:
	 * https://github.com/patriciogonzalezvivo/glslViewer/pull/51 (GeForce,
	 * the program's log) */
	{ "NVIDIA", "github patriciogonzalezvivo/glslViewer#51",
	  "Vertex info\n-----------\n(0) : error C0000: syntax error, unexpected $end, expecting \"::\" at token "
	  "\"<EOF>\"\n(0) : error C2003: incompatible options for link\n\nFragment info\n-------------\n0(72) : warning "
	  "C7011: implicit cast from \"int\" to \"float\"\n",
	  0, FILES(one_file), "main.frag: error C0000: ", "unexpected $end" },

	/* ---- Mesa: "S:L(C): error: ..." */
	/* made here (llvmpipe, Mesa 22.3.6): tests/test_cli.sh's edit, line
	 * 149 of density.glsl, with the loader's numbering (file 9 from 90001) */
	{ "Mesa", "llvmpipe / Mesa 22.3.6, this machine: test_cli.sh's broken density.glsl (line 149)",
	  "9:90149(2): error: illegal use of reserved word `this'\n9:90149(2): error: syntax error, unexpected "
	  "ERROR_TOK\n",
	  0, FILES(density_files), "density.glsl:149: error: ", "reserved word `this'" },
	/* the same edit before the numbering (string 9, line 149): the log the
	 * old reader handled */
	{ "Mesa", "llvmpipe / Mesa 22.3.6, this machine, lines numbered from 1 in each file",
	  "9:149(2): error: illegal use of reserved word `this'\n9:149(2): error: syntax error, unexpected ERROR_TOK\n",
	  0, FILES(density_files), "density.glsl:149: error: ", "reserved word `this'" },
	/* an error found after parsing: Mesa names string 0 (not the #line's
	 * 9); the line names the file.  "\tundeclared_b = 1.0;" inserted as line
	 * 149 of density.glsl */
	{ "Mesa", "llvmpipe / Mesa 22.3.6, this machine: an undeclared name at line 149 of density.glsl",
	  "0:90149(2): error: `undeclared_b' undeclared\n0:90149(2): error: value of type float cannot be assigned to "
	  "variable of type error\n",
	  0, FILES(density_files), "density.glsl:149: error: ", "`undeclared_b' undeclared" },
	/* a warning before the error: render.frag with "float uninit_a;" (60),
	 * "float read_a = uninit_a + 1.0;" (61), "undeclared_b = read_a;" (62) */
	{ "Mesa", "llvmpipe / Mesa 22.3.6, this machine: render.frag, a warning at 61, the error at 62",
	  "0:10061(17): warning: `uninit_a' used uninitialized\n0:10062(2): error: `undeclared_b' undeclared\n"
	  "0:10062(2): error: value of type float cannot be assigned to variable of type error\n",
	  0, FILES(render_files), "render.frag:62: error: ", "`undeclared_b' undeclared" },
	/* warnings first, from https://github.com/XProger/OpenLara/issues/171 */
	{ "Mesa", "github XProger/OpenLara#171",
	  "0:1(12): warning: extension `GL_OES_standard_derivatives' unsupported in fragment shader\n"
	  "0:2(12): warning: extension `GL_EXT_shadow_samplers' unsupported in fragment shader\n"
	  "0:4(1): error: syntax error, unexpected NEW_IDENTIFIER\n",
	  0, FILES(one_file), "app.frag:4: error: ", "unexpected NEW_IDENTIFIER" },

	/* ---- Mali: "S:L: Xnnnn: ..." (ARM's ESSL compiler writes
	 * "%d:%d: %s: ", the code S/L/P + 4 digits for errors, "Warning" for
	 * warnings: its common/error_reporting.c) */
	{ "Mali", "github vrld/moonshine#39 (Mali-450 MP4)",
	  "0:11: L0001: Excpected token 'i', found 'identifier'\n0:12: L0002: Undeclared variable 'v'\n", 0,
	  FILES(one_file), "app.frag:11: error: L0001: ", "Excpected token 'i'" },
	{ "Mali", "github Open4Es/Open4Es-Shader-Android#161",
	  "0:142: L0001: Expected token ';' \n0:178: L0001: Expected token ';' \n0:189: L0001: Expected token ';' \n"
	  "0:190: L0002: Undeclared variable 'scatterCoeff'\n",
	  0, FILES(one_file), "app.frag:142: error: L0001: ", "Expected token ';'" },
	/* a warning first: made in that format (no public Mali log with a
	 * warning before an error was found); the error line is moonshine's */
	{ "Mali", "made in the format of ARM's ESSL compiler + github vrld/moonshine#39",
	  "0:7: Warning: a warning in ARM's format\n0:11: L0001: Excpected token 'i', found 'identifier'\n", 0,
	  FILES(one_file), "app.frag:11: error: L0001: ", "Excpected token" },

	/* ---- Adreno: "ERROR: S:L: 'x' : ..." */
	{ "Adreno", "github gonetz/GLideN64#1075 (Adreno 420)",
	  "ERROR: 0:31: 'uniform' :  cannot initialize this type of qualifier  \nERROR: 1 compilation errors.  No code "
	  "generated.\n",
	  0, FILES(one_file), "app.frag:31: error: 'uniform' :  cannot initialize this type of qualifier", "qualifier" },
	/* a first line without a place, as Adreno 30x wrote it:
	 * https://github.com/google/filament/issues/1544 */
	{ "Adreno", "github google/filament#1544 (Adreno 30x)",
	  "Fragment shader compilation failed.\nERROR: 0:93: 'Error' : Cannot offset into the vector \nERROR: 0:93: "
	  "'Error' : Cannot offset into the vector \nERROR: 0:93: '=' :  cannot convert from '3-component vector of "
	  "float' to 'float'\nERROR: 0:96: 'Error' : Cannot offset into the vector \n",
	  0, FILES(one_file), "app.frag:93: error: 'Error' : Cannot offset into the vector", "Cannot offset" },
	/* GLideN64's log with Windows line endings */
	{ "Adreno", "github gonetz/GLideN64#1075, CR LF line ends",
	  "ERROR: 0:31: 'uniform' :  cannot initialize this type of qualifier  \r\nERROR: 1 compilation errors.  No "
	  "code generated.\r\n",
	  0, FILES(one_file), "app.frag:31: error: 'uniform' :  cannot initialize this type of qualifier", "qualifier" },

	/* ---- PowerVR (IMG): "Compile failed." then "WARNING:/ERROR: S:L: ..." */
	/* a failure with warnings only: the first warning's place is the clue */
	{ "PowerVR", "github google/filament#4837 (PowerVR GE8320)",
	  "Compile failed.\nWARNING: 0:4: Extension GL_GOOGLE_cpp_style_line_directive not supported\n1 compilation "
	  "warnings.\n\n",
	  0, FILES(one_file), "app.frag:4: warning: Extension GL_GOOGLE_cpp_style_line_directive", "not supported" },
	{ "PowerVR", "github manuelbua/libgdx-contribs#10 (PowerVR SGX 540)",
	  "Compile failed.\nWARNING: 0:86: Calls to any function that may require a gradient calculation inside a "
	  "conditional block may return undefined results\nWARNING: 0:101: Calls to any function that may require a "
	  "gradient calculation inside a conditional block may return undefined results\n",
	  0, FILES(one_file), "app.frag:86: warning: Calls to any function", "gradient calculation" },
	/* SGX 540's warnings, then an error line in the front end's format the
	 * IMG and Adreno compilers share (made: no public PowerVR log with an
	 * ERROR line was found) */
	{ "PowerVR", "github manuelbua/libgdx-contribs#10 + an ERROR line made in that format",
	  "Compile failed.\nWARNING: 0:86: Calls to any function that may require a gradient calculation inside a "
	  "conditional block may return undefined results\nERROR: 0:120: 'vignette' : undeclared identifier\nERROR: 1 "
	  "compilation errors.  No code generated.\n",
	  0, FILES(one_file), "app.frag:120: error: 'vignette' : undeclared identifier", "undeclared" },

	/* ---- AMD: "ERROR: S:L: error(#n) ..." after a header that says "errors" */
	{ "AMD", "github dfranx/SHADERed#91",
	  "Vertex shader failed to compile with the following errors:\nERROR: 0:10: error(#132) Syntax error: "
	  "\"rawr\" parse error\nERROR: error(#273) 1 compilation errors.  No code generated\n",
	  0, FILES(one_file), "app.frag:10: error(#132) Syntax error: ", "parse error" },
	{ "AMD", "github PixarAnimationStudios/OpenSubdiv#189 (string 2)",
	  "Vertex shader failed to compile with the following errors:\n\nERROR: 2:218: error(#143) Undeclared "
	  "identifier: gl_PrimitiveID\n\nERROR: 2:218: error(#160) Cannot convert from: \"float\" to: \"highp int\"\n\n"
	  "ERROR: error(#273) 8 compilation errors.  No code generated",
	  0, FILES(three_files), "osd_patch.glsl:218: error(#143) Undeclared identifier", "gl_PrimitiveID" },

	/* ---- the buffer's end */
	/* GL_INFO_LOG_LENGTH counts the terminating NUL: a length past it */
	{ "Mesa", "this machine's log, its length counting the NUL",
	  "9:90149(2): error: illegal use of reserved word `this'\n", sizeof("9:90149(2): error: illegal use of reserved "
						     "word `this'\n"),
	  FILES(density_files), "density.glsl:149: error: ", "reserved word `this'" },
	/* a NUL ends the log, whatever the length says follows it */
	{ "Mesa", "this machine's log, then a NUL and stale bytes",
	  "0:90149(2): warning: a warning\n\0" "9:90149(2): error: after the NUL\n", 64, FILES(density_files),
	  "density.glsl:149: warning: a warning", "a warning" },
	/* a string the program does not have: the driver's line as it is */
	{ "NVIDIA", "a string number past the file table", "31(5) : error C0000: syntax error\n", 0,
	  FILES(render_files), "main.frag: 31(5) : error C0000: syntax error", "syntax error" },
};

static void check_sample(const struct sample *s)
{
	size_t len = s->len ? s->len : strlen(s->log);
	char out[512];
	shader_log_format(s->log, len, s->files, s->nfiles, "main.frag", out, sizeof(out));
	CHECK(!strncmp(out, s->want, strlen(s->want)), "%s (%s): '%s', want '%s...'", s->vendor, s->where, out,
	      s->want);
	CHECK(strstr(out, s->msg) != NULL, "%s (%s): '%s' lost '%s'", s->vendor, s->where, out, s->msg);
	CHECK(!strchr(out, '\n') && !strchr(out, '\r'), "%s (%s): one line: '%s'", s->vendor, s->where, out);
	size_t n = strlen(out);
	CHECK(n > 0 && out[n - 1] != ' ', "%s (%s): no trailing blank: '%s'", s->vendor, s->where, out);
}

/* One line read, field by field. */
static void check_line(const char *text, bool placed, int source, int line, int column, enum shader_log_kind kind,
		       const char *msg)
{
	struct shader_log_line l;
	bool got = shader_log_parse_line(text, strlen(text), &l);
	CHECK(got == placed, "'%s': placed %d, want %d", text, got, placed);
	CHECK(l.source == source && l.line == line && l.column == column,
	      "'%s': string %d line %d column %d, want %d %d %d", text, l.source, l.line, l.column, source, line, column);
	CHECK(l.kind == kind, "'%s': kind %d, want %d", text, (int)l.kind, (int)kind);
	CHECK(l.msg_len == (int)strlen(msg) && !strncmp(l.msg, msg, strlen(msg)), "'%s': message '%.*s', want '%s'",
	      text, l.msg_len, l.msg, msg);
}

int main(void)
{
	/* each vendor's place, read */
	check_line("0:58(12): error: `foo' undeclared", true, 0, 58, 12, SHADER_LOG_ERROR, "error: `foo' undeclared");
	check_line("3:10061(17): warning: `a' used uninitialized", true, 3, 10061, 17, SHADER_LOG_WARNING,
		   "warning: `a' used uninitialized");
	check_line("0(58) : error C0000: syntax error", true, 0, 58, -1, SHADER_LOG_ERROR, "error C0000: syntax error");
	check_line("0(72) : warning C7011: implicit cast", true, 0, 72, -1, SHADER_LOG_WARNING,
		   "warning C7011: implicit cast");
	check_line("(0) : error C0000: syntax error, unexpected $end", false, -1, 0, -1, SHADER_LOG_ERROR,
		   "error C0000: syntax error, unexpected $end");
	check_line("ERROR: 0:58: 'foo' : undeclared identifier ", true, 0, 58, -1, SHADER_LOG_ERROR,
		   "'foo' : undeclared identifier");
	check_line("WARNING: 0:4: Extension not supported\r", true, 0, 4, -1, SHADER_LOG_WARNING,
		   "Extension not supported");
	check_line("ERROR: 2:218: error(#143) Undeclared identifier: x", true, 2, 218, -1, SHADER_LOG_ERROR,
		   "error(#143) Undeclared identifier: x");
	check_line("0:58: L0001: Expected token ';'", true, 0, 58, -1, SHADER_LOG_ERROR, "L0001: Expected token ';'");
	check_line("1:3: Warning: a warning", true, 1, 3, -1, SHADER_LOG_WARNING, "Warning: a warning");
	/* no place: glslang's "0:?", summaries, headers */
	check_line("ERROR: 0:? : '' : syntax error", false, -1, -1, -1, SHADER_LOG_ERROR, "0:? : '' : syntax error");
	check_line("ERROR: 1 compilation errors.  No code generated.", false, -1, -1, -1, SHADER_LOG_ERROR,
		   "1 compilation errors.  No code generated.");
	check_line("Vertex shader failed to compile with the following errors:", false, -1, -1, -1, SHADER_LOG_OTHER,
		   "Vertex shader failed to compile with the following errors:");
	check_line("1 compilation warnings.", false, -1, -1, -1, SHADER_LOG_OTHER, "1 compilation warnings.");
	check_line("Compile failed.", false, -1, -1, -1, SHADER_LOG_OTHER, "Compile failed.");
	/* the line ends at '\n' */
	check_line("0:5(1): error: first\n0:9(1): error: second", true, 0, 5, 1, SHADER_LOG_ERROR, "error: first");

	for (size_t i = 0; i < sizeof(samples) / sizeof(samples[0]); i++)
		check_sample(&samples[i]);

	char out[256];
	/* a line with a place that says neither error nor warning (a vendor's
	 * own code) goes before a warning */
	const char *own = "0:4: Warning: w\n0:9: X: a vendor's own message\n";
	shader_log_format(own, strlen(own), FILES(render_files), "main.frag", out, sizeof(out));
	CHECK(!strncmp(out, "<prelude>:9: X: ", 16), "unknown code after a warning: '%s'", out);

	/* a log without text, or none at all */
	shader_log_format("", 0, FILES(one_file), "main.frag", out, sizeof(out));
	CHECK(!strncmp(out, "main.frag: ", 11), "empty log: '%s'", out);
	shader_log_format("\n\r\n  \n", 6, FILES(one_file), "main.frag", out, sizeof(out));
	CHECK(!strncmp(out, "main.frag: ", 11), "blank log: '%s'", out);
	shader_log_format(NULL, 0, FILES(one_file), "main.frag", out, sizeof(out));
	CHECK(!strncmp(out, "main.frag: ", 11), "no log: '%s'", out);
	/* the report fits what it is given */
	char small[16];
	shader_log_format(samples[0].log, strlen(samples[0].log), FILES(render_files), "main.frag", small, sizeof(small));
	CHECK(strlen(small) == sizeof(small) - 1 && !strncmp(small, "render.frag:58: ", 15), "truncated: '%s'", small);

	return tc_done("test_shader_log");
}
