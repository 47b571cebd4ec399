/* isoterra — the volume's mesh drawn in parts (app/render/parts.c,
 * shaders/draw_parts.comp): the parts' commands, made on the GPU from the
 * mesh's own, draw the very picture of the single draw (every triangle
 * once, in order: a part that dropped, repeated or shifted triangles would
 * change pixels), for indexed and unindexed meshes, with and without the
 * depth pre-pass, for parts that divide the mesh evenly or not and parts
 * past its end.  And what the parts are for: on a software rasterizer the
 * peak resident memory the draw adds, each way measured by the kernel in
 * a process of its own, is far smaller in parts. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "gpu_fixture.h"
#include "tcheck.h"

#define W 320
#define H 240

static int frame(struct renderer *r, const struct pipeline_draw *d, const struct params *p, const struct grid *g,
		 int w, int h, struct image *img)
{
	struct camera c;
	camera_orbit(&c, p, g, 0.0f, (float)w / (float)h);
	if (renderer_draw(r, d, &c, p) < 0)
		return -1;
	return img ? renderer_read(r, img) : 0;
}

static int differ(const struct image *a, const struct image *b)
{
	int n = 0;
	for (int i = 0; i < W * H * 4; i += 4)
		n += memcmp(a->rgba + i, b->rgba + i, 4) != 0;
	return n;
}

/* The picture drawn in parts of each size against the single draw, with
 * the depth pre-pass and without. */
static void same_picture(struct renderer *r, struct fixture_terrain *ft, struct params *p, const struct grid *g,
			 const char *what)
{
	CHECK(fixture_run(ft->pl, p) == 0, "%s: run", what);
	struct extract_stats st;
	CHECK(pipeline_read_stats(ft->pl, &st) == 0, "%s: stats", what);
	struct pipeline_draw d;
	pipeline_draw_info(ft->pl, &d);
	printf("%s: %u triangles, capacity %u\n", what, st.triangles, d.capacity);
	CHECK(st.triangles > 2000, "%s: a mesh worth splitting (%u triangles)", what, st.triangles);
	/* the default; parts dividing the capacity's 64 parts; odd sizes;
	 * one part larger than the mesh */
	uint32_t sizes[] = { RENDER_PART_TRIANGLES, 1, 700, 1237, 4096, 1000000 };
	bool was = renderer_prepass(r);
	for (int pre = 0; pre < 2; pre++) {
		renderer_set_prepass(r, pre == 1);
		struct image whole = { 0 };
		renderer_set_parts(r, 0);
		CHECK(frame(r, &d, p, g, W, H, &whole) == 0, "%s: the single draw", what);
		for (size_t k = 0; k < sizeof(sizes) / sizeof(sizes[0]); k++) {
			struct image img = { 0 };
			renderer_set_parts(r, sizes[k]);
			CHECK(frame(r, &d, p, g, W, H, &img) == 0, "%s: parts of %u", what, sizes[k]);
			int n = whole.rgba && img.rgba ? differ(&img, &whole) : -1;
			CHECK(n == 0, "%s: parts of %u triangles (pre-pass %s) change %d pixels of the single draw", what,
			      sizes[k], pre ? "on" : "off", n);
			free(img.rgba);
		}
		free(whole.rgba);
	}
	renderer_set_prepass(r, was);
	renderer_set_parts(r, RENDER_PART_TRIANGLES);
}

/* ---- the memory ------------------------------------------------------------ */

static long status_kb(const char *key)
{
	FILE *f = fopen("/proc/self/status", "r");
	char line[256];
	long v = -1;
	size_t n = strlen(key);
	while (f && fgets(line, sizeof(line), f))
		if (!strncmp(line, key, n) && line[n] == ':')
			v = strtol(line + n + 1, NULL, 10);
	if (f)
		fclose(f);
	return v;
}

/* In this (child) process: the no-flag picture's volume at 1280x720, its
 * draw warmed up once (shaders compiled) in small parts; then the peak
 * resident memory (VmHWM, reset through clear_refs) the draw adds over the
 * resident size before it, in kB, drawn in parts of part_tris (0: whole).
 * -1 when it cannot be measured. */
