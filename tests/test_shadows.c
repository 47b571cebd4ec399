/* isoterra tests — sun shadows (shaders/sun.glsl) against the CPU.
 *
 * The extraction bakes each vertex's sun visibility from one ray through
 * the density volume.  Here the CPU marches the same ray, from the GPU
 * vertex's position and normal, through the CPU reference of the field
 * (density_ref), in steps of a quarter cell, and classifies the vertex:
 *   - blocked: the ray crosses rock for longer than the GPU's step there
 *     (its steps grow geometrically; a thinner blade may fall between two
 *     of them) -> the GPU's visibility must be dark (<= 0.2);
 *   - open: the ray's clearance stays well outside the penumbra
 *     ((iso - d) >= 2 * shadow_soft * t + a quarter cell everywhere) ->
 *     the GPU's visibility must be full sun (>= 0.8);
 *   - between: the penumbra and the blades, not judged.
 * At most 2 % of either class may disagree (the GPU reads the stored
 * samples trilinearly, the CPU evaluates the field), and both classes must
 * hold enough vertices for the check to mean something.  Then: shadows off
 * (shadows = 0 or shadow_steps = 0) leaves every vertex in full sun.
 *
 * And per pixel, in the picture a viewer sees: the volume scene rendered
 * three times, with shadows, without, and without the sun (nothing else
 * changed, no edge smoothing, no water).  For each pixel the CPU finds the
 * surface point it shows (the pixel's ray through the GPU's stored
 * densities, trilinear, in quarter cells, then bisected: where the mesh
 * is; a surface with no vertex of the mesh within a cell is passed, the
 * debris filter having left that island of rock out of the mesh, so the
 * picture shows what is behind it; none within two cells of the box's
 * sides, where the open volume's mesh is cut) and judges that point's sun
 * ray through the CPU field as
 * above, where the sun faces it (its normal from the field's gradient,
 * n.l >= 0.3) and adds 8 levels of 255 or more to the pixel's luminance
 * (the picture without shadows less the one without the sun).  Blocked:
 * the shadows must take at least half of that away; open: at most 0.15 of
 * it + 2 levels.  A pixel within two pixels of the other class (an open
 * one: of a blocked or between one) is not judged: a triangle blends its
 * vertices' visibility over a cell, about a pixel and a half here, which
 * the point's own ray does not see.  At most 5 % of either class may
 * disagree, and both must hold enough pixels.  (Judged with the sun turned
 * 90 degrees, 77 % and 29 % of the blocked pixels disagree.) */
#include "app.h"
#include "tcheck.h"
#include "gpu_fixture.h"
#include "terrain.h"
#include "density_ref.h"

#include <math.h>
#include <string.h>

struct tally {
	unsigned blocked, blocked_bad, open, open_bad, between;
	double sum_blocked, sum_open; /* mean GPU visibility per class */
};

static void sun_dir(const struct params *p, float l[3])
{
	float el = p->light_el * (float)M_PI / 180.0f, az = p->light_az * (float)M_PI / 180.0f;
	l[0] = cosf(el) * cosf(az);
	l[1] = sinf(el);
	l[2] = cosf(el) * sinf(az);
}

/* The CPU's march of vertex v's ray: 1 blocked, 0 open, -1 between. */
static int classify(const struct params *p, const struct noise_set *ns, const struct grid *g, const float pos[3],
		    const float nrm[3])
{
	float l[3], start[3], lo[3], hi[3];
	sun_dir(p, l);
	int m = grid_margin(g);
	for (int a = 0; a < 3; a++) {
		start[a] = pos[a] + nrm[a] * 0.5f * g->cell;
		lo[a] = g->origin[a] + (float)(g->base[a] - m) * g->cell;
	}
	hi[0] = g->origin[0] + (float)(g->base[0] + g->nx + m) * g->cell;
	hi[1] = g->origin[1] + (float)(g->base[1] + g->ny + m) * g->cell;
	hi[2] = g->origin[2] + (float)(g->base[2] + g->nz + m) * g->cell;
	/* the GPU's steps: t_k = cell * q^k up to the reach */
	float q = powf(fmaxf(p->shadow_reach / g->cell, 1.0f), 1.0f / (float)p->shadow_steps);
	float dt = 0.25f * g->cell, run = 0.0f, run_from = 0.0f;
	bool blocked = false, open = true;
	for (float t = g->cell; t <= p->shadow_reach; t += dt) {
		float x[3];
		bool inside = true;
		for (int a = 0; a < 3; a++) {
			x[a] = start[a] + l[a] * t;
			inside = inside && x[a] >= lo[a] && x[a] <= hi[a];
		}
		if (!inside)
			break; /* a lone volume: open sky beyond its sides */
		float d = density_ref(p, ns, NULL, x[0], x[1], x[2]);
		if (d > p->iso) {
			if (run == 0.0f)
				run_from = t;
			run += dt;
			/* longer than the GPU's step where the run began (and a cell) */
			float step = run_from * (1.0f - 1.0f / q);
			if (run >= 1.5f * fmaxf(step, g->cell))
				blocked = true;
		} else {
			run = 0.0f;
		}
		if (p->iso - d < 2.0f * p->shadow_soft * t + 0.25f * g->cell)
			open = false;
	}
	return blocked ? 1 : open ? 0 : -1;
}

