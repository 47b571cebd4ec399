/* isoterra — the heap kept from frame to frame (app/core/heap.c), checked
 * against the kernel's own counts: a frame's worth of 64 KiB blocks (the
 * size llvmpipe bins a frame into) freed and allocated again costs no page
 * faults the second time and leaves the resident size where it was; once
 * the heap has grown, heap_reserve grows it by HEAP_HEADROOM more, resident,
 * so that as much again arrives without faults.  Under a sanitizer (whose
 * allocator refuses mallopt) the policy is off and heap_reserve says so. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "heap.h"
#include "tcheck.h"

#define BLOCK (64 * 1024 + 16) /* llvmpipe's data block and its header */
#define NBLOCKS 512            /* 32 MiB: one heavy frame's bins */
#define MIB (1024.0 * 1024.0)

static long faults(void)
{
	struct rusage ru;
	if (getrusage(RUSAGE_SELF, &ru) != 0)
		return -1;
	return ru.ru_minflt;
}

static double resident_mib(void)
{
	FILE *f = fopen("/proc/self/statm", "r");
	long size = 0, res = 0;
	if (!f)
		return -1;
	if (fscanf(f, "%ld %ld", &size, &res) != 2)
		res = -1;
	fclose(f);
	return (double)res * (double)sysconf(_SC_PAGESIZE) / MIB;
}

/* Allocates n blocks, writes every page, frees them; returns the page
 * faults it took and the resident size while they were held. */
static long frame(int n, double *held_mib)
{
	static void *b[4096];
	long f0 = faults();
	for (int i = 0; i < n; i++) {
		b[i] = malloc(BLOCK);
		if (!b[i]) {
			n = i;
			break;
		}
		memset(b[i], i & 0xff, BLOCK);
	}
	*held_mib = resident_mib();
	for (int i = 0; i < n; i++)
		free(b[i]);
	return faults() - f0;
}

int main(void)
{
	heap_policy();
	double held;
	long first = frame(NBLOCKS, &held);
	double after_first = resident_mib();
	long second = frame(NBLOCKS, &held);
	double after_second = resident_mib();
	long pages = (long)NBLOCKS * BLOCK / sysconf(_SC_PAGESIZE);
	printf("frame of %d blocks (%.1f MiB): %ld page faults the first time, %ld the second; resident %.1f MiB "
	       "after the first, %.1f after the second\n",
	       NBLOCKS, NBLOCKS * BLOCK / MIB, first, second, after_first, after_second);
	/* the first frame has to fault its pages in, under any policy */
	CHECK(first >= pages / 2, "first frame: %ld faults for %ld pages", first, pages);
	if (SANITIZED) {
		/* the sanitizer's allocator keeps its own rules */
		CHECK(heap_reserve() == 0, "heap_reserve under a sanitizer: the policy is off");
		return tc_done("heap");
	}
	/* kept: the second frame reuses the first one's pages */
	CHECK(second < pages / 20, "second frame: %ld faults for %ld pages (memory not kept)", second, pages);
	CHECK(after_first > held - 2.0, "resident %.1f MiB after the free, %.1f while held: given back", after_first,
	      held);
	CHECK(after_second < after_first + 2.0, "second frame grew the resident size %.1f -> %.1f MiB", after_first,
	      after_second);

	/* the reserve: HEAP_HEADROOM on top of the heap as it is now */
	size_t before = heap_reserve();
	double res_before = resident_mib();
	printf("heap_reserve: %.1f MiB (resident %.1f MiB)\n", before / MIB, res_before);
	CHECK(before >= (size_t)((double)NBLOCKS * BLOCK * (1.0 + HEAP_HEADROOM)),
	      "heap_reserve: %.1f MiB, want at least %.1f", before / MIB,
	      NBLOCKS * BLOCK * (1.0 + HEAP_HEADROOM) / MIB);
	CHECK(res_before > after_second + NBLOCKS * BLOCK * HEAP_HEADROOM / MIB * 0.8,
	      "the headroom is not resident: %.1f MiB, was %.1f", res_before, after_second);
	/* a frame heavier by most of the headroom arrives without faults */
	int heavier = (int)(NBLOCKS * (1.0 + 0.8 * HEAP_HEADROOM));
	long third = frame(heavier, &held);
	printf("frame of %d blocks after the reserve: %ld page faults\n", heavier, third);
	CHECK(third < pages / 20, "heavier frame: %ld faults after the reserve", third);
	/* checked at most once every HEAP_CHECK_MS: a second call at once
	 * answers the same without looking */
	CHECK(heap_reserve() == before, "heap_reserve called again at once: %zu, was %zu", heap_reserve(), before);
	/* a heap grown past the reserve gets the headroom again, on its new size */
	void *keep[4096];
	int nkeep = (int)(NBLOCKS * (1.0 + 2 * HEAP_HEADROOM));
	int kept = 0;
	for (int i = 0; i < nkeep; i++) {
		keep[i] = malloc(BLOCK);
		if (keep[i]) {
			memset(keep[i], 1, BLOCK);
			kept++;
		}
	}
	CHECK(kept == nkeep, "malloc: %d of %d blocks", kept, nkeep);
	usleep((useconds_t)(HEAP_CHECK_MS * 1000.0) + 100000);
	size_t grown = heap_reserve();
	printf("heap_reserve with %.1f MiB live: %.1f MiB\n", nkeep * BLOCK / MIB, grown / MIB);
	CHECK(grown >= (size_t)((double)nkeep * BLOCK * (1.0 + HEAP_HEADROOM)), "heap_reserve: %.1f MiB for %.1f MiB live",
	      grown / MIB, nkeep * BLOCK / MIB);
	for (int i = 0; i < nkeep; i++)
		free(keep[i]);
	return tc_done("heap");
}
