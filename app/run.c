/* isoterra — the main job: headless frames of the terrain to PNG. */
#include "render.h"
#include "cli.h"
#include "gpu.h"
#include "log.h"
#include "ply.h"
#include "platform.h"
#include "display.h" /* issue 4: display platforms */

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "frame%04d.png" style names: the out parameter may hold one %d. */
static int frame_name(const char *pattern, int frame, char *buf, size_t len)
{
	const char *pc = strchr(pattern, '%');
	if (!pc) {
		snprintf(buf, len, "%s", pattern);
		return 0;
	}
	/* allow %d, %0Nd only */
	const char *q = pc + 1;
	while (*q >= '0' && *q <= '9')
		q++;
	if (*q != 'd' || strchr(q + 1, '%'))
		return -1;
	char fmt[32];
	snprintf(fmt, sizeof(fmt), "%%.%ds%%%.*s%%s", (int)(pc - pattern), (int)(q - pc), pc + 1);
	snprintf(buf, len, fmt, pattern, frame, q + 1);
	return 1;
}

int run_headless(const struct params *p_in)
{
	struct params p = *p_in;
	char err[512] = "";
	int w, h;
	if (cli_parse_size(p.size, &w, &h) < 0) {
		log_error("--size '%s' is not WxH", p.size);
		return 2;
	}
	char name[PARAM_STR_MAX + 32];
	int per_frame = frame_name(p.out, 0, name, sizeof(name));
	if (per_frame < 0) {
		log_error("--out '%s': only one %%d (or %%0Nd) is allowed in the file name", p.out);
		return 2;
	}
	log_set_level(p.verbose ? LOG_DEBUG : LOG_INFO);
	shader_set_dir(p.shader_dir);

	struct platform_options po = { .name = p.platform, .width = w, .height = h, .debug = p.verbose,
		.fullscreen = p.fullscreen, .hide_cursor = p.hide_cursor, .drm_device = p.drm_device,
		.mode = p.mode, .kms_legacy = p.kms_legacy };
	struct platform *plat = platform_open(&po, err, sizeof(err));
	if (!plat) {
		log_error("%s", err);
		return 1;
	}
	int rc = 1;
	struct pipeline *pl = NULL;
	struct renderer *r = NULL;
	/* issue 4: display platforms render at the window's / mode's size */
	struct display_loop disp;
	display_begin(&disp, plat, &p);
	if (plat->headless && p.count == 0) {
		log_error("--count 0 (until closed) needs a display platform (gbm, wayland, x11), not '%s'",
			  plat->backend->name);
		goto out;
	}
	if (!plat->headless) {
		w = plat->width;
		h = plat->height;
	}
	struct gpu_caps caps;
	if (gpu_init(&caps, p.verbose, err, sizeof(err)) < 0) {
		log_error("%s", err);
		goto out;
	}
	log_debug("platform %s on %s", plat->backend->name, plat->device_desc);
	struct grid g;
	grid_from_params(&g, &p);
	pl = pipeline_create(&g, &p, err, sizeof(err));
	if (!pl) {
		log_error("%s", err);
		goto out;
	}
	r = renderer_create(w, h, err, sizeof(err));
	if (!r) {
		log_error("%s", err);
		goto out;
	}
	struct pipeline_draw d;
	struct camera cam;
	float t0 = p.time;
	int frames = 0;
	for (int f = 0; p.count == 0 || f < p.count; f++, frames++) {
		float t = (float)f / p.fps;
		p.time = t0 + t;
		if (pipeline_run(pl, &p) < 0)
			goto out;
		pipeline_draw_info(pl, &d);
		camera_orbit(&cam, &p, &g, t, (float)w / (float)h);
		if (renderer_draw(r, &d, &cam, &p) < 0)
			goto out;
		if (per_frame || f == p.count - 1) {
			struct image img = { 0 };
			frame_name(p.out, f, name, sizeof(name));
			if (renderer_read(r, &img) < 0) {
				log_error("reading the frame back failed");
				goto out;
			}
			int wr = image_write_png(&img, name, err, sizeof(err));
			image_free(&img);
			if (wr < 0) {
				log_error("%s", err);
				goto out;
			}
		}
		if (!plat->headless) { /* issue 4: blit, present, events, signals */
			int q = display_frame(&disp, plat, &r, &w, &h);
			if (q < 0)
				goto out;
			if (q > 0) {
				frames++;
				break;
			}
		} else if (platform_present(plat) < 0) {
			log_error("presenting the frame failed");
			goto out;
		}
	}
	struct extract_stats st;
	if (pipeline_read_stats(pl, &st) == 0) {
		if (st.overflow)
			log_warn("mesh capacity exceeded: the field needs %llu triangles / %llu vertices, capacity %u / %u; "
				 "output clamped (raise --max-triangles / --max-vertices)",
				 (unsigned long long)st.triangles_needed, (unsigned long long)st.vertices_needed,
				 st.triangle_capacity, st.vertex_capacity);
		log_info("%d frame(s) %dx%d, grid %d^3: %u triangles, %u vertices -> %s", frames, w, h, p.grid,
			 st.triangles, st.vertices,
			 per_frame ? p.out : frames == p.count ? name : "(stopped early: no image)");
	}
	if (p.export_mesh[0]) {
		struct mesh m;
		if (pipeline_read_mesh(pl, &m) < 0) {
			log_error("reading the mesh back failed");
			goto out;
		}
		int wr = ply_write(&m, p.export_mesh, err, sizeof(err));
		mesh_free(&m);
		if (wr < 0) {
			log_error("%s", err);
			goto out;
		}
	}
	rc = 0;
out:
	renderer_destroy(r);
	pipeline_destroy(pl);
	platform_close(plat);
	display_end(&disp);
	return rc;
}

int render_to_image(const struct params *p_in, struct image *img, char *err, size_t errlen)
{
	struct params p = *p_in;
	int w, h;
	memset(img, 0, sizeof(*img));
	if (cli_parse_size(p.size, &w, &h) < 0) {
		snprintf(err, errlen, "--size '%s' is not WxH", p.size);
		return -1;
	}
	struct grid g;
	grid_from_params(&g, &p);
	struct pipeline *pl = pipeline_create(&g, &p, err, errlen);
	if (!pl)
		return -1;
	struct renderer *r = renderer_create(w, h, err, errlen);
	int rc = -1;
	if (r) {
		struct pipeline_draw d;
		struct camera cam;
		float t0 = p.time;
		rc = 0;
		for (int f = 0; f < p.count && rc == 0; f++) {
			float t = (float)f / p.fps;
			p.time = t0 + t;
			rc = pipeline_run(pl, &p);
			pipeline_draw_info(pl, &d);
			camera_orbit(&cam, &p, &g, t, (float)w / (float)h);
			if (rc == 0)
				rc = renderer_draw(r, &d, &cam, &p);
		}
		if (rc == 0)
			rc = renderer_read(r, img);
		if (rc < 0)
			snprintf(err, errlen, "rendering failed (see the log)");
	}
	renderer_destroy(r);
	pipeline_destroy(pl);
	return rc;
}