static void judge(const char *what, const struct params *p, const struct noise_set *ns, const struct grid *g,
		  const struct mesh *m, struct tally *t)
{
	memset(t, 0, sizeof(*t));
	for (uint32_t i = 0; i < m->nverts; i += 3) {
		float sun = m->vis[2 * i + 1];
		int c = classify(p, ns, g, m->pos + 3 * i, m->nrm + 3 * i);
		if (c == 1) {
			t->blocked++;
			t->blocked_bad += sun > 0.2f;
			t->sum_blocked += sun;
		} else if (c == 0) {
			t->open++;
			t->open_bad += sun < 0.8f;
			t->sum_open += sun;
		} else {
			t->between++;
		}
	}
	unsigned n = t->blocked + t->open + t->between;
	printf("%s: %u vertices judged: %u blocked (%u lit by the GPU, mean %.3f), %u open (%u shadowed by the GPU, "
	       "mean %.3f), %u between\n",
	       what, n, t->blocked, t->blocked_bad, t->blocked ? t->sum_blocked / t->blocked : 0.0, t->open,
	       t->open_bad, t->open ? t->sum_open / t->open : 0.0, t->between);
	CHECK(t->blocked >= n / 20, "%s: only %u of %u vertices in shadow: the case tests little", what, t->blocked, n);
	CHECK(t->open >= n / 5, "%s: only %u of %u vertices in open sun", what, t->open, n);
	CHECK(t->blocked_bad <= t->blocked / 50, "%s: %u of %u vertices the CPU finds in shadow are lit", what,
	      t->blocked_bad, t->blocked);
	CHECK(t->open_bad <= t->open / 50, "%s: %u of %u vertices the CPU finds in the sun are shadowed", what,
	      t->open_bad, t->open);
}

/* Trilinear density at world point x from the stored samples d of g (the
 * margin included); returns 0 outside them. */
static int dens_at(const struct grid *g, const float *d, const float x[3], float *out)
{
	int m = grid_margin(g), n[3] = { g->nx, g->ny, g->nz }, i[3];
	float f[3];
	for (int a = 0; a < 3; a++) {
		float u = (x[a] - g->origin[a]) / g->cell;
		float fl = floorf(u);
		if (fl < (float)-m || fl >= (float)(n[a] + m))
			return 0;
		i[a] = (int)fl;
		f[a] = u - fl;
	}
	float v = 0.0f;
	for (int c = 0; c < 8; c++) {
		float w = 1.0f;
		for (int a = 0; a < 3; a++)
			w *= (c >> a & 1) ? f[a] : 1.0f - f[a];
		v += w * d[grid_dens_index(g, i[0] + (c & 1), i[1] + (c >> 1 & 1), i[2] + (c >> 2 & 1))];
	}
	*out = v;
	return 1;
}

static float luma(const struct image *im, int x, int y)
{
	const uint8_t *q = im->rgba + 4 * ((size_t)y * (size_t)im->width + (size_t)x);
	return 0.2126f * q[0] + 0.7152f * q[1] + 0.0722f * q[2];
}

/* The cell of g holding world point x, as its index in a byte per cell;
 * -1 outside the cells. */
