/* isoterra — the program binary cache (app/gpu/program_cache.c): a first
 * run writes one file per program, a second run loads every program from
 * the files and extracts the identical mesh; a truncated file, a file with
 * a flipped payload byte and a file from another renderer are ignored and
 * rewritten (and the mesh is still identical); an unwritable or missing
 * cache directory only costs the compile.  The reference is the mesh of
 * freshly compiled programs with the cache off. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "gpu_fixture.h"
#include "tcheck.h"

static char dir[256];

/* One extraction at grid 24 of the default field; mesh out, 0 or -1. */
static int extract(struct mesh *m)
{
	struct params p;
	params_defaults(&p);
	p.grid = 24;
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "";
	struct fixture_terrain ft;
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0) {
		fprintf(stderr, "pipeline_create: %s\n", err);
		return -1;
	}
	int rc = fixture_run(ft.pl, &p) == 0 && pipeline_read_mesh(ft.pl, m) == 0 ? 0 : -1;
	fixture_terrain_close(&ft);
	return rc;
}

static bool same_mesh(const struct mesh *a, const struct mesh *b)
{
	return a->ntris == b->ntris && a->nverts == b->nverts &&
	       !memcmp(a->idx, b->idx, (size_t)a->ntris * 3 * sizeof(uint32_t)) &&
	       !memcmp(a->pos, b->pos, (size_t)a->nverts * 3 * sizeof(float)) &&
	       !memcmp(a->nrm, b->nrm, (size_t)a->nverts * 3 * sizeof(float));
}

/* The cache's entries (names sorted, up to max); returns the count. */
static int entries(char names[][64], int max)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while (d && (e = readdir(d)))
		if (strstr(e->d_name, ".bin") && n < max)
			snprintf(names[n++], 64, "%.63s", e->d_name);
	if (d)
		closedir(d);
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
			char t[64];
			memcpy(t, names[j], 64);
			memcpy(names[j], names[j - 1], 64);
			memcpy(names[j - 1], t, 64);
		}
	return n;
}

static void path_of(const char *name, char *out, size_t n)
{
	snprintf(out, n, "%.255s/%.63s", dir, name);
}

/* Damages three entries three ways; 0 or -1. */
static int damage(char names[][64], int n)
{
	if (n < 3)
		return -1;
	char path[512];
	struct stat sb;
	/* 1: truncated by a crash (only the header and half the payload) */
	path_of(names[0], path, sizeof(path));
	if (stat(path, &sb) < 0 || truncate(path, sb.st_size / 2) < 0)
		return -1;
	/* 2: one payload byte flipped */
	path_of(names[1], path, sizeof(path));
	FILE *f = fopen(path, "r+b");
	if (!f || fseek(f, -7, SEEK_END) != 0)
		return -1;
	int c = fgetc(f);
	fseek(f, -7, SEEK_END);
	fputc(c ^ 0x5a, f);
	fclose(f);
	/* 3: written by another driver (the renderer string follows the
	 * magic, the key, format, length and checksum: 8 + 16 + 8 + 8 bytes) */
	path_of(names[2], path, sizeof(path));
	f = fopen(path, "r+b");
	if (!f || fseek(f, 40, SEEK_SET) != 0)
		return -1;
	fputs("Some Other GPU", f);
	fclose(f);
	return 0;
}

