/* isoterra — app/gpu's private interfaces: the program binary cache as the
 * shader loader uses it (program_cache.c). */
#ifndef ISOTERRA_GPU_INT_H
#define ISOTERRA_GPU_INT_H

#include <stdint.h>
#include <GLES3/gl31.h>

/* A linked program from the cache for these stage sources (each the full
 * text given to the driver), or 0; key_out is filled for a later store
 * either way. */
GLuint program_cache_load(const char *const *sources, int n, uint64_t key_out[2]);
/* Writes a freshly linked program under key (atomically); failures are
 * logged once and otherwise ignored. */
void program_cache_store(GLuint prog, const uint64_t key[2]);

/* The locations cached for prog are stale: it was (re)linked
 * (uniform_cache.c). */
void uniform_cache_forget(GLuint prog);

#endif
