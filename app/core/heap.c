/* isoterra — the C heap kept to what is in use (heap.h).
 *
 * Why: Mesa's llvmpipe bins every frame's triangles into 64 KiB blocks
 * (DATA_BLOCK_SIZE plus a header) and frees them once the frame is
 * rasterized: the streaming world draws hundreds of thousands of triangles
 * a frame, megabytes of such blocks, allocated and freed every frame.
 * Under glibc's defaults they come from the heap (the mmap threshold has
 * grown past them), and a heap full of freed holes pinned by a few live
 * allocations only grows: the process's resident size climbs to the
 * largest frame it ever binned and stays there.  Blocks of 64 KiB or more
 * mapped on their own go back to the kernel when freed; malloc_trim gives
 * back the free pages that smaller allocations leave in the heap. */
#include "heap.h"
#include "clock.h"
#include "log.h"

#if defined(__GLIBC__)
#include <malloc.h>

void heap_policy(void)
{
	/* a sanitizer's allocator refuses it (and keeps its own rules) */
	if (mallopt(M_MMAP_THRESHOLD, HEAP_OWN_MAP) != 1)
		log_debug("mallopt(M_MMAP_THRESHOLD, %d) refused: freed memory may stay in the process", HEAP_OWN_MAP);
}

void heap_release(void)
{
	static double next;
	double now = clock_ms();
	if (now < next)
		return;
	next = now + HEAP_RELEASE_MS;
	malloc_trim(0);
}
#else
void heap_policy(void)
{
}

void heap_release(void)
{
}
#endif