int main(void)
{
	struct platform *plat = fixture_open();
	snprintf(dir, sizeof(dir), "/tmp/isoterra-progcache-%d", (int)getpid());
	struct mesh ref, m;

	gpu_program_cache_config(false, dir);
	CHECK(extract(&ref) == 0 && ref.ntris > 0, "reference extraction without the cache");
	struct gpu_program_cache_stats st = gpu_program_cache_stats();
	CHECK(st.hits == 0 && st.writes == 0, "cache off: no hits (%u), no writes (%u)", st.hits, st.writes);
	struct stat sb;
	CHECK(stat(dir, &sb) < 0, "cache off: no directory made");

	gpu_program_cache_config(true, dir);
	CHECK(extract(&m) == 0 && same_mesh(&m, &ref), "first run with the cache: same mesh");
	mesh_free(&m);
	st = gpu_program_cache_stats();
	printf("first run: %u compiled, %u written, %u hits\n", st.misses, st.writes, st.hits);
	if (st.misses == 0 && st.writes == 0) {
		fprintf(stderr, "this driver offers no program binary format: nothing to test\n");
		return 77;
	}
	unsigned programs = st.misses;
	CHECK(programs >= 4 && st.writes == programs && st.hits == 0, "first run writes every program (%u of %u)",
	      st.writes, programs);
	char names[64][64];
	int n = entries(names, 64);
	CHECK(n == (int)programs, "one file per program (%d files, %u programs)", n, programs);

	gpu_program_cache_config(true, dir);
	CHECK(extract(&m) == 0 && same_mesh(&m, &ref), "second run from the cache: same mesh");
	mesh_free(&m);
	st = gpu_program_cache_stats();
	CHECK(st.hits == programs && st.misses == 0 && st.writes == 0, "second run: all %u from the cache (hits %u, compiled %u)",
	      programs, st.hits, st.misses);

	CHECK(damage(names, n) == 0, "damage three entries");
	gpu_program_cache_config(true, dir);
	CHECK(extract(&m) == 0 && same_mesh(&m, &ref), "run over damaged entries: same mesh");
	mesh_free(&m);
	st = gpu_program_cache_stats();
	CHECK(st.rejected == 3 && st.misses == 3 && st.writes == 3 && st.hits == programs - 3,
	      "damaged entries ignored and rewritten (rejected %u, compiled %u, written %u, hits %u)", st.rejected,
	      st.misses, st.writes, st.hits);
	gpu_program_cache_config(true, dir);
	CHECK(extract(&m) == 0 && same_mesh(&m, &ref), "run after the rewrite: same mesh");
	mesh_free(&m);
	st = gpu_program_cache_stats();
	CHECK(st.hits == programs && st.rejected == 0, "rewritten entries are good (hits %u)", st.hits);

	/* a directory that exists but takes no files, even for root */
	gpu_program_cache_config(true, "/proc/self");
	CHECK(extract(&m) == 0 && same_mesh(&m, &ref), "read-only cache directory: same mesh");
	mesh_free(&m);
	st = gpu_program_cache_stats();
	CHECK(st.writes == 0 && st.write_errors == programs, "read-only directory: writes fail quietly (%u errors)",
	      st.write_errors);
	/* a path that cannot be a directory */
	gpu_program_cache_config(true, "/dev/null/isoterra");
	CHECK(extract(&m) == 0 && same_mesh(&m, &ref), "impossible cache directory: same mesh");
	mesh_free(&m);

	/* programs issued ahead (gpu_prefetch_*: the pipeline issues its own,
	 * so the runs above went through it): one issued and then asked for is
	 * compiled once; one never asked for is dropped; a missing file issued
	 * ahead is still reported, by the build, with its name */
	gpu_program_cache_config(true, dir);
	gpu_prefetch_compute("mc_setup.comp", "#define PREFETCH_TEST 1\n");
	gpu_prefetch_compute("mc_setup.comp", "#define PREFETCH_TEST 1\n"); /* issued once */
	char err[512] = "";
	GLuint prog = gpu_compute_program("mc_setup.comp", "#define PREFETCH_TEST 1\n", err, sizeof(err));
	st = gpu_program_cache_stats();
	CHECK(prog != 0 && st.misses == 1 && st.writes == 1, "issued ahead, then asked for: one compile (%u), one write (%u) %s",
	      st.misses, st.writes, err);
	if (prog)
		glDeleteProgram(prog);
	gpu_prefetch_compute("no_such_file.comp", NULL);
	prog = gpu_compute_program("no_such_file.comp", NULL, err, sizeof(err));
	CHECK(prog == 0 && strstr(err, "no_such_file.comp"), "a missing file issued ahead is reported: '%s'", err);
	gpu_prefetch_compute("mc_finish.comp", "#define PREFETCH_TEST 2\n");
	gpu_prefetch_drop();
	CHECK(gpu_check("prefetch") == 0, "no GL error");

	n = entries(names, 64);
	for (int i = 0; i < n; i++) {
		char path[512];
		path_of(names[i], path, sizeof(path));
		unlink(path);
	}
	rmdir(dir);
	mesh_free(&ref);
	platform_close(plat);
	return tc_done("program_cache");
}
