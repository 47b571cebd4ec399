/* isoterra — a small strict JSON parser that keeps line numbers (see
 * curves_json.h). */
#include "curves_json.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 64

const char *const jtype_names[] = { "null", "a boolean", "a number", "a string", "an array", "an object" };

struct jparser {
	const char *s, *end;
	int line;
	const char *fname;
	char *err;
	size_t errlen;
	bool failed;
};

static void jfail(struct jparser *jp, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void jfail(struct jparser *jp, const char *fmt, ...)
{
	if (jp->failed)
		return;
	jp->failed = true;
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof(msg), fmt, ap);
	va_end(ap);
	snprintf(jp->err, jp->errlen, "%s:%d: invalid JSON: %s", jp->fname, jp->line, msg);
}

static void jskip(struct jparser *jp)
{
	while (jp->s < jp->end) {
		char c = *jp->s;
		if (c == '\n')
			jp->line++;
		else if (c != ' ' && c != '\t' && c != '\r')
			break;
		jp->s++;
	}
}

static void describe(const struct jparser *jp, char *buf, size_t len)
{
	if (jp->s >= jp->end)
		snprintf(buf, len, "end of file");
	else if (isprint((unsigned char)*jp->s))
		snprintf(buf, len, "'%c'", *jp->s);
	else
		snprintf(buf, len, "byte 0x%02x", (unsigned char)*jp->s);
}

static char *jstring(struct jparser *jp)
{
	/* at the opening quote */
	jp->s++;
	size_t cap = 32, n = 0;
	char *out = malloc(cap);
	if (!out) {
		jfail(jp, "out of memory");
		return NULL;
	}
	while (jp->s < jp->end && *jp->s != '"') {
		unsigned char c = (unsigned char)*jp->s++;
		if (c < 0x20) {
			jfail(jp, "control character in a string (unterminated string?)");
			free(out);
			return NULL;
		}
		if (c == '\\') {
			if (jp->s >= jp->end)
				break;
			char e = *jp->s++;
			switch (e) {
			case '"': c = '"'; break;
			case '\\': c = '\\'; break;
			case '/': c = '/'; break;
			case 'b': c = '\b'; break;
			case 'f': c = '\f'; break;
			case 'n': c = '\n'; break;
			case 'r': c = '\r'; break;
			case 't': c = '\t'; break;
			case 'u':
				for (int i = 0; i < 4; i++)
					if (jp->s + i >= jp->end || !isxdigit((unsigned char)jp->s[i])) {
						jfail(jp, "bad \\u escape in a string");
						free(out);
						return NULL;
					}
				jp->s += 4;
				c = '?'; /* names and kinds are ASCII; others are not used */
				break;
			default:
				jfail(jp, "bad escape '\\%c' in a string", isprint((unsigned char)e) ? e : '?');
				free(out);
				return NULL;
			}
		}
		if (n + 2 > cap) {
			cap *= 2;
			char *no = realloc(out, cap);
			if (!no) {
				free(out);
				jfail(jp, "out of memory");
				return NULL;
			}
			out = no;
		}
		out[n++] = (char)c;
	}
	if (jp->s >= jp->end) {
		jfail(jp, "unterminated string");
		free(out);
		return NULL;
	}
	jp->s++;
	out[n] = 0;
	return out;
}

void jfree(struct jval *v)
{
	if (v->type == J_STR)
		free(v->str);
	if (v->type == J_ARR || v->type == J_OBJ) {
		for (int i = 0; i < v->n; i++) {
			jfree(&v->items[i]);
			if (v->keys)
				free(v->keys[i]);
		}
		free(v->items);
		free(v->keys);
	}
	memset(v, 0, sizeof(*v));
}

static bool jvalue(struct jparser *jp, struct jval *v, int depth);

static bool jappend(struct jparser *jp, struct jval *v, int *cap, char *key)
{
	if (v->n + 1 > *cap) {
		int nc = *cap ? *cap * 2 : 4;
		struct jval *ni = realloc(v->items, sizeof(*ni) * (size_t)nc);
		if (!ni) {
			jfail(jp, "out of memory");
			return false;
		}
		v->items = ni;
		if (v->type == J_OBJ) {
			char **nk = realloc(v->keys, sizeof(*nk) * (size_t)nc);
			if (!nk) {
				jfail(jp, "out of memory");
				return false;
			}
			v->keys = nk;
		}
		*cap = nc;
	}
	memset(&v->items[v->n], 0, sizeof(struct jval));
	if (v->type == J_OBJ)
		v->keys[v->n] = key;
	v->n++;
	return true;
}

