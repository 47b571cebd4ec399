/* isoterra — the C heap kept to what is in use: freed memory goes back to
 * the kernel instead of staying in the process (docs/RELIABILITY.md,
 * "Memory"). */
#ifndef ISOTERRA_HEAP_H
#define ISOTERRA_HEAP_H

/* From now on every allocation of HEAP_OWN_MAP bytes or more gets its own
 * mapping, unmapped when it is freed (glibc: a fixed M_MMAP_THRESHOLD; by
 * default the threshold grows with the largest block freed, up to 32 MB,
 * and blocks under it are carved from the heap, which only shrinks from
 * its top).  Elsewhere a no-op. */
void heap_policy(void);
/* Gives whole free pages inside the heap back to the kernel (glibc:
 * malloc_trim), at most once every HEAP_RELEASE_MS; cheap to call every
 * frame.  Elsewhere a no-op. */
void heap_release(void);

#define HEAP_OWN_MAP (64 * 1024)
#define HEAP_RELEASE_MS 1000.0

#endif
