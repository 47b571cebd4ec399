/* isoterra — libFuzzer harnesses: the input as a file, for the readers that
 * take a path (config files, PNG heightmaps, PLY).  One file per process,
 * rewritten for every input, in a private folder under $TMPDIR (or /tmp)
 * that is removed at exit. */
#ifndef ISOTERRA_FUZZ_FILE_H
#define ISOTERRA_FUZZ_FILE_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char fuzz_dir[256];
static char fuzz_path_buf[320];

static void fuzz_file_cleanup(void)
{
	if (fuzz_path_buf[0])
		unlink(fuzz_path_buf);
	if (fuzz_dir[0])
		rmdir(fuzz_dir);
}

/* The input written to "<private folder>/in<suffix>"; aborts when it cannot
 * be (a harness that silently tested nothing would be worse). */
static const char *fuzz_file(const unsigned char *data, size_t size, const char *suffix)
{
	if (!fuzz_dir[0]) {
		const char *tmp = getenv("TMPDIR");
		snprintf(fuzz_dir, sizeof(fuzz_dir), "%s/isoterra-fuzz-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
		if (!mkdtemp(fuzz_dir)) {
			perror("fuzz: mkdtemp");
			abort();
		}
		snprintf(fuzz_path_buf, sizeof(fuzz_path_buf), "%s/in%s", fuzz_dir, suffix);
		atexit(fuzz_file_cleanup);
	}
	FILE *f = fopen(fuzz_path_buf, "wb");
	if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
		perror("fuzz: writing the input file");
		abort();
	}
	return fuzz_path_buf;
}

#endif
