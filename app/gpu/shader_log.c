/* isoterra — the GLSL compiler's log, read for file:line reports whatever
 * the vendor's format (the formats, with the real logs they were checked
 * against, in shader_int.h and tests/test_shader_log.c).  Pure C: no GL. */
#include "shader_int.h"

#include <stdio.h>
#include <string.h>

static bool is_digit(char c)
{
	return c >= '0' && c <= '9';
}

static bool is_alpha(char c)
{
	return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
}

static char lower(char c)
{
	return c >= 'A' && c <= 'Z' ? (char)(c - 'A' + 'a') : c;
}

static size_t skip_blanks(const char *s, size_t i, size_t n)
{
	while (i < n && (s[i] == ' ' || s[i] == '\t'))
		i++;
	return i;
}

/* A decimal number at s[*i] (clamped, not wrapped). */
static bool read_int(const char *s, size_t *i, size_t n, int *out)
{
	size_t j = *i;
	long v = 0;
	if (j >= n || !is_digit(s[j]))
		return false;
	for (; j < n && is_digit(s[j]); j++)
		if (v < 100000000)
			v = v * 10 + (s[j] - '0');
	*out = (int)v;
	*i = j;
	return true;
}

/* s (n bytes) starts with the word w, any case, not followed by a letter:
 * "error:", "error C0000", "error(#132)", but not "errors". */
static bool starts_word(const char *s, size_t n, const char *w)
{
	size_t k = strlen(w);
	if (n < k)
		return false;
	for (size_t i = 0; i < k; i++)
		if (lower(s[i]) != w[i])
			return false;
	return n == k || !is_alpha(s[k]);
}

/* Mali's codes: a letter and four digits and ':' (S0001, L0002, P0005). */
static bool mali_code(const char *s, size_t n)
{
	return n >= 6 && s[0] >= 'A' && s[0] <= 'Z' && is_digit(s[1]) && is_digit(s[2]) && is_digit(s[3]) &&
	       is_digit(s[4]) && s[5] == ':';
}

/* The place after a severity prefix, at s[*i]: "S:L", "S:L(C)" or "S(L)",
 * or NVIDIA's "(L)" without a string, then blanks and the ':' that ends
 * every vendor's prefix.  *i moves past it only when there is one. */
static bool read_place(const char *s, size_t *i, size_t n, struct shader_log_line *out)
{
	size_t j = *i;
	int a = -1, b = -1, c = -1;
	if (read_int(s, &j, n, &a)) {
		if (j < n && s[j] == ':') {
			j++;
			if (!read_int(s, &j, n, &b))
				return false;
			if (j < n && s[j] == '(') {
				size_t k = j + 1;
				if (read_int(s, &k, n, &c) && k < n && s[k] == ')')
					j = k + 1;
				else
					c = -1;
			}
		} else if (j < n && s[j] == '(') {
			j++;
			if (!read_int(s, &j, n, &b) || j >= n || s[j] != ')')
				return false;
			j++;
		} else {
			return false;
		}
	} else if (j < n && s[j] == '(') {
		j++;
		if (!read_int(s, &j, n, &b) || j >= n || s[j] != ')')
			return false;
		j++;
		a = -1;
	} else {
		return false;
	}
	j = skip_blanks(s, j, n);
	if (j >= n || s[j] != ':')
		return false;
	out->source = a;
	out->line = b;
	out->column = c;
	*i = j + 1;
	return true;
}

bool shader_log_parse_line(const char *text, size_t len, struct shader_log_line *out)
{
	size_t n = 0;
	while (n < len && text[n] && text[n] != '\n')
		n++;
	while (n > 0 && (text[n - 1] == '\r' || text[n - 1] == ' ' || text[n - 1] == '\t'))
		n--;
	memset(out, 0, sizeof(*out));
	out->source = out->line = out->column = -1;
	out->kind = SHADER_LOG_OTHER;
	size_t i = skip_blanks(text, 0, n);
	out->text = text + i;
	out->text_len = (int)(n - i);
	/* the 3Dlabs front end's severity prefix (Adreno, PowerVR, AMD) */
	if (starts_word(text + i, n - i, "error") && i + 5 < n && text[i + 5] == ':') {
		out->kind = SHADER_LOG_ERROR;
		i += 6;
	} else if (starts_word(text + i, n - i, "warning") && i + 7 < n && text[i + 7] == ':') {
		out->kind = SHADER_LOG_WARNING;
		i += 8;
	}
	i = skip_blanks(text, i, n);
	bool placed = read_place(text, &i, n, out);
	i = skip_blanks(text, i, n);
	out->msg = text + i;
	out->msg_len = (int)(n - i);
	/* a severity after the place (Mesa, NVIDIA, AMD's "error(#132)", Mali's
	 * "Warning:" and error codes) */
	if (out->kind == SHADER_LOG_OTHER) {
		if (starts_word(out->msg, n - i, "error"))
			out->kind = SHADER_LOG_ERROR;
		else if (starts_word(out->msg, n - i, "warning"))
			out->kind = SHADER_LOG_WARNING;
		else if (placed && mali_code(out->msg, n - i))
			out->kind = SHADER_LOG_ERROR;
	}
	return placed && out->source >= 0 && out->line >= 0;
}

/* How much a line is worth reporting (see shader_log_pick). */
static int line_rank(const struct shader_log_line *l, bool placed)
{
	if (l->kind == SHADER_LOG_ERROR)
		return placed ? 5 : 4;
	if (placed)
		return l->kind == SHADER_LOG_WARNING ? 2 : 3;
	return l->text_len > 0 ? 1 : 0;
}

bool shader_log_pick(const char *log, size_t len, struct shader_log_line *out)
{
	int best = 0;
	size_t i = 0;
	while (i < len && log[i]) {
		struct shader_log_line l;
		bool placed = shader_log_parse_line(log + i, len - i, &l);
		int rank = line_rank(&l, placed);
		if (rank > best) {
			best = rank;
			*out = l;
			if (rank == 5)
				break;
		}
		while (i < len && log[i] && log[i] != '\n')
			i++;
		if (i < len && log[i] == '\n')
			i++;
	}
	return best > 0;
}

void shader_log_format(const char *log, size_t len, const char *const *files, int nfiles, const char *fallback,
		       char *out, size_t outlen)
{
	struct shader_log_line l;
	if (!log || !shader_log_pick(log, len, &l)) {
		snprintf(out, outlen, "%s: compile failed (the driver's log is empty)", fallback);
		return;
	}
	const char *sev = "";
	if (l.kind == SHADER_LOG_ERROR && !starts_word(l.msg, (size_t)l.msg_len, "error"))
		sev = "error: ";
	else if (l.kind == SHADER_LOG_WARNING && !starts_word(l.msg, (size_t)l.msg_len, "warning"))
		sev = "warning: ";
	int src = l.source, line = l.line;
	if (line >= SHADER_LINE_BASE) { /* the loader's numbering: the line names the file */
		src = line / SHADER_LINE_BASE;
		line %= SHADER_LINE_BASE;
	}
	if (src >= 0 && src < nfiles && line >= 0 && files[src])
		snprintf(out, outlen, "%s:%d: %s%.*s", files[src], line, sev, l.msg_len, l.msg);
	else if (src < 0)
		snprintf(out, outlen, "%s: %s%.*s", fallback, sev, l.msg_len, l.msg);
	else /* a string the program does not have: the driver's line as it is */
		snprintf(out, outlen, "%s: %.*s", fallback, l.text_len, l.text);
}
