/* isoterra build tool: the manual page, isoterra(1), from the parameter
 * table.
 * usage: isoterra-gen-man OUT.1 VERSION
 * Built for the build machine with app/params/params.c (the table of
 * params.def and the presets), so a cross build writes the same page.
 * Every option gets its type, range, default and help as --help shows them;
 * the presets get their settings.  The date is SOURCE_DATE_EPOCH's when it
 * is set (reproducible builds), else none. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gen_file.h"
#include "params.h"

/* Text for roff: backslashes, leading dots and quotes, minus signs. */
static void roff(FILE *f, const char *s)
{
	int bol = 1;
	for (; *s; s++) {
		if (bol && (*s == '.' || *s == '\''))
			fputs("\\&", f);
		bol = *s == '\n';
		if (*s == '\\')
			fputs("\\e", f);
		else if (*s == '-')
			fputs("\\-", f);
		else
			fputc(*s, f);
	}
}

/* "--" + the name with '_' as '-' (both written as roff minus signs) */
static void option_name(FILE *f, const char *prefix, const char *name)
{
	fputs("\\-\\-", f);
	fputs(prefix, f);
	for (const char *c = name; *c; c++) {
		if (*c == '_' || *c == '-')
			fputs("\\-", f);
		else
			fputc(*c, f);
	}
}

static void parameter(FILE *f, const struct param_info *pi)
{
	static const char *const meta[] = { "NUMBER", "N", "", "NAME", "TEXT" };
	char buf[256];
	fputs(".TP\n.B ", f);
	option_name(f, "", pi->name);
	if (pi->type == PT_BOOL) {
		fputs(", ", f); /* .B takes the rest of the line: one bold pair */
		option_name(f, "no\\-", pi->name);
		fputc('\n', f);
	} else {
		fprintf(f, " \\fI%s\\fR\n", meta[pi->type]);
	}
	roff(f, pi->help);
	fputs(".\n.br\n", f);
	switch (pi->type) {
	case PT_FLOAT: snprintf(buf, sizeof(buf), "Float in [%.10g, %.10g], default %.10g", pi->lo, pi->hi, pi->def); break;
	case PT_INT: snprintf(buf, sizeof(buf), "Integer in [%.10g, %.10g], default %.10g", pi->lo, pi->hi, pi->def); break;
	case PT_BOOL: snprintf(buf, sizeof(buf), "Boolean, default %s", pi->def ? "true" : "false"); break;
	case PT_ENUM: {
		char d[64];
		params_enum_name(pi, (int)pi->def, d, sizeof(d));
		snprintf(buf, sizeof(buf), "One of %s, default %s", pi->choices, d);
		break;
	}
	case PT_STRING:
		snprintf(buf, sizeof(buf), "Text, default %s%s%s", pi->def_str[0] ? "\"" : "",
			 pi->def_str[0] ? pi->def_str : "empty", pi->def_str[0] ? "\"" : "");
		break;
	}
	roff(f, buf);
	fputs(pi->flags & P_LIVE ? "; a knob can change it while running.\n" : ".\n", f);
}

static void section(FILE *f, const char *title, unsigned mask)
{
	fprintf(f, ".SS \"%s\"\n", title);
	for (size_t i = 0; i < param_count; i++)
		if (param_table[i].flags & mask)
			parameter(f, &param_table[i]);
}

static const char *const head =
	".SH NAME\n"
	"isoterra \\- procedural terrain on the GPU with OpenGL ES 3.1 compute shaders\n"
	".SH SYNOPSIS\n"
	".B isoterra\n"
	"[\\fIoptions\\fR]\n"
	".SH DESCRIPTION\n"
	".B isoterra\n"
	"generates procedural 3D terrain on the GPU: a density function (noise octaves,\n"
	"domain warp, hard floor, terraces, caves, planets), Marching Cubes compacted with\n"
	"HistoPyramids, and shading, all in OpenGL ES 3.1 compute and graphics shaders\n"
	"embedded in the binary.  It renders headless through EGL (a GPU's EGL device or\n"
	"Mesa's surfaceless platform) to PNG files or a Y4M stream, or live on a display:\n"
	"full screen through DRM/KMS with no window system (kiosks), or in a Wayland or X11\n"
	"window.\n"
	".PP\n"
	"Every parameter below is \\fB\\-\\-name\\fR \\fIVALUE\\fR or\n"
	"\\fB\\-\\-name\\fR=\\fIVALUE\\fR ('\\-' or '_' in names); booleans also\n"
	"\\fB\\-\\-name\\fR / \\fB\\-\\-no\\-name\\fR.  The same names are keys of the\n"
	"configuration file.  \\fB\\-\\-preset\\fR and \\fB\\-\\-config\\fR apply first, then\n"
	"the other options in order, so explicit options win.  Same seed and parameters\n"
	"give the same terrain.\n"
	".PP\n"
	"Bad input (an unknown option, a value out of range, a broken configuration line,\n"
	"a shader that fails to compile, no OpenGL ES 3.1, a GL limit too small for one of\n"
	"the passes) gives one line naming the problem and a non\\-zero exit status.\n"
	".SH OPTIONS\n"
	".SS \"General\"\n"
	".TP\n.B \\-\\-help\nShow the options with their ranges and defaults, and exit.\n"
	".TP\n.B \\-\\-version\nShow the version and exit.\n"
	".TP\n.B \\-\\-list\\-presets\nList the presets and exit.\n"
	".TP\n.B \\-\\-list\\-devices\nList the EGL devices (\\fB\\-\\-platform device\\fR): each one's index for\n"
	"\\fB\\-\\-device\\fR, its kind, DRM nodes, the GL renderer a context on it reports and its\n"
	"extensions; and exit.\n"
	".TP\n.BI \\-\\-preset \" NAME\"\nStart from a preset (see \\fBPRESETS\\fR).\n"
	".TP\n.BI \\-\\-config \" FILE\"\nRead \\fIname\\fR = \\fIvalue\\fR lines (\\fB#\\fR comments,\n"
	"\\fBpreset\\fR = \\fINAME\\fR) after the preset.\n"
	".TP\n.BI \\-\\-set \" NAME=VALUE\"\nSet any parameter.\n"
	".TP\n.BI \\-D \" CARD\"\nThe same as \\fB\\-\\-drm\\-device\\fR.\n";