static long cell_at(const struct grid *g, const float x[3], const int d[3])
{
	int n[3] = { g->nx, g->ny, g->nz }, c[3];
	for (int a = 0; a < 3; a++) {
		c[a] = (int)floorf((x[a] - g->origin[a]) / g->cell) + d[a];
		if (c[a] < 0 || c[a] >= n[a])
			return -1;
	}
	return ((long)c[2] * n[1] + c[1]) * n[0] + c[0];
}

/* Cells within one cell of a vertex of the mesh m: where a surface point
 * of the field is one the mesh has (the debris filter leaves small islands
 * of rock out of it; docs/PIPELINE.md). */
static unsigned char *mesh_cells(const struct grid *g, const struct mesh *m)
{
	unsigned char *near = calloc((size_t)g->nx * (size_t)g->ny * (size_t)g->nz, 1);
	for (uint32_t v = 0; near && v < m->nverts; v++)
		for (int k = 0; k < 27; k++) {
			int d[3] = { k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1 };
			long c = cell_at(g, m->pos + 3 * v, d);
			if (c >= 0)
				near[c] = 1;
		}
	return near;
}

static bool near_mesh(const struct grid *g, const unsigned char *near, const float x[3])
{
	static const int here[3] = { 0, 0, 0 };
	long c = cell_at(g, x, here);
	return c >= 0 && near[c];
}

/* Within two cells of the box's sides, where the open volume's mesh is cut:
 * what a pixel shows there may be the rock's inside. */
static bool near_sides(const struct grid *g, const float x[3])
{
	int n[3] = { g->nx, g->ny, g->nz };
	for (int a = 0; a < 3; a++)
		if (x[a] < g->origin[a] + 2.0f * g->cell || x[a] > g->origin[a] + (float)(n[a] - 2) * g->cell)
			return true;
	return false;
}

