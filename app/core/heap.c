/* isoterra — the C heap sized once to what the frame loop needs (heap.h).
 *
 * Why: Mesa's llvmpipe bins every frame's triangles into 64 KiB blocks
 * (DATA_BLOCK_SIZE plus a header) and frees them once the frame is
 * rasterized: the streaming world draws hundreds of thousands of triangles
 * a frame, tens of megabytes of such blocks, allocated and freed every
 * frame.  Mapped on their own (as glibc does for large blocks, and as this
 * file did before), every frame pays a page fault and a zeroed page for
 * each 4 KiB of them and a munmap for each block: half the frame's time at
 * 160x90, and a resident size that swings by a frame's bins from sample to
 * sample.  Kept in the heap, the blocks freed by one frame are the next
 * frame's.  What bounds the heap is the frame fence (world.c: at most two
 * frames' bins alive); what keeps it from creeping in small steps as the
 * view finds a heavier frame is the headroom heap_reserve adds each time it
 * grows. */
#include "heap.h"
#include "clock.h"
#include "log.h"

#if defined(__GLIBC__)
#include <malloc.h>
#include <stdlib.h>
#include <unistd.h>

static int active;
static size_t reserved;

void heap_policy(void)
{
	/* a sanitizer's allocator refuses them (and keeps its own rules) */
	if (mallopt(M_MMAP_THRESHOLD, HEAP_OWN_MAP) != 1 || mallopt(M_TRIM_THRESHOLD, HEAP_KEEP) != 1) {
		log_debug("mallopt(M_MMAP_THRESHOLD, M_TRIM_THRESHOLD) refused: the heap keeps the allocator's defaults");
		return;
	}
	active = 1;
}

/* Pieces the heap is grown by: under HEAP_OWN_MAP, so they come from the
 * heap; each holds the link to the one before. */
#define PIECE (256 * 1024)

size_t heap_reserve(void)
{
	static double next;
	if (!active)
		return 0;
	double now = clock_ms();
	if (now < next)
		return reserved;
	next = now + HEAP_CHECK_MS;
	struct mallinfo2 mi = mallinfo2();
	if (mi.arena <= reserved)
		return reserved;
	size_t target = mi.arena + (size_t)((double)mi.arena * HEAP_HEADROOM);
	/* the pieces fill the heap's free holes first, then extend it; taking
	 * the holes' size more than the growth wanted reaches the target */
	size_t want = target - mi.arena + mi.fordblks;
	long page = sysconf(_SC_PAGESIZE); /* 4 KiB, or 16 KiB on a Raspberry Pi 5's kernel */
	size_t stride = page > 0 ? (size_t)page : 4096;
	void *chain = NULL;
	for (size_t got = 0; got < want; got += PIECE) {
		void **piece = malloc(PIECE);
		if (!piece)
			break;
		/* resident now, not at the next frame: a write to each page
		 * (volatile: the compiler sees the piece freed unread) */
		for (size_t off = 0; off < PIECE; off += stride)
			((volatile char *)piece)[off] = 0;
		*piece = chain;
		chain = piece;
	}
	while (chain) {
		void *before = *(void **)chain;
		free(chain);
		chain = before;
	}
	mi = mallinfo2();
	reserved = mi.arena;
	log_debug("heap: %zu KiB reserved (%zu KiB in use)", reserved >> 10, mi.uordblks >> 10);
	return reserved;
}
#else
void heap_policy(void)
{
}

size_t heap_reserve(void)
{
	return 0;
}
#endif
