/* isoterra — live shader editing: a copy of the shaders as the
 * --shader-dir, frames through the frame loop with the watcher; a sink
 * between frames (as an editor would, mid-run) rewrites render.frag:
 *   frame 1 written: the terrain's colour changed -> frame 2 differs from 1
 *   frame 3 written: a syntax error at a known line -> "render.frag:LINE:"
 *                    on stderr, frames 4 and 5 still come, drawn with the
 *                    last good program (equal to frame 3)
 *   frame 5 written: density.glsl raises the terrain (a compute program
 *                    whose grid uniforms were set once, at creation: kept
 *                    across the rebuild) -> frame 6 differs, frame 7 = 6
 * Nothing else changes between frames (no camera spin, no water). */
#include "app.h"
#include "gpu_fixture.h"
#include "tcheck.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define FRAMES 8

struct edit_sink {
	struct sink base;
	struct image img[FRAMES];
	char dir[64];
	int broken_line;
};

static char *slurp(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	char *buf = calloc(1, 1 << 20);
	size_t n = buf ? fread(buf, 1, (1 << 20) - 1, f) : 0;
	fclose(f);
	if (buf)
		buf[n] = 0;
	return buf;
}

static bool put(const char *path, const char *text)
{
	FILE *f = fopen(path, "wb");
	if (!f)
		return false;
	bool ok = fputs(text, f) >= 0;
	return fclose(f) == 0 && ok;
}

/* file with `old` replaced by `repl` (*line: the line of `old`). */
static bool rewrite(struct edit_sink *s, const char *file, const char *old, const char *repl, int *line)
{
	char path[128];
	snprintf(path, sizeof(path), "%s/%s", s->dir, file);
	char *text = slurp(path);
	char *at = text ? strstr(text, old) : NULL;
	if (!at) {
		free(text);
		return false;
	}
	if (line) {
		*line = 1;
		for (const char *c = text; c < at; c++)
			*line += *c == '\n';
	}
	size_t n = strlen(text) + strlen(repl) + 1;
	char *out = malloc(n);
	bool ok = out != NULL;
	if (ok) {
		snprintf(out, n, "%.*s%s%s", (int)(at - text), text, repl, at + strlen(old));
		ok = put(path, out);
	}
	free(out);
	free(text);
	return ok;
}

static int edit_frame(struct sink *base, struct sink_frame *fr, char *err, size_t errlen)
{
	struct edit_sink *s = (struct edit_sink *)base;
	if (fr->index < FRAMES && renderer_read(fr->r, &s->img[fr->index]) < 0) {
		snprintf(err, errlen, "read frame %d", fr->index);
		return -1;
	}
	if (fr->index == 1)
		CHECK(rewrite(s, "render.frag", "frag = vec4(display(col), 1.0);", "frag = vec4(1.0, 0.0, 1.0, 1.0);", NULL),
		      "edit render.frag");
	if (fr->index == 3)
		CHECK(rewrite(s, "render.frag", "void main()", "this is not GLSL;\nvoid main()", &s->broken_line), "break render.frag");
	if (fr->index == 5)
		CHECK(rewrite(s, "density.glsl", "return carve_density(ws_orig, d);", "return carve_density(ws_orig, d + 4.0);",
			      NULL),
		      "edit density.glsl");
	return 0;
}

static int edit_finish(struct sink *base, const struct sink_end *end, char *err, size_t errlen)
{
	(void)base;
	(void)end;
	(void)err;
	(void)errlen;
	return 0;
}

static void edit_destroy(struct sink *base)
{
	(void)base;
}

static const struct sink_ops edit_ops = { .frame = edit_frame, .finish = edit_finish, .destroy = edit_destroy };

static int differing(const struct image *a, const struct image *b)
{
	int n = 0;
	for (int i = 0; a->rgba && b->rgba && i < a->width * a->height; i++)
		n += memcmp(a->rgba + 4 * i, b->rgba + 4 * i, 3) != 0;
	return n;
}

