/* isoterra — the screenshot sink: the frame the controls asked for (a
 * button, a key: sink_frame.screenshot) read back and written to the next
 * numbered name of p->screenshot, OSD included.  A screenshot that cannot
 * be written is a warning: the run goes on.  A name that cannot number its
 * files is refused at open. */
#include "sink.h"
#include "params.h"
#include "core.h"
#include "render.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct shot_sink {
	struct sink base;
	char name[PARAM_STR_MAX];
	int n; /* the next number */
};

static int shot_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	struct shot_sink *ss = (struct shot_sink *)s;
	if (!fr->screenshot)
		return 0;
	char name[PATH_MAX], e[512];
	if (cli_numbered_name(ss->name, ss->n++, name, sizeof(name)) < 0) {
		log_warn("screenshot: no room for number %d in '%s'", ss->n - 1, ss->name);
		return 0;
	}
	struct image img = { 0 };
	if (renderer_read(fr->r, &img) < 0) {
		snprintf(err, errlen, "screenshot: reading the frame back failed");
		return -1;
	}
	if (image_write_png(&img, name, e, sizeof(e)) < 0)
		log_warn("screenshot: %s", e);
	else
		log_info("screenshot: %s", name);
	image_free(&img);
	return 0;
}

static int shot_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	(void)s;
	(void)end;
	(void)err;
	(void)errlen;
	return 0;
}

static void shot_destroy(struct sink *s)
{
	free(s);
}

static const struct sink_ops shot_ops = { .frame = shot_frame, .finish = shot_finish, .destroy = shot_destroy };

struct sink *sink_shot_open(const struct params *p, char *err, size_t errlen)
{
	char buf[PATH_MAX];
	size_t sl = strlen(p->screenshot);
	if (cli_numbered_name(p->screenshot, 0, buf, sizeof(buf)) == -1 || sl < 5 ||
	    strcmp(p->screenshot + sl - 4, ".png")) {
		snprintf(err, errlen, "screenshot: '%s' must end in .png with at most one %%d (or %%0Nd)",
			 p->screenshot);
		return NULL;
	}
	struct shot_sink *ss = calloc(1, sizeof(*ss));
	if (!ss) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	ss->base.ops = &shot_ops;
	snprintf(ss->name, sizeof(ss->name), "%s", p->screenshot);
	return &ss->base;
}
