/* isoterra — the mesh export sink: the scene's mesh (the volume's last
 * extraction, or the world's blocks: world_read_mesh) as binary PLY at the
 * end of a run that went well, staged until every output is ready; only
 * whole triangles (a mesh clamped at its capacity is said to be). */
#include "sink.h"
#include "core.h"
#include "ply.h"
#include "scene.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct mesh_sink {
	struct sink base;
	char path[PARAM_STR_MAX];
	struct atomic_file af; /* the PLY, staged until commit */
};

static int mesh_frame(struct sink *s, struct sink_frame *fr, char *err, size_t errlen)
{
	(void)s;
	(void)fr;
	(void)err;
	(void)errlen;
	return 0;
}

/* Only whole triangles: a mesh clamped at its vertex capacity holds
 * triangles whose vertices were never written (indices repeated, or past
 * the vertices).  The number left out. */
static uint32_t whole_triangles(struct mesh *m)
{
	uint32_t kept = 0;
	for (uint32_t t = 0; t < m->ntris; t++) {
		const uint32_t *i = m->idx + 3 * (size_t)t;
		if (i[0] == i[1] || i[1] == i[2] || i[0] == i[2] || i[0] >= m->nverts || i[1] >= m->nverts ||
		    i[2] >= m->nverts)
			continue;
		memmove(m->idx + 3 * (size_t)kept++, i, 3 * sizeof(*i));
	}
	uint32_t dropped = m->ntris - kept;
	m->ntris = kept;
	return dropped;
}

static int mesh_finish(struct sink *s, const struct sink_end *end, char *err, size_t errlen)
{
	struct mesh_sink *ms = (struct mesh_sink *)s;
	if (!end->ok || !end->scene)
		return 0;
	struct mesh m;
	if (end->scene->ops->read_mesh(end->scene, &m) < 0) {
		snprintf(err, errlen, "reading the mesh back failed");
		return -1;
	}
	uint32_t dropped = whole_triangles(&m);
	if (dropped)
		log_warn("export_mesh: the mesh was clamped at its capacity: %" PRIu32 " incomplete triangles left out of "
			 "'%s' (raise --max-triangles / --max-vertices)", dropped, ms->path);
	int rc = ply_write_staged(&m, ms->path, &ms->af, err, errlen);
	mesh_free(&m);
	return rc;
}

static int mesh_commit(struct sink *s, char *err, size_t errlen)
{
	struct mesh_sink *ms = (struct mesh_sink *)s;
	return ms->af.tmp ? atomic_commit(&ms->af, ms->path, err, errlen) : 0;
}

static void mesh_destroy(struct sink *s)
{
	struct mesh_sink *ms = (struct mesh_sink *)s;
	atomic_abort(&ms->af);
	free(s);
}

static const struct sink_ops mesh_ops = { .frame = mesh_frame, .finish = mesh_finish, .commit = mesh_commit,
					  .destroy = mesh_destroy };

struct sink *sink_mesh_open(const char *path, char *err, size_t errlen)
{
	struct mesh_sink *ms = calloc(1, sizeof(*ms));
	if (!ms) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	ms->base.ops = &mesh_ops;
	snprintf(ms->path, sizeof(ms->path), "%s", path);
	return &ms->base;
}
