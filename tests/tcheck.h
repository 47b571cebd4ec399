/* isoterra — minimal test harness.  Each test program prints one line per
 * failed check and ends with "N passed, N failed"; exit 1 on any failure,
 * 77 (meson's "skip") only when a test says why it cannot run. */
#ifndef ISOTERRA_TCHECK_H
#define ISOTERRA_TCHECK_H

#include <stdio.h>
#include <stdlib.h>

/* SANITIZED: 1 in an AddressSanitizer build (its allocator and shadow
 * memory are not the program's: memory measurements mean nothing there) */
#if defined(__SANITIZE_ADDRESS__)
#define SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SANITIZED 1
#endif
#endif
#ifndef SANITIZED
#define SANITIZED 0
#endif

/* A test program of several files defines TCHECK_SHARED before this header
 * in each of them, and the counters once, in the file with main:
 *     int tc_pass, tc_fail; */
#ifdef TCHECK_SHARED
extern int tc_pass, tc_fail;
#else
static int tc_pass, tc_fail;
#endif

#define CHECK(cond, ...)                                                        \
	do {                                                                    \
		if (cond) {                                                     \
			tc_pass++;                                              \
		} else {                                                        \
			tc_fail++;                                              \
			fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond); \
			fprintf(stderr, __VA_ARGS__);                           \
			fputc('\n', stderr);                                    \
		}                                                               \
	} while (0)

#define CHECK_NEAR(a, b, tol, what)                                             \
	CHECK(fabs((double)(a) - (double)(b)) <= (tol), "%s: %g vs %g (tol %g)", what, (double)(a), (double)(b), (double)(tol))

static inline int tc_done(const char *name)
{
	printf("%s: %d passed, %d failed\n", name, tc_pass, tc_fail);
	return tc_fail ? 1 : 0;
}

#endif
