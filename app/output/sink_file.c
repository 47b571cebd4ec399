/* isoterra — file sinks: one PNG (the last frame), a PNG sequence (every
 * frame), a Y4M stream (file or stdout); and the memory sink of
 * render_to_image.  See sink.h. */
#include "sink.h"
#include "params.h"
#include "render.h"
#include "y4m.h"
#include "y4m_thread.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* A frame written to a temp file beside its target, renamed at commit. */
struct staged {
	struct atomic_file af;
	char *path;
};

struct file_sink {
	struct sink base;
	enum cli_out_kind kind;
	char name[PARAM_STR_MAX]; /* --out: a name, a pattern, or - */
	struct y4m y;
	struct y4m_thread *wt;    /* Y4M: converts and writes beside the next frame */
	bool y4m_open, progress;
	struct staged *st;        /* PNG: the last frame; sequence: every frame */
	int nst, cap;
};

/* [#####     ] 3/10 on stderr for each frame done. */
static void progress(int f, int count)
{
	int width = 40, done = (f + 1) * width / count;
	fprintf(stderr, "\r[%.*s%*s] %d/%d", done, "########################################", width - done, "", f + 1,
		count);
	if (f + 1 == count)
		fputc('\n', stderr);
}

static void unstage_all(struct file_sink *fs)
{
	for (int i = 0; i < fs->nst; i++) {
		atomic_abort(&fs->st[i].af);
		free(fs->st[i].path);
	}
	fs->nst = 0;
}

/* The frame as a PNG into a temp file beside its name (the sequence's
 * number in it); a single PNG replaces the frame staged before. */
static int stage_png(struct file_sink *fs, const struct image *img, int f, char *err, size_t errlen)
{
	char name[PATH_MAX];
	if (cli_numbered_name(fs->name, f, name, sizeof(name)) < 0) {
		snprintf(err, errlen, "--out '%s': no room for frame %d's name", fs->name, f);
		return -1;
	}
	if (fs->kind == CLI_OUT_PNG)
		unstage_all(fs);
	if (fs->nst == fs->cap) {
		int cap = fs->cap ? 2 * fs->cap : 16;
		struct staged *ns = realloc(fs->st, sizeof(*ns) * (size_t)cap);
		if (!ns) {
			snprintf(err, errlen, "out of memory");
			return -1;
		}
		fs->st = ns;
		fs->cap = cap;
	}
	struct staged *st = &fs->st[fs->nst];
	if (!(st->path = strdup(name))) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	if (image_write_png_staged(img, name, &st->af, err, errlen) < 0) {
		free(st->path);
		return -1;
	}
	fs->nst++;
	return 0;
}

static int write_frame(struct file_sink *fs, struct renderer *r, int f, char *err, size_t errlen)
{
	struct image img = { 0 };
	if (renderer_read(r, &img) < 0) {
		snprintf(err, errlen, "reading the frame back failed");
		return -1;
	}
	int rc;
	if (fs->kind == CLI_OUT_Y4M) {
		/* the pixels go to the writer thread; an earlier frame's failure
		 * comes back here (or at the finish) */
		rc = y4m_thread_put(fs->wt, &img, f, fs->name, err, errlen);
	} else {
		rc = stage_png(fs, &img, f, err, errlen);
		if (rc == 0 && fs->kind == CLI_OUT_PNG)
			fs->base.dest = fs->name; /* the last frame is in the file */
	}
	image_free(&img);
	return rc;
}

static int file_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	struct file_sink *fs = (struct file_sink *)s;
	if (fs->kind != CLI_OUT_PNG || fr->last) {
		if (write_frame(fs, fr->r, fr->number, err, errlen) < 0) {
			if (fs->progress && fr->index > 0)
				fputc('\n', stderr); /* the error on a line of its own */
			return -1;
		}
	}
	if (fs->progress && fr->count > 0)
		progress(fr->index, fr->count);
	return 0;
}

static int file_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	struct file_sink *fs = (struct file_sink *)s;
	(void)end;
	if (!fs->y4m_open)
		return 0;
	if (y4m_thread_drain(fs->wt, fs->name, err, errlen) < 0)
		return -1;
	return y4m_finish(&fs->y, fs->name, err, errlen);
}

static int file_commit(struct sink *s, char *err, size_t errlen)
{
	struct file_sink *fs = (struct file_sink *)s;
	if (fs->y4m_open)
		return y4m_commit(&fs->y, fs->name, err, errlen);
	for (int i = 0; i < fs->nst; i++)
		if (atomic_commit(&fs->st[i].af, fs->st[i].path, err, errlen) < 0)
			return -1;
	return 0;
}

static void file_destroy(struct sink *s)
{
	struct file_sink *fs = (struct file_sink *)s;
	y4m_thread_stop(fs->wt); /* (the frame in flight written first) */
	if (fs->y4m_open)
		y4m_free(&fs->y);
	unstage_all(fs);
	free(fs->st);
	free(fs);
}

static const struct sink_ops file_ops = { .frame = file_frame, .finish = file_finish, .commit = file_commit,
					  .destroy = file_destroy };

struct sink *sink_file_open(const struct params *p, int w, int h, char *err, size_t errlen)
{
	struct file_sink *fs = calloc(1, sizeof(*fs));
	if (!fs) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	fs->base.ops = &file_ops;
	snprintf(fs->name, sizeof(fs->name), "%s", p->out);
	if (cli_parse_out(p->out, &fs->kind, err, errlen) < 0) {
		free(fs);
		return NULL;
	}
	fs->progress = p->count > 1 && isatty(2);
	if (fs->kind != CLI_OUT_PNG)
		fs->base.dest = fs->name; /* a stream or a sequence: named whatever it holds */
	if (fs->kind == CLI_OUT_Y4M) {
		if (y4m_open(&fs->y, p->out, w, h, p->fps, err, errlen) < 0) {
			free(fs);
			return NULL;
		}
		fs->y4m_open = true;
		if (!(fs->wt = y4m_thread_start(&fs->y, err, errlen))) {
			y4m_free(&fs->y);
			free(fs);
			return NULL;
		}
	}
	return &fs->base;
}

/* ---- memory: the last frame into an image ------------------------------------ */
struct memory_sink {
	struct sink base;
	struct image *img;
};

static int memory_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	struct memory_sink *ms = (struct memory_sink *)s;
	if (!fr->last)
		return 0;
	image_free(ms->img);
	if (renderer_read(fr->r, ms->img) < 0) {
		snprintf(err, errlen, "reading the frame back failed");
		return -1;
	}
	return 0;
}

static int memory_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	(void)s;
	(void)end;
	(void)err;
	(void)errlen;
	return 0;
}

static void memory_destroy(struct sink *s)
{
	free(s);
}

static const struct sink_ops memory_ops = { .frame = memory_frame, .finish = memory_finish, .destroy = memory_destroy };

struct sink *sink_memory_open(struct image *img, char *err, size_t errlen)
{
	struct memory_sink *ms = calloc(1, sizeof(*ms));
	if (!ms) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	ms->base.ops = &memory_ops;
	ms->img = img;
	return &ms->base;
}
