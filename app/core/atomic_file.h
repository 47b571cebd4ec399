/* isoterra — atomic file writes (temp + fsync + rename). */
#ifndef ISOTERRA_ATOMIC_FILE_H
#define ISOTERRA_ATOMIC_FILE_H

#include <stddef.h>
#include <stdio.h>

struct atomic_file {
	FILE *f;   /* write here */
	char *tmp; /* the temp file's name */
};

/* The temp file's name is path + ".XXXXXX": ATOMIC_TMP_EXTRA more bytes.
 * 0, or -1 with "cannot write 'path': reason" in err. */
#define ATOMIC_TMP_EXTRA 7
int atomic_open(struct atomic_file *af, const char *path, char *err, size_t errlen);
/* Flush, fsync and close, keeping the temp (staged: commit or abort it
 * later); on failure the temp is removed.  0, or -1 with err. */
int atomic_close(struct atomic_file *af, const char *path, char *err, size_t errlen);
/* Close (unless staged) and rename into place; on failure the temp is removed. */
int atomic_commit(struct atomic_file *af, const char *path, char *err, size_t errlen);
/* Close and remove the temp file (after a write error); nothing when there
 * is none (committed, aborted, or never opened with af zeroed). */
void atomic_abort(struct atomic_file *af);

#endif
