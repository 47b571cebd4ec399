/* isoterra — the C heap sized once to what the frame loop needs, then
 * kept: no memory mapped and unmapped every frame, a resident size that
 * settles after a few steps (docs/RELIABILITY.md, "Memory"). */
#ifndef ISOTERRA_HEAP_H
#define ISOTERRA_HEAP_H

#include <stddef.h>

/* From now on allocations under HEAP_OWN_MAP come from the heap and memory
 * freed inside it stays there for the next frame (glibc: a fixed
 * M_MMAP_THRESHOLD, so it no longer grows by itself, and an M_TRIM_THRESHOLD
 * of HEAP_KEEP).  Elsewhere, or under a sanitizer's allocator, a no-op. */
void heap_policy(void);
/* Once the heap has grown past what was last reserved, grows it to
 * HEAP_HEADROOM more (touched, then freed back into the heap): the next
 * frames' growth lands in memory the process already holds.  Looks at most
 * once every HEAP_CHECK_MS; cheap to call every frame.  Returns the heap's
 * size in bytes after it (0 where there is nothing to do). */
size_t heap_reserve(void);

#define HEAP_OWN_MAP (4 * 1024 * 1024)
#define HEAP_KEEP (1024 * 1024 * 1024)
#define HEAP_HEADROOM 0.25
#define HEAP_CHECK_MS 1000.0

#endif
