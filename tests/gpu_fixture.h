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

static struct platform *fixture_open(void)
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