static long draw_growth(uint32_t part_tris, bool *software)
{
	fixture_open();
	*software = gpu_software_rasterizer();
	struct params p;
	params_defaults(&p);
	struct grid g;
	grid_from_params(&g, &p);
	char err[512];
	struct fixture_terrain ft;
	struct renderer *r = NULL;
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0 ||
	    !(r = renderer_create(1280, 720, ANTIALIAS_OFF, err, sizeof(err))) || fixture_run(ft.pl, &p) < 0) {
		fprintf(stderr, "memory: %s\n", err);
		return -1;
	}
	pipeline_release_field(ft.pl);
	struct pipeline_draw d;
	pipeline_draw_info(ft.pl, &d);
	renderer_set_parts(r, 2048);
	if (frame(r, &d, &p, &g, 1280, 720, NULL) < 0)
		return -1;
	glFinish();
	FILE *f = fopen("/proc/self/clear_refs", "w");
	if (!f || fputs("5", f) < 0 || fclose(f) != 0) {
		perror("memory: /proc/self/clear_refs");
		return -1;
	}
	long before = status_kb("VmRSS");
	renderer_set_parts(r, part_tris);
	if (frame(r, &d, &p, &g, 1280, 720, NULL) < 0)
		return -1;
	glFinish();
	long peak = status_kb("VmHWM");
	return before < 0 || peak < 0 ? -1 : peak - before;
}

/* draw_growth in a child process of its own (a fresh heap and context);
 * *software: whether that context renders on the CPU
 * (gpu_software_rasterizer: its EGL device's EGL_MESA_device_software). */
static long growth_apart(uint32_t part_tris, bool *software)
{
	int fd[2];
	*software = false;
	if (pipe(fd) < 0)
		return -1;
	fflush(stdout);
	pid_t pid = fork();
	if (pid == 0) {
		close(fd[0]);
		long v[2] = { -1, 0 };
		bool sw = false;
		v[0] = draw_growth(part_tris, &sw);
		v[1] = sw;
		ssize_t w = write(fd[1], v, sizeof(v));
		_exit(w == (ssize_t)sizeof(v) ? 0 : 1);
	}
	close(fd[1]);
	long got[2] = { -1, 0 };
	if (pid < 0 || read(fd[0], got, sizeof(got)) != (ssize_t)sizeof(got))
		got[0] = -1;
	long v = got[0];
	*software = got[1] != 0;
	close(fd[0]);
	int status = 0;
	if (pid > 0 && (waitpid(pid, &status, 0) != pid || !WIFEXITED(status) || WEXITSTATUS(status) != 0))
		v = -1;
	return v;
}

static void memory(void)
{
	if (SANITIZED) {
		printf("memory: not measured under a sanitizer (its allocator is not the program's)\n");
		return;
	}
	bool sw_whole = false, sw_parts = false;
	long whole = growth_apart(0, &sw_whole), parts = growth_apart(RENDER_PART_TRIANGLES, &sw_parts);
	printf("memory: the no-flag picture's draw adds %.1f MB drawn whole, %.1f MB in parts of %d triangles\n",
	       whole / 1024.0, parts / 1024.0, RENDER_PART_TRIANGLES);
	CHECK(whole >= 0 && parts >= 0, "memory: both draws measured");
	CHECK(sw_whole == sw_parts, "memory: both draws on the same kind of rasterizer");
	/* The bins are a software rasterizer's (llvmpipe's scene of binned
	 * commands, in this process's heap); a GPU's driver keeps its command
	 * buffers elsewhere (GPU or pinned memory, mostly not in VmHWM): a
	 * capability, not a renderer name, decides. */
	if (!sw_whole) {
		printf("memory: the bins' checks skipped: this EGL device is not a software rasterizer (no "
		       "EGL_MESA_device_software); a GPU bins in its own memory, not in this process's heap\n");
		return;
	}
	CHECK(whole >= 4096, "memory: the single draw's bins are visible (%ld kB)", whole);
	CHECK(parts * 2 <= whole, "memory: in parts the draw adds at most half as much (%ld kB vs %ld kB)", parts, whole);
}

int main(void)
{
	/* first, before this process has a context: the children have theirs */
	memory();
	struct platform *plat = fixture_open();
	bool software = gpu_software_rasterizer();
	struct params p;
	params_defaults(&p);
	p.grid = 48;
	struct grid g;
	grid_from_params(&g, &p);
	char err[512] = "";
	struct fixture_terrain ft;
	struct renderer *r = NULL;
	if (fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) < 0 ||
	    !(r = renderer_create(W, H, ANTIALIAS_OFF, err, sizeof(err)))) {
		fprintf(stderr, "setup: %s\n", err);
		return 1;
	}
	CHECK(renderer_parts(r) == (software ? RENDER_PART_TRIANGLES : 0u),
	      "parts by default on a software rasterizer only (%u)", renderer_parts(r));
	same_picture(r, &ft, &p, &g, "indexed (HistoPyramid)");
	p.compaction = COMPACTION_ATOMIC;
	p.ao_rays = 0; /* atomic append has no vertex pass to trace them */
	same_picture(r, &ft, &p, &g, "unindexed (atomic append)");
	renderer_destroy(r);
	fixture_terrain_close(&ft);
	platform_close(plat);
	return tc_done("parts");
}
