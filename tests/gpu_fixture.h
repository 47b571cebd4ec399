/* isoterra tests — a GLES 3.1 context for GPU tests (surfaceless unless
 * ISOTERRA_PLATFORM says otherwise). */
#ifndef ISOTERRA_GPU_FIXTURE_H
#define ISOTERRA_GPU_FIXTURE_H

#include <stdio.h>
#include <stdlib.h>
#include "app.h"

/* The extraction engine's passes, the reason printed on failure: 0 or -1. */
static inline int fixture_report(int rc, const char *pass, const char *err)
{
	if (rc < 0 && err[0])
		fprintf(stderr, "%s: %s\n", pass, err);
	return rc;
}

static inline int fixture_run(struct pipeline *pl, const struct params *p)
{
	char err[512];
	return fixture_report(pipeline_run(pl, p, err, sizeof(err)), "pipeline_run", err);
}

static inline int fixture_density(struct pipeline *pl, const struct params *p)
{
	char err[512];
	return fixture_report(pipeline_density(pl, p, err, sizeof(err)), "pipeline_density", err);
}

/* The tests' small streaming world: the world scene over a view of 40
 * units, block_pool slots, 4 AO rays, no fade-in. */
static inline void fixture_small_world(struct params *p, int block_pool)
{
	params_defaults(p);
	p->scene = 1;
	p->block_pool = block_pool;
	p->view_distance = 40.0f;
	p->ao_rays = 4;
	p->fade_time = 0.0f;
}

/* The terrain's extraction on grid g: its own edit state, the terrain
 * field and a pipeline.  0, or -1 with err (nothing left open). */
struct fixture_terrain {
	struct edits *ed;
	struct terrain *tr;
	struct pipeline *pl;
};
static inline int fixture_terrain_open(struct fixture_terrain *ft, const struct grid *g, const struct params *p,
				       char *err, size_t errlen)
{
	ft->ed = edits_create();
	ft->tr = ft->ed ? terrain_create(ft->ed) : NULL;
	ft->pl = ft->tr ? pipeline_create(g, p, terrain_field(ft->tr), err, errlen) : NULL;
	if (!ft->pl) {
		if (!ft->tr)
			snprintf(err, errlen, "out of memory");
		terrain_destroy(ft->tr);
		edits_destroy(ft->ed);
		return -1;
	}
	return 0;
}
static inline void fixture_terrain_close(struct fixture_terrain *ft)
{
	pipeline_destroy(ft->pl);
	terrain_destroy(ft->tr);
	edits_destroy(ft->ed);
}

static inline struct platform *fixture_open(void)
{
	char err[512];
	const char *name = getenv("ISOTERRA_PLATFORM");
	struct platform_options po = { .name = name && *name ? name : "surfaceless", .width = 64, .height = 64 };
	struct platform *p = platform_open(&po, err, sizeof(err));
	if (!p) {
		fprintf(stderr, "cannot open a GL context: %s\n", err);
		exit(1);
	}
	struct gpu_caps caps;
	if (gpu_init(&caps, false, err, sizeof(err)) < 0) {
		fprintf(stderr, "%s\n", err);
		exit(1);
	}
	printf("GL: %s (%s)\n", caps.renderer, caps.version);
	return p;
}

#endif
