/* isoterra — a small strict JSON parser (RFC 8259: no comments, no
 * trailing commas) that keeps line numbers, so the GeoJSON reader
 * (curves_io.c) names the line of every error.  Internal to app/edit/. */
#ifndef ISOTERRA_CURVES_JSON_H
#define ISOTERRA_CURVES_JSON_H

#include <stdbool.h>
#include <stddef.h>

enum jtype { J_NULL, J_BOOL, J_NUM, J_STR, J_ARR, J_OBJ };
extern const char *const jtype_names[]; /* "null", "a boolean", ... */

struct jval {
	enum jtype type;
	int line;
	double num;
	char *str;            /* J_STR */
	struct jval *items;   /* J_ARR, J_OBJ values */
	char **keys;          /* J_OBJ */
	int n;
};

/* Parses text (one top-level value, nothing after it) into root; fname
 * for messages ("FILE:LINE: invalid JSON: ...").  Returns false with err;
 * root is to be freed either way. */
bool json_parse(const char *text, size_t len, const char *fname, struct jval *root, char *err, size_t errlen);
void jfree(struct jval *v);
/* Member key of object o, or NULL. */
const struct jval *jget(const struct jval *o, const char *key);

#endif