/* The picture with and without shadows, judged pixel by pixel (above). */
static void per_pixel(const char *what, struct params p, const struct grid *g, const float *dens,
		      const struct noise_set *ns, const struct mesh *m)
{
	char err[512] = "";
	int w = 160, h = 120;
	snprintf(p.size, sizeof(p.size), "%dx%d", w, h);
	p.count = 1;
	p.water = false;
	CHECK(params_set(&p, "antialias", "off", err, sizeof(err)) == 0, "antialias off: %s", err);
	struct image on = { 0 }, off = { 0 }, dark_sky = { 0 };
	struct params q = p, nosun;
	q.shadows = 0.0f;
	nosun = q;
	nosun.sun = 0.0f;
	CHECK(render_to_image(&p, &on, err, sizeof(err)) == 0, "%s: render with shadows: %s", what, err);
	CHECK(render_to_image(&q, &off, err, sizeof(err)) == 0, "%s: render without: %s", what, err);
	CHECK(render_to_image(&nosun, &dark_sky, err, sizeof(err)) == 0, "%s: render without the sun: %s", what, err);
	if (!on.rgba || !off.rgba || !dark_sky.rgba) {
		image_free(&on), image_free(&off), image_free(&dark_sky);
		return;
	}
	struct camera cam;
	float inv[16], l[3];
	camera_orbit(&cam, &p, g, 0.0f, (float)w / (float)h);
	CHECK(mat4_invert(inv, cam.viewproj) == 0, "%s: the camera's matrix has no inverse", what);
	sun_dir(&p, l);
	unsigned blocked = 0, blocked_bad = 0, open = 0, open_bad = 0, between = 0, sky = 0, edge = 0, faint = 0,
		 skipped = 0;
	unsigned char *near = mesh_cells(g, m);
	double dark_sum = 0.0;
	signed char *cls = malloc((size_t)w * (size_t)h); /* -2 not judged, else classify()'s */
	CHECK(cls != NULL && near != NULL, "out of memory");
	if (!cls || !near) {
		free(cls), free(near);
		image_free(&on), image_free(&off), image_free(&dark_sky);
		return;
	}
	memset(cls, -2, (size_t)w * (size_t)h);
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			/* the pixel's ray: its centre at the near and far planes (row 0 on top) */
			float ndc[2] = { (x + 0.5f) / w * 2.0f - 1.0f, 1.0f - (y + 0.5f) / h * 2.0f }, e[2][3];
			for (int k = 0; k < 2; k++) {
				float c[4] = { ndc[0], ndc[1], k ? 1.0f : -1.0f, 1.0f }, r[4] = { 0 };
				for (int i = 0; i < 4; i++)
					for (int j = 0; j < 4; j++)
						r[i] += inv[j * 4 + i] * c[j];
				for (int i = 0; i < 3; i++)
					e[k][i] = r[i] / r[3];
			}
			float dir[3], len = 0.0f;
			for (int i = 0; i < 3; i++)
				dir[i] = e[1][i] - e[0][i], len += dir[i] * dir[i];
			len = sqrtf(len);
			/* the first surface on the pixel's ray that the mesh has (the
			 * stored densities hold the debris the filter took out of the
			 * mesh: the picture shows what is behind it) */
			float step = 0.25f * g->cell, prev_t = -1.0f, lo = 0.0f, pt[3];
			bool entered = false, in_rock = false, found = false;
			for (float t = 0.0f; t < len && !found; t += step) {
				float at[3] = { e[0][0] + dir[0] / len * t, e[0][1] + dir[1] / len * t,
						e[0][2] + dir[2] / len * t },
				      d;
				if (!dens_at(g, dens, at, &d)) {
					if (entered)
						break; /* out of the volume again */
					continue;
				}
				if (!entered) {
					entered = true;
					if (d > p.iso)
						break; /* entering through rock: the box's cut, not a surface */
				}
				if (d <= p.iso) {
					in_rock = false;
					prev_t = t;
					continue;
				}
				if (in_rock)
					continue;
				in_rock = true;
				float hi = t;
				lo = prev_t;
				for (int it = 0; it < 12; it++) {
					float mid = 0.5f * (lo + hi), dm = p.iso;
					for (int i = 0; i < 3; i++)
						pt[i] = e[0][i] + dir[i] / len * mid;
					dens_at(g, dens, pt, &dm);
					if (dm > p.iso)
						hi = mid;
					else
						lo = mid;
				}
				for (int i = 0; i < 3; i++)
					pt[i] = e[0][i] + dir[i] / len * lo;
				/* near the box's sides the mesh is cut open (an open
				 * volume): what the pixel shows there may be the rock's
				 * inside */
				if (near_sides(g, pt))
					break;
				found = near_mesh(g, near, pt);
				skipped += !found;
			}
			if (!found) {
				sky++;
				continue;
			}
			/* the field's normal there (out of the rock) */
			float n[3], nl = 0.0f, hd = 0.1f * g->cell;
			for (int a = 0; a < 3; a++) {
				float u[3] = { pt[0], pt[1], pt[2] }, v[3] = { pt[0], pt[1], pt[2] };
				u[a] += hd, v[a] -= hd;
				n[a] = -(density_ref(&p, ns, NULL, u[0], u[1], u[2]) - density_ref(&p, ns, NULL, v[0], v[1], v[2]));
				nl += n[a] * n[a];
			}
			nl = sqrtf(nl);
			if (nl < 1e-12f)
				continue;
			float ndl = (n[0] * l[0] + n[1] * l[1] + n[2] * l[2]) / nl;
			if (ndl < 0.3f)
				continue;
			for (int a = 0; a < 3; a++)
				n[a] /= nl;
			cls[y * w + x] = (signed char)classify(&p, ns, g, pt, n);
		}
	/* a pixel is judged where no pixel within RADIUS is of the other
	 * class (or, for an open one, between): a triangle blends its
	 * vertices' visibility over a cell (about a pixel and a half here),
	 * which the point's own ray does not see */
	const int RADIUS = 2;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			int c = cls[y * w + x];
			if (c == -2)
				continue;
			bool same = true;
			for (int dy = -RADIUS; dy <= RADIUS && same; dy++)
				for (int dx = -RADIUS; dx <= RADIUS && same; dx++) {
					int u = x + dx, v = y + dy;
					same = u < 0 || v < 0 || u >= w || v >= h ||
					       (c == 1 ? cls[v * w + u] != 0 : cls[v * w + u] != 1 && cls[v * w + u] != -1);
				}
			if (!same && c >= 0) {
				edge++;
				continue;
			}
			/* what the sun adds to this pixel (the picture without it; the
			 * fog's colour towards the sun changes too, a little), and
			 * what the shadows take away */
			float sun = luma(&off, x, y) - luma(&dark_sky, x, y), dark = luma(&off, x, y) - luma(&on, x, y);
			if (sun < 8.0f) {
				faint++;
				continue;
			}
			if (c == 1) {
				blocked++;
				blocked_bad += dark < 0.5f * sun;
				dark_sum += dark / sun;
			} else if (c == 0) {
				open++;
				open_bad += fabsf(dark) > 0.15f * sun + 2.0f;
			} else {
				between++;
			}
		}
	free(cls);
	free(near);
	printf("%s, per pixel (%dx%d): %u blocked (%u losing less than half the sun's light, mean loss %.2f of it), "
	       "%u open (%u changed by more than 0.15 of it + 2), %u between, %u near the other class (within %d pixels), "
	       "%u where the sun adds under 8 levels, %u sky or near the box's sides; %u surfaces passed that the mesh "
	       "has not (debris)\n",
	       what, w, h, blocked, blocked_bad, blocked ? dark_sum / blocked : 0.0, open, open_bad, between, edge, RADIUS,
	       faint, sky, skipped);
	CHECK(blocked >= 200, "%s: only %u pixels the CPU finds in shadow: the case tests little", what, blocked);
	CHECK(open >= 500, "%s: only %u pixels in open sun", what, open);
	CHECK(blocked_bad <= blocked / 20, "%s: %u of %u pixels the CPU finds in shadow are not darker", what,
	      blocked_bad, blocked);
	CHECK(open_bad <= open / 20, "%s: %u of %u pixels the CPU finds in the sun are changed", what, open_bad, open);
	image_free(&on);
	image_free(&off);
	image_free(&dark_sky);
}