int main(void)
{
	struct platform *plat = fixture_open();
	static struct edit_sink es = { .base = { &edit_ops, NULL } };
	snprintf(es.dir, sizeof(es.dir), "/tmp/isoterra-shaders-XXXXXX");
	CHECK(mkdtemp(es.dir) != NULL, "mkdtemp");
	const char *src = getenv("ISOTERRA_SRC");
	char cmd[512], err[1024] = "", logf[128];
	snprintf(cmd, sizeof(cmd), "cp '%s/shaders/'* '%s/'", src ? src : ".", es.dir);
	CHECK(system(cmd) == 0, "copy the shaders: %s", cmd);
	snprintf(logf, sizeof(logf), "%s/stderr.txt", es.dir);

	struct params p;
	params_defaults(&p);
	/* the diorama box fills the frame: an edit of the field shows */
	CHECK(params_apply_preset(&p, "diorama", err, sizeof(err)) == 0, "preset diorama: %s", err);
	snprintf(p.size, sizeof(p.size), "96x72");
	p.grid = 24;
	p.count = FRAMES;
	p.cam_spin = 0.0f;
	p.water = false;
	snprintf(p.shader_dir, sizeof(p.shader_dir), "%s", es.dir);
	shader_set_dir(p.shader_dir);
	struct shader_watch *w = shader_watch_open(p.shader_dir, err, sizeof(err));
	CHECK(w != NULL, "shader_watch_open: %s", err);
	struct scene *scene = scene_create(&p, err, sizeof(err));
	struct renderer *r = renderer_create(96, 72, ANTIALIAS_AUTO, err, sizeof(err));
	CHECK(scene && r, "scene and renderer: %s", err);
	struct sink_set sinks = { .n = 0 };
	sinks_add(&sinks, &es.base);
	/* the loop's messages go to stderr: into a file for the check */
	fflush(stderr);
	int saved = dup(2);
	FILE *lf = freopen(logf, "w", stderr);
	CHECK(lf != NULL, "redirect stderr");
	struct frame_loop lp = { .p = &p, .scene = scene, .sinks = &sinks, .r = r, .w = 96, .h = 72, .shaders = w };
	int rc = scene && r ? frame_loop_run(&lp, err, sizeof(err)) : -1;
	fflush(stderr);
	dup2(saved, 2);
	close(saved);
	CHECK(rc == 0, "frame loop: %s", err);
	CHECK(lp.frames == FRAMES, "every frame came (%d of %d), also after the broken edit", lp.frames, FRAMES);

	char *log = slurp(logf);
	char want[64];
	snprintf(want, sizeof(want), "render.frag:%d:", es.broken_line);
	printf("stderr of the run:\n%s", log ? log : "(none)\n");
	CHECK(log && strstr(log, want), "the broken edit is reported as '%s...'", want);
	CHECK(log && strstr(log, "program(s) rebuilt"), "the good edit is reported");
	int d01 = differing(&es.img[0], &es.img[1]), d12 = differing(&es.img[1], &es.img[2]);
	int d23 = differing(&es.img[2], &es.img[3]), d34 = differing(&es.img[3], &es.img[4]);
	int d45 = differing(&es.img[4], &es.img[5]), d56 = differing(&es.img[5], &es.img[6]);
	int d67 = differing(&es.img[6], &es.img[7]);
	printf("pixels changed: 0->1 %d, 1->2 %d (edit), 2->3 %d, 3->4 %d (broken), 4->5 %d, 5->6 %d (density), 6->7 %d\n",
	       d01, d12, d23, d34, d45, d56, d67);
	CHECK(d56 > 96 * 72 / 20 && d67 == 0, "the density edit changes the terrain once (%d, then %d pixels)", d56, d67);
	CHECK(log && !strstr(log, "GL error") && !strstr(log, "GL_INVALID"), "no GL error after the rebuilds");
	CHECK(d01 == 0, "nothing changes between frames without an edit (%d pixels)", d01);
	CHECK(d12 > 96 * 72 / 10, "the edit changes the next frame (%d pixels)", d12);
	CHECK(d23 == 0 && d34 == 0 && d45 == 0, "the broken edit keeps the last good program (%d, %d, %d pixels)", d23,
	      d34, d45);
	free(log);

	sinks_destroy(&sinks);
	renderer_destroy(r);
	scene_destroy(scene);
	shader_watch_close(w);
	shader_set_dir(NULL);
	for (int i = 0; i < FRAMES; i++)
		image_free(&es.img[i]);
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", es.dir);
	if (system(cmd) != 0)
		fprintf(stderr, "warning: could not remove %s\n", es.dir);
	platform_close(plat);
	return tc_done("shader_watch");
}
