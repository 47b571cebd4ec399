/* isoterra — between the shader loader (shader.c) and the live-editing
 * watcher (shader_watch.c): what a program is built from, and the note the
 * loader sends for every program it builds; the compiler's log read into
 * file:line reports (shader_log.c).  Private to app/gpu. */
#ifndef ISOTERRA_SHADER_INT_H
#define ISOTERRA_SHADER_INT_H

#include <stdbool.h>
#include <stddef.h>
#include <GLES3/gl31.h>

#define SHADER_MAX_DEPS 48

/* A program's sources: one .comp file, or a vertex and a fragment file,
 * and the caller's #defines (NULL: none; borrowed). */
struct shader_desc {
	bool compute;
	char file[2][64];
	const char *defines;
};

/* The files a program was made of (its own and every #include). */
struct shader_deps {
	char names[SHADER_MAX_DEPS][64];
	int n;
};

/* Compiles and links a new program from the files as they are now; deps
 * (or NULL) gets the files.  0 with a file:line message in err. */
GLuint shader_build(const struct shader_desc *d, struct shader_deps *deps, char *err, size_t errlen);
/* The loader built prog from d: the open watcher (if any) records it. */
void shader_watch_note(GLuint prog, const struct shader_desc *d, const struct shader_deps *deps);

/* ---- the compiler's log (shader_log.c: pure C, no GL) ----------------
 * Every vendor writes its own prefix before a message; each names the
 * source-string number (set by the loader's "#line N id": the index of the
 * program's file table) and the line:
 *   Mesa              0:58(12): error: ...             string 0, line 58, column 12
 *   NVIDIA            0(58) : error C0000: ...         string 0, line 58
 *   Adreno, PowerVR,  ERROR: 0:58: 'x' : ...           (also WARNING:, AMD's
 *   AMD (3Dlabs)                                        "ERROR: 0:58: error(#132) ...")
 *   Mali              0:58: L0001: ...                  (S/L/P codes; "0:58: Warning: ...")
 * The loader numbers each file's lines from its number times
 * SHADER_LINE_BASE ("#line 90001 9" opens file 9), so that the line alone
 * names the file too: Mesa (22.3) reports string 0 for every error found
 * after parsing ("0:90149(2): error: `x' undeclared"); only its lexer's and
 * parser's errors carry the #line's string.  A line under SHADER_LINE_BASE
 * is the prelude's (string 0) or one from a log of another numbering.
 * One line of a log, read: */
#define SHADER_LINE_BASE 10000
enum shader_log_kind { SHADER_LOG_OTHER, SHADER_LOG_WARNING, SHADER_LOG_ERROR };
struct shader_log_line {
	int source;  /* source-string number, -1 when the line names none */
	int line;    /* line number, -1 when none */
	int column;  /* column (Mesa), -1 when none */
	enum shader_log_kind kind;
	const char *msg; /* the message after the prefix (inside the log), */
	int msg_len;     /* without the line's trailing blanks, CR or NUL */
	const char *text; /* the whole line, trimmed the same way */
	int text_len;
};
/* Reads the line of len bytes at text (a '\n' or NUL ends it earlier);
 * true when it names both a source string and a line. */
bool shader_log_parse_line(const char *text, size_t len, struct shader_log_line *out);
/* The line of a whole log (len bytes, or up to a NUL) worth reporting: the
 * first error with a place, else the first error, else the first line with
 * a place that is no warning, else the first warning with a place (a driver
 * that fails with warnings only), else the first line with text.  false
 * for a log without text. */
bool shader_log_pick(const char *log, size_t len, struct shader_log_line *out);
/* The log's report "file:line: message" (files[source], nfiles of them;
 * a line of SHADER_LINE_BASE or more names its file itself),
 * "error: " / "warning: " added where the message does not say which;
 * "fallback: message" where the line names no file of the table. */
void shader_log_format(const char *log, size_t len, const char *const *files, int nfiles, const char *fallback,
		       char *out, size_t outlen);

#endif