/* Every vertex in full sun (the rays not cast). */
static void all_lit(const char *what, struct fixture_terrain *ft, const struct params *p)
{
	struct mesh m = { 0 };
	CHECK(fixture_run(ft->pl, p) == 0 && pipeline_read_mesh(ft->pl, &m) == 0, "%s: pipeline", what);
	uint32_t dark = 0;
	for (uint32_t i = 0; m.vis && i < m.nverts; i++)
		dark += m.vis[2 * i + 1] < 1.0f;
	CHECK(m.nverts > 1000 && dark == 0, "%s: %u of %u vertices shadowed", what, dark, m.nverts);
	mesh_free(&m);
}

int main(void)
{
	struct platform *plat = fixture_open();
	/* a low sun from two sides, two seeds; AO off (independent of the sun) */
	static const struct {
		int seed;
		float el, az;
	} cases[] = { { 1, 22.0f, 70.0f }, { 5, 30.0f, -120.0f } };
	for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
		struct params p;
		params_defaults(&p);
		p.grid = 64;
		p.seed = cases[c].seed;
		p.light_el = cases[c].el;
		p.light_az = cases[c].az;
		p.ao_rays = 0;
		p.closed = false;
		struct grid g;
		grid_from_params(&g, &p);
		char err[512] = "", what[64];
		snprintf(what, sizeof(what), "seed %d, sun at %.0f/%.0f deg", p.seed, (double)p.light_el,
			 (double)p.light_az);
		struct fixture_terrain ft;
		CHECK(fixture_terrain_open(&ft, &g, &p, err, sizeof(err)) == 0, "pipeline: %s", err);
		if (!ft.pl)
			continue;
		struct mesh m = { 0 };
		CHECK(fixture_run(ft.pl, &p) == 0 && pipeline_read_mesh(ft.pl, &m) == 0, "%s: pipeline", what);
		struct noise_set ns;
		noise_set_init(&ns, p.seed);
		struct tally t;
		if (m.vis)
			judge(what, &p, &ns, &g, &m, &t);
		float *dens = malloc(sizeof(float) * (size_t)grid_dens_count(&g));
		CHECK(dens && pipeline_read_density(ft.pl, dens) == 0, "%s: read density", what);
		if (dens)
			per_pixel(what, p, &g, dens, &ns, &m);
		free(dens);
		mesh_free(&m);
		if (c == 0) {
			struct params q = p;
			q.shadows = 0.0f;
			all_lit("shadows 0", &ft, &q);
			q = p;
			q.shadow_steps = 0;
			all_lit("shadow_steps 0", &ft, &q);
		}
		fixture_terrain_close(&ft);
	}
	platform_close(plat);
	return tc_done("shadows");
}
