/* isoterra tests — a GLES 3.1 context for GPU tests (surfaceless unless
 * ISOTERRA_PLATFORM says otherwise). */
#ifndef ISOTERRA_GPU_FIXTURE_H
#define ISOTERRA_GPU_FIXTURE_H

#include <stdio.h>
#include <stdlib.h>
#include "app.h"

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
