/* isoterra build tool: the C enums of the parameter table.
 * usage: isoterra-gen-enums OUT.h
 * Every enum parameter of app/params/params.def (PE entries) becomes
 *     enum param_<name> { <NAME>_<CHOICE> = 0, ..., <NAME>_COUNT };
 * with the same names params_glsl_decls() gives the shaders, so C and GLSL
 * see one order, the table's. */
#include <ctype.h>
#include <stdio.h>
#include <string.h>

#include "gen_file.h"

struct entry {
	const char *name, *choices;
};

static const struct entry entries[] = {
#define PF(name, def, lo, hi, flags, help)
#define PI(name, def, lo, hi, flags, help)
#define PB(name, def, flags, help)
#define PS(name, def, flags, help)
#define PE(name, def, choices, flags, help) { #name, choices },
#include "params.def"
#undef PF
#undef PI
#undef PB
#undef PE
#undef PS
};

static void upper(FILE *f, const char *s, size_t n)
{
	for (size_t i = 0; i < n && s[i]; i++)
		fputc(toupper((unsigned char)s[i]), f);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: %s OUT.h\n", argv[0]);
		return 2;
	}
	struct gen_file g;
	FILE *out = gen_begin(&g, argv[1]);
	if (!out)
		return 1;
	fprintf(out, "/* generated from app/params/params.def by isoterra-gen-enums: do not edit */\n"
		     "#ifndef ISOTERRA_PARAMS_ENUMS_H\n#define ISOTERRA_PARAMS_ENUMS_H\n");
	for (size_t i = 0; i < sizeof(entries) / sizeof(entries[0]); i++) {
		const struct entry *e = &entries[i];
		fprintf(out, "\nenum param_%s {", e->name);
		for (const char *c = e->choices; c;) {
			const char *bar = strchr(c, '|');
			fputs("\n\t", out);
			upper(out, e->name, strlen(e->name));
			fputc('_', out);
			upper(out, c, bar ? (size_t)(bar - c) : strlen(c));
			fputc(',', out);
			c = bar ? bar + 1 : NULL;
		}
		fputs("\n\t", out);
		upper(out, e->name, strlen(e->name));
		fputs("_COUNT\n};\n", out);
	}
	fprintf(out, "\n#endif\n");
	return gen_commit(&g);
}