/* An object or an array, at its opening bracket. */
static bool jcontainer(struct jparser *jp, struct jval *v, int depth)
{
	char what[32];
	bool obj = *jp->s == '{';
	v->type = obj ? J_OBJ : J_ARR;
	jp->s++;
	int cap = 0;
	jskip(jp);
	if (jp->s < jp->end && *jp->s == (obj ? '}' : ']')) {
		jp->s++;
		return true;
	}
	for (;;) {
		char *key = NULL;
		jskip(jp);
		if (obj) {
			if (jp->s >= jp->end || *jp->s != '"') {
				describe(jp, what, sizeof(what));
				jfail(jp, "expected a quoted member name, got %s", what);
				return false;
			}
			key = jstring(jp);
			if (!key)
				return false;
			jskip(jp);
			if (jp->s >= jp->end || *jp->s != ':') {
				describe(jp, what, sizeof(what));
				jfail(jp, "expected ':' after member \"%s\", got %s", key, what);
				free(key);
				return false;
			}
			jp->s++;
		}
		if (!jappend(jp, v, &cap, key)) {
			free(key);
			return false;
		}
		if (!jvalue(jp, &v->items[v->n - 1], depth + 1))
			return false;
		jskip(jp);
		if (jp->s < jp->end && *jp->s == ',') {
			jp->s++;
			jskip(jp);
			if (jp->s < jp->end && (*jp->s == '}' || *jp->s == ']')) {
				jfail(jp, "trailing comma");
				return false;
			}
			continue;
		}
		if (jp->s < jp->end && *jp->s == (obj ? '}' : ']')) {
			jp->s++;
			return true;
		}
		describe(jp, what, sizeof(what));
		jfail(jp, "expected ',' or '%c', got %s", obj ? '}' : ']', what);
		return false;
	}
}

/* A number: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)? */
static bool jnumber(struct jparser *jp, struct jval *v)
{
	const char *p = jp->s;
	if (*p == '-')
		p++;
	if (p < jp->end && *p == '0')
		p++;
	else if (p < jp->end && isdigit((unsigned char)*p))
		while (p < jp->end && isdigit((unsigned char)*p))
			p++;
	else {
		jfail(jp, "malformed number");
		return false;
	}
	if (p < jp->end && *p == '.') {
		p++;
		if (p >= jp->end || !isdigit((unsigned char)*p)) {
			jfail(jp, "malformed number (digits expected after '.')");
			return false;
		}
		while (p < jp->end && isdigit((unsigned char)*p))
			p++;
	}
	if (p < jp->end && (*p == 'e' || *p == 'E')) {
		p++;
		if (p < jp->end && (*p == '+' || *p == '-'))
			p++;
		if (p >= jp->end || !isdigit((unsigned char)*p)) {
			jfail(jp, "malformed number (exponent digits expected)");
			return false;
		}
		while (p < jp->end && isdigit((unsigned char)*p))
			p++;
	}
	char buf[64];
	size_t l = (size_t)(p - jp->s);
	if (l >= sizeof(buf)) {
		jfail(jp, "number too long");
		return false;
	}
	memcpy(buf, jp->s, l);
	buf[l] = 0;
	errno = 0;
	v->num = strtod(buf, NULL);
	if (errno == ERANGE && fabs(v->num) > 1.0) {
		jfail(jp, "number %s out of range", buf);
		return false;
	}
	v->type = J_NUM;
	jp->s = p;
	return true;
}

static bool jvalue(struct jparser *jp, struct jval *v, int depth)
{
	memset(v, 0, sizeof(*v));
	jskip(jp);
	v->line = jp->line;
	if (depth > MAX_DEPTH) {
		jfail(jp, "nested deeper than %d levels", MAX_DEPTH);
		return false;
	}
	if (jp->s >= jp->end) {
		jfail(jp, "unexpected end of file, expected a value");
		return false;
	}
	char c = *jp->s;
	if (c == '{' || c == '[')
		return jcontainer(jp, v, depth);
	if (c == '"') {
		v->type = J_STR;
		v->str = jstring(jp);
		return v->str != NULL;
	}
	static const char *const words[] = { "true", "false", "null" };
	for (int i = 0; i < 3; i++) {
		size_t l = strlen(words[i]);
		if ((size_t)(jp->end - jp->s) >= l && !strncmp(jp->s, words[i], l)) {
			jp->s += l;
			v->type = i < 2 ? J_BOOL : J_NULL;
			v->num = i == 0;
			return true;
		}
	}
	if (c == '-' || isdigit((unsigned char)c))
		return jnumber(jp, v);
	char what[32];
	describe(jp, what, sizeof(what));
	jfail(jp, "unexpected %s, expected a value", what);
	return false;
}

bool json_parse(const char *text, size_t len, const char *fname, struct jval *root, char *err, size_t errlen)
{
	struct jparser jp = { text, text + len, 1, fname, err, errlen, false };
	if (!jvalue(&jp, root, 0))
		return false;
	jskip(&jp);
	if (jp.s < jp.end) {
		jfail(&jp, "text after the end of the top-level value");
		return false;
	}
	return true;
}

const struct jval *jget(const struct jval *o, const char *key)
{
	if (o->type != J_OBJ)
		return NULL;
	for (int i = 0; i < o->n; i++)
		if (!strcmp(o->keys[i], key))
			return &o->items[i];
	return NULL;
}