static const char *const tail =
	".SH FILES\n"
	".TP\n.I /etc/isoterra/kiosk.conf\n"
	"Settings of the kiosk service (a \\fB\\-\\-config\\fR file).\n"
	".TP\n.I isoterra\\-kiosk.service\n"
	"A systemd unit that shows the terrain full screen on the first connected display\n"
	"(GBM/KMS); installed, not enabled.\n"
	".SH EXIT STATUS\n"
	"0 when the frames were rendered and written; 1 or 2, with one line on standard\n"
	"error, on bad input, when an output cannot be written (every destination is\n"
	"checked before any work) or when the GPU or a device cannot be used; 130 or 143\n"
	"when SIGINT or SIGTERM stopped a \\fB\\-\\-count\\fR \\fIN\\fR run before its\n"
	"last frame.  Files are written to temporary files beside them and renamed only\n"
	"when the run went well: a run that fails or is stopped leaves every earlier file\n"
	"as it was.  A closed pipe on standard output is an error (EPIPE), not SIGPIPE.\n"
	".SH EXAMPLES\n"
	".nf\n"
	"isoterra \\-\\-size 640x480 \\-\\-out terrain.png\n"
	"isoterra \\-\\-preset canyon \\-\\-grid 160 \\-\\-out canyon.png\n"
	"isoterra \\-\\-count 120 \\-\\-out 'frames/f%04d.png'\n"
	"isoterra \\-\\-scene world \\-\\-count 600 \\-\\-out \\- | ffmpeg \\-i \\- fly.mp4\n"
	"isoterra \\-\\-platform gbm \\-\\-count 0 \\-\\-config /etc/isoterra/kiosk.conf\n"
	".fi\n"
	".SH SEE ALSO\n"
	"The documentation in\n"
	".IR /usr/share/doc/isoterra/ :\n"
	"README, KIOSK (displays and the kiosk service), HARDWARE (knobs, V4L2 output),\n"
	"PLATFORMS (the GL limits each pass needs, by driver).\n";

int main(int argc, char **argv)
{
	if (argc != 3) {
		fprintf(stderr, "usage: %s OUT.1 VERSION\n", argv[0]);
		return 2;
	}
	char date[32] = "";
	const char *sde = getenv("SOURCE_DATE_EPOCH");
	if (sde && *sde) {
		time_t t = (time_t)strtoll(sde, NULL, 10);
		struct tm tm;
		if (gmtime_r(&t, &tm))
			strftime(date, sizeof(date), "%Y-%m-%d", &tm);
	}
	struct gen_file g;
	FILE *f = gen_begin(&g, argv[1]);
	if (!f)
		return 1;
	fprintf(f, ".\\\" generated from app/params/params.def by isoterra-gen-man: do not edit\n"
		   ".TH ISOTERRA 1 \"%s\" \"isoterra %s\" \"User Commands\"\n", date, argv[2]);
	fputs(head, f);
	section(f, "Application", P_APP);
	section(f, "Terrain (shader uniforms)", P_SHADER);
	fputs(".SH PRESETS\n", f);
	for (size_t i = 0; i < preset_count; i++) {
		fputs(".TP\n.B ", f);
		roff(f, presets[i].name);
		fputc('\n', f);
		roff(f, presets[i].help);
		fputs(".\n", f);
		if (presets[i].settings[0]) {
			fputs(".br\n", f);
			char buf[1024];
			snprintf(buf, sizeof(buf), "%s", presets[i].settings);
			for (char *c = buf; *c; c++)
				if (*c == ';')
					*c = ' ';
			roff(f, buf);
			fputc('\n', f);
		}
	}
	fputs(tail, f);
	if (ferror(f))
		return gen_abort(&g);
	return gen_commit(&g);
}
