/* isoterra — the set of sinks a run writes to (see sink.h). */
#include "sink.h"

#include <stdio.h>
#include <string.h>

int sinks_add(struct sink_set *set, struct sink *s)
{
	if (!s || set->n == SINK_MAX)
		return -1;
	set->s[set->n++] = s;
	return 0;
}

int sinks_open(struct sink_set *set, const struct params *p, int w, int h, char *err, size_t errlen)
{
	memset(set, 0, sizeof(*set));
	err[0] = 0;
	struct sink *v = sink_v4l2_open(p, w, h, err, errlen);
	if (!v && err[0])
		return 2;
	if (v)
		sinks_add(set, v);
	if (p->export_mesh[0] && sinks_add(set, sink_mesh_open(p->export_mesh, err, errlen)) < 0)
		return 1;
	if (sinks_add(set, sink_file_open(p, w, h, err, errlen)) < 0)
		return 1;
	struct sink *shot = sink_shot_open(p, err, errlen);
	if (!shot)
		return 2;
	if (sinks_add(set, shot) < 0) {
		shot->ops->destroy(shot);
		snprintf(err, errlen, "too many outputs");
		return 1;
	}
	return 0;
}

int sinks_frame(struct sink_set *set, struct sink_frame *fr, char *err, size_t errlen)
{
	int stop = 0;
	for (int i = 0; i < set->n; i++) {
		int q = set->s[i]->ops->frame(set->s[i], fr, err, errlen);
		if (q < 0)
			return -1;
		stop |= q > 0;
	}
	return stop;
}

int sinks_finish(struct sink_set *set, const struct sink_end *end, char *err, size_t errlen)
{
	int rc = 0;
	for (int i = 0; i < set->n; i++) {
		char e[512] = "";
		if (set->s[i]->ops->finish(set->s[i], end, e, sizeof(e)) < 0 && rc == 0) {
			snprintf(err, errlen, "%s", e);
			rc = -1;
		}
	}
	for (int i = 0; rc == 0 && end->ok && i < set->n; i++)
		if (set->s[i]->ops->commit && set->s[i]->ops->commit(set->s[i], err, errlen) < 0)
			rc = -1;
	return rc;
}

const char *sinks_dest(const struct sink_set *set)
{
	for (int i = 0; i < set->n; i++)
		if (set->s[i]->dest)
			return set->s[i]->dest;
	return NULL;
}

void sinks_destroy(struct sink_set *set)
{
	for (int i = set->n - 1; i >= 0; i--)
		set->s[i]->ops->destroy(set->s[i]);
	set->n = 0;
}
