/* isoterra build tools: a generated file is written to OUT.tmp and renamed
 * over OUT only when complete, so an interrupted build never leaves half a
 * file behind. */
#ifndef ISOTERRA_GEN_FILE_H
#define ISOTERRA_GEN_FILE_H

#include <stdio.h>

struct gen_file {
	const char *path;
	char tmp[4096];
	FILE *f;
};

/* Opens path's temporary file; NULL (reported) on failure. */
static inline FILE *gen_begin(struct gen_file *g, const char *path)
{
	g->path = path;
	snprintf(g->tmp, sizeof(g->tmp), "%s.tmp", path);
	g->f = fopen(g->tmp, "w");
	if (!g->f)
		perror(g->tmp);
	return g->f;
}

/* Drops the temporary file; returns 1 (the tools' exit status). */
static inline int gen_abort(struct gen_file *g)
{
	fclose(g->f);
	remove(g->tmp);
	return 1;
}

/* Closes and renames; 0, or 1 (reported). */
static inline int gen_commit(struct gen_file *g)
{
	if (fclose(g->f) != 0 || rename(g->tmp, g->path) != 0) {
		perror(g->path);
		remove(g->tmp);
		return 1;
	}
	return 0;
}

#endif
