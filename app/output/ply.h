/* isoterra — binary little-endian PLY export (MeshLab, Blender). */
#ifndef ISOTERRA_PLY_H
#define ISOTERRA_PLY_H

#include <stddef.h>
#include "core.h"

/* Writes vertices (x y z nx ny nz float) and faces (uchar count, uint
 * indices) atomically (temp file + rename).  0 or -1 with err. */
int ply_write(const struct mesh *m, const char *path, char *err, size_t errlen);
/* The same into a staged temp file beside path (atomic_close'd): the caller
 * commits it to path, or aborts it.  0 or -1 with err (no temp left). */
int ply_write_staged(const struct mesh *m, const char *path, struct atomic_file *af, char *err, size_t errlen);
/* Reads back a file written by ply_write (used by the tests). */
int ply_read(struct mesh *m, const char *path, char *err, size_t errlen);

#endif
