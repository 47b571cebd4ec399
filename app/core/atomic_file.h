/* isoterra — atomic file writes (temp + fsync + rename). */
#ifndef ISOTERRA_ATOMIC_FILE_H
#define ISOTERRA_ATOMIC_FILE_H

#include <stddef.h>
#include <stdio.h>

struct atomic_file {
	FILE *f;   /* write here */
	char *tmp; /* the temp file's name */
};

/* 0, or -1 with "cannot write 'path': reason" in err. */
int atomic_open(struct atomic_file *af, const char *path, char *err, size_t errlen);
/* Flush, fsync, close and rename into place; on failure the temp is removed. */
int atomic_commit(struct atomic_file *af, const char *path, char *err, size_t errlen);
/* Close and remove the temp file (after a write error). */
void atomic_abort(struct atomic_file *af);

#endif
