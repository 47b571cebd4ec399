/* isoterra — a small strict JSON parser that keeps line numbers.  See json.h. */
#include "json.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 64

const char *const json_type_names[] = { "null", "a boolean", "a number", "a string", "an array", "an object" };

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

void json_free(struct json_value *v)
{
	if (v->type == JSON_STRING)
		free(v->str);
	if (v->type == JSON_ARRAY || v->type == JSON_OBJECT) {
		for (int i = 0; i < v->n; i++) {
			json_free(&v->items[i]);
			if (v->keys)
				free(v->keys[i]);
		}
		free(v->items);
		free(v->keys);
	}
	memset(v, 0, sizeof(*v));
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

/* End of the number at jp->s (JSON grammar
 * -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?), or NULL when malformed. */
static const char *jnumber_end(struct jparser *jp)
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
		return NULL;
	}
	if (p < jp->end && *p == '.') {
		p++;
		if (p >= jp->end || !isdigit((unsigned char)*p)) {
			jfail(jp, "malformed number (digits expected after '.')");
			return NULL;
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
			return NULL;
		}
		while (p < jp->end && isdigit((unsigned char)*p))
			p++;
	}
	return p;
}

static bool jnumber(struct jparser *jp, struct json_value *v)
{
	const char *p = jnumber_end(jp);
	if (!p)
		return false;
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
	v->type = JSON_NUMBER;
	jp->s = p;
	return true;
}

static bool jvalue(struct jparser *jp, struct json_value *v, int depth);

static bool jappend(struct jparser *jp, struct json_value *v, int *cap, char *key)
{
	if (v->n + 1 > *cap) {
		int nc = *cap ? *cap * 2 : 4;
		struct json_value *ni = realloc(v->items, sizeof(*ni) * (size_t)nc);
		if (!ni) {
			jfail(jp, "out of memory");
			return false;
		}
		v->items = ni;
		if (v->type == JSON_OBJECT) {
			char **nk = realloc(v->keys, sizeof(*nk) * (size_t)nc);
			if (!nk) {
				jfail(jp, "out of memory");
				return false;
			}
			v->keys = nk;
		}
		*cap = nc;
	}
	memset(&v->items[v->n], 0, sizeof(struct json_value));
	if (v->type == JSON_OBJECT)
		v->keys[v->n] = key;
	v->n++;
	return true;
}

/* A member's quoted name and the ':' after it; NULL on error. */
static char *jmember_name(struct jparser *jp)
{
	char what[32];
	if (jp->s >= jp->end || *jp->s != '"') {
		describe(jp, what, sizeof(what));
		jfail(jp, "expected a quoted member name, got %s", what);
		return NULL;
	}
	char *key = jstring(jp);
	if (!key)
		return NULL;
	jskip(jp);
	if (jp->s >= jp->end || *jp->s != ':') {
		describe(jp, what, sizeof(what));
		jfail(jp, "expected ':' after member \"%s\", got %s", key, what);
		free(key);
		return NULL;
	}
	jp->s++;
	return key;
}

/* An object or an array, at its '{' or '['. */
static bool jcontainer(struct jparser *jp, struct json_value *v, int depth)
{
	bool obj = *jp->s == '{';
	char close = obj ? '}' : ']';
	v->type = obj ? JSON_OBJECT : JSON_ARRAY;
	jp->s++;
	int cap = 0;
	jskip(jp);
	if (jp->s < jp->end && *jp->s == close) {
		jp->s++;
		return true;
	}
	for (;;) {
		char *key = NULL;
		jskip(jp);
		if (obj && !(key = jmember_name(jp)))
			return false;
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
		if (jp->s < jp->end && *jp->s == close) {
			jp->s++;
			return true;
		}
		char what[32];
		describe(jp, what, sizeof(what));
		jfail(jp, "expected ',' or '%c', got %s", close, what);
		return false;
	}
}

static bool jvalue(struct jparser *jp, struct json_value *v, int depth)
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
		v->type = JSON_STRING;
		v->str = jstring(jp);
		return v->str != NULL;
	}
	static const char *const words[] = { "true", "false", "null" };
	for (int i = 0; i < 3; i++) {
		size_t l = strlen(words[i]);
		if ((size_t)(jp->end - jp->s) >= l && !strncmp(jp->s, words[i], l)) {
			jp->s += l;
			v->type = i < 2 ? JSON_BOOL : JSON_NULL;
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

int json_parse(const char *text, size_t len, const char *fname, struct json_value *root, char *err,
	       size_t errlen)
{
	struct jparser jp = { text, text + len, 1, fname, err, errlen, false };
	bool ok = jvalue(&jp, root, 0);
	if (ok) {
		jskip(&jp);
		if (jp.s < jp.end) {
			jfail(&jp, "text after the end of the top-level value");
			ok = false;
		}
	}
	if (!ok) {
		json_free(root);
		return -1;
	}
	return 0;
}

const struct json_value *json_get(const struct json_value *o, const char *key)
{
	if (o->type != JSON_OBJECT)
		return NULL;
	for (int i = 0; i < o->n; i++)
		if (!strcmp(o->keys[i], key))
			return &o->items[i];
	return NULL;
}
