/* isoterra — a small strict JSON parser (RFC 8259 grammar) into a tree that
 * keeps the line of every value, so that readers of JSON formats (the
 * GeoJSON curves) can name the line of what they reject. */
#ifndef ISOTERRA_JSON_H
#define ISOTERRA_JSON_H

#include <stddef.h>

enum json_type { JSON_NULL, JSON_BOOL, JSON_NUMBER, JSON_STRING, JSON_ARRAY, JSON_OBJECT };
/* "null", "a boolean", "a number", "a string", "an array", "an object" */
extern const char *const json_type_names[];

struct json_value {
	enum json_type type;
	int line;                  /* where the value starts */
	double num;                /* JSON_NUMBER; JSON_BOOL: 1 or 0 */
	char *str;                 /* JSON_STRING (\u escapes read as '?') */
	struct json_value *items;  /* JSON_ARRAY, JSON_OBJECT values */
	char **keys;               /* JSON_OBJECT member names */
	int n;
};

/* Parses text (one value, nested at most 64 levels, white space around it)
 * into root.  0, or -1 with err "fname:line: invalid JSON: why" and nothing
 * left to free. */
int json_parse(const char *text, size_t len, const char *fname, struct json_value *root, char *err,
	       size_t errlen);
void json_free(struct json_value *v);
/* Member key of an object (the first of that name), or NULL (also when o is
 * not an object). */
const struct json_value *json_get(const struct json_value *o, const char *key);

#endif
