/* isoterra — CPU reference Marching Cubes (plain C), same tables, same
 * vertex ownership and output order as the GPU passes. */
#include "mc.h"
#include "gpu.h" /* abi.h: DEBRIS_SPAN, DEBRIS_BOX */

#include <math.h>
#include <stdlib.h>
#include <string.h>

static float D(const struct grid *g, const float *dens, int i, int j, int k)
{
	return dens[grid_dens_index(g, i, j, k)];
}

static void gradient(const struct grid *g, const float *dens, int i, int j, int k, float out[3])
{
	out[0] = D(g, dens, i + 1, j, k) - D(g, dens, i - 1, j, k);
	out[1] = D(g, dens, i, j + 1, k) - D(g, dens, i, j - 1, k);
	out[2] = D(g, dens, i, j, k + 1) - D(g, dens, i, j, k - 1);
}

/* The raw sign of a stored sample (one beyond them: outside). */
static int raw_inside(const struct grid *g, const float *dens, float iso, int x, int y, int z)
{
	int m = grid_margin(g);
	if (x < -m || y < -m || z < -m || x > g->nx + m || y > g->ny + m || z > g->nz + m)
		return 0;
	return D(g, dens, x, y, z) > iso;
}

static const int nb6[6][3] = { { -1, 0, 0 }, { 1, 0, 0 }, { 0, -1, 0 }, { 0, 1, 0 }, { 0, 0, -1 }, { 0, 0, 1 } };

#define DEBRIS_ROWS (DEBRIS_BOX * DEBRIS_BOX)

/* Debris (shaders/debris_island.glsl, which this mirrors): the 6-connected
 * inside component of the sample at the centre of box (DEBRIS_BOX samples
 * an edge, abi.h; row (dz + S) * B + dy + S holds dx = -S .. S in bits
 * 0 .. B - 1), grown within the box, never reaches the box's faces and
 * spans at most DEBRIS_SPAN samples along each axis.  The growth a fixed
 * point, swept in place as the shader does. */
static int debris_island(const uint32_t box[DEBRIS_ROWS])
{
	enum { B = DEBRIS_BOX, S = DEBRIS_SPAN };
	const uint32_t faces = 1u | 1u << (B - 1);
	uint32_t cur[DEBRIS_ROWS] = { 0 };
	int centre = S * B + S;
	cur[centre] = box[centre] & 1u << S;
	if (!cur[centre])
		return 0; /* an outside centre: no component */
	int settled = 0;
	for (int sweep = 0; sweep <= S * S * S && !settled; sweep++) {
		int grew = 0;
		uint32_t face = 0;
		for (int z = 0; z < B; z++)
			for (int y = 0; y < B; y++) {
				int i = z * B + y;
				uint32_t v = cur[i] | cur[i] << 1 | cur[i] >> 1;
				if (y > 0)
					v |= cur[i - 1];
				if (y < B - 1)
					v |= cur[i + 1];
				if (z > 0)
					v |= cur[i - B];
				if (z < B - 1)
					v |= cur[i + B];
				v &= box[i];
				grew |= v != cur[i];
				cur[i] = v;
				face |= v & faces;
				if (v && (y == 0 || y == B - 1 || z == 0 || z == B - 1))
					face = 1;
			}
		settled = !grew;
		if (face)
			return 0; /* a face reached: more than S samples along an axis */
	}
	if (!settled)
		return 0;
	int xlo = B, xhi = -1, ylo = B, yhi = -1, zlo = B, zhi = -1;
	for (int z = 0; z < B; z++)
		for (int y = 0; y < B; y++)
			for (int x = 0; x < B; x++)
				if (cur[z * B + y] >> x & 1u) {
					xlo = x < xlo ? x : xlo, xhi = x > xhi ? x : xhi;
					ylo = y < ylo ? y : ylo, yhi = y > yhi ? y : yhi;
					zlo = z < zlo ? z : zlo, zhi = z > zhi ? z : zhi;
				}
	return xhi - xlo < S && yhi - ylo < S && zhi - zlo < S;
}

/* Inside: above iso, unless its inside component is debris of a few
 * samples, which would float as a speck or a rock (a single sample of
 * eight triangles, a pair of sixteen, up to a clump of DEBRIS_SPAN^3,
 * abi.h); or below iso with
 * all six neighbours inside (a one-sample bubble, never seen).  The debris
 * filter of shaders/mc_debris.comp, on the raw densities; a sample beyond
 * the stored ones counts as outside. */
int mc_ref_inside(const struct grid *g, const float *dens, float iso, int x, int y, int z)
{
	int count = 0;
	for (int k = 0; k < 6; k++)
		count += raw_inside(g, dens, iso, x + nb6[k][0], y + nb6[k][1], z + nb6[k][2]);
	if (!raw_inside(g, dens, iso, x, y, z))
		return count == 6;
	if (count == 0)
		return 0;
	/* debris spans at most DEBRIS_SPAN samples: along each of the six
	 * directions an outside sample within that many steps */
	for (int k = 0; k < 6; k++) {
		int run = 1;
		for (int t = 1; t <= DEBRIS_SPAN && run; t++)
			run = raw_inside(g, dens, iso, x + t * nb6[k][0], y + t * nb6[k][1], z + t * nb6[k][2]);
		if (run)
			return 1;
	}
	uint32_t box[DEBRIS_ROWS];
	for (int dz = 0; dz < DEBRIS_BOX; dz++)
		for (int dy = 0; dy < DEBRIS_BOX; dy++) {
			uint32_t row = 0;
			for (int dx = 0; dx < DEBRIS_BOX; dx++)
				row |= (uint32_t)raw_inside(g, dens, iso, x + dx - DEBRIS_SPAN, y + dy - DEBRIS_SPAN,
							    z + dz - DEBRIS_SPAN)
				       << dx;
			box[dz * DEBRIS_BOX + dy] = row;
		}
	return !debris_island(box);
}

static int vmask(const struct grid *g, const float *dens, float iso, int x, int y, int z)
{
	if (x > g->nx || y > g->ny || z > g->nz)
		return 0;
	int in0 = mc_ref_inside(g, dens, iso, x, y, z), m = 0;
	if (x < g->nx && y <= g->ny && z <= g->nz && in0 != mc_ref_inside(g, dens, iso, x + 1, y, z))
		m |= 1;
	if (y < g->ny && in0 != mc_ref_inside(g, dens, iso, x, y + 1, z))
		m |= 2;
	if (z < g->nz && in0 != mc_ref_inside(g, dens, iso, x, y, z + 1))
		m |= 4;
	return m;
}

static int cell_case(const struct mc_tables *t, const struct grid *g, const float *dens, float iso, int x, int y, int z)
{
	int cs = 0;
	for (int n = 0; n < 8; n++)
		cs |= mc_ref_inside(g, dens, iso, x + t->corner[n][0], y + t->corner[n][1], z + t->corner[n][2]) << n;
	return cs;
}

/* The vertex on the edge from corner (x, y, z) along axis s: position and
 * normal (the interpolated gradient, pointing out of the rock). */
static void edge_vertex(const struct grid *g, const float *dens, float iso, int x, int y, int z, int s, float pos[3],
			float nrm[3])
{
	int x1 = x + (s == 0), y1 = y + (s == 1), z1 = z + (s == 2);
	float d0 = D(g, dens, x, y, z), d1 = D(g, dens, x1, y1, z1);
	float tt = (d0 - iso) / (d0 - d1);
	float p0[3] = { (float)x, (float)y, (float)z };
	float g0[3], g1[3];
	gradient(g, dens, x, y, z, g0);
	gradient(g, dens, x1, y1, z1, g1);
	float n[3], len = 0.0f;
	for (int a = 0; a < 3; a++) {
		float pa = p0[a] + (a == s ? tt : 0.0f);
		pos[a] = g->origin[a] + pa * g->cell;
		n[a] = g0[a] + (g1[a] - g0[a]) * tt;
		len += n[a] * n[a];
	}
	len = sqrtf(len);
	for (int a = 0; a < 3; a++)
		nrm[a] = len > 1e-20f ? -n[a] / len : (a == 1 ? 1.0f : 0.0f);
}

int mc_ref_extract(const struct grid *g, const float *dens, float iso, struct mesh *out)
{
	struct mc_tables tables;
	mc_tables_build(&tables);
	const struct mc_tables *t = &tables;
	const int ox = g->nx + 1, oy = g->ny + 1, oz = g->nz + 1;
	const size_t owners = (size_t)ox * oy * oz;
	uint32_t *base = malloc(sizeof(uint32_t) * (owners + 1));
	uint8_t *mask = malloc(owners);
	if (!base || !mask) {
		free(base);
		free(mask);
		return -1;
	}
	/* pass 1: vertex ownership and prefix sum; triangle count */
	uint64_t nv = 0, nt = 0;
	for (int z = 0; z < oz; z++)
		for (int y = 0; y < oy; y++)
			for (int x = 0; x < ox; x++) {
				size_t c = (size_t)x + (size_t)ox * ((size_t)y + (size_t)oy * z);
				int m = vmask(g, dens, iso, x, y, z);
				mask[c] = (uint8_t)m;
				base[c] = (uint32_t)nv;
				nv += (uint64_t)((m & 1) + ((m >> 1) & 1) + ((m >> 2) & 1));
				if (x < g->nx && y < g->ny && z < g->nz)
					nt += t->tri_count[cell_case(t, g, dens, iso, x, y, z)];
			}
	if (nv > UINT32_MAX || nt > UINT32_MAX / 3 || mesh_alloc(out, (uint32_t)nv, (uint32_t)nt) < 0) {
		free(base);
		free(mask);
		return -1;
	}
	/* pass 2: vertices */
	uint32_t v = 0;
	for (int z = 0; z < oz; z++)
		for (int y = 0; y < oy; y++)
			for (int x = 0; x < ox; x++) {
				size_t c = (size_t)x + (size_t)ox * ((size_t)y + (size_t)oy * z);
				for (int s = 0; s < 3; s++)
					if (mask[c] & (1 << s)) {
						edge_vertex(g, dens, iso, x, y, z, s, out->pos + 3 * v, out->nrm + 3 * v);
						v++;
					}
			}
	/* pass 3: triangles */
	uint32_t tri = 0;
	for (int z = 0; z < g->nz; z++)
		for (int y = 0; y < g->ny; y++)
			for (int x = 0; x < g->nx; x++) {
				int cs = cell_case(t, g, dens, iso, x, y, z);
				for (int k = 0; k < t->tri_count[cs] * 3; k++) {
					int e = t->tri[cs][k];
					int qx = x + t->edge_owner[e][0], qy = y + t->edge_owner[e][1], qz = z + t->edge_owner[e][2];
					int s = t->edge_owner[e][3];
					size_t c = (size_t)qx + (size_t)ox * ((size_t)qy + (size_t)oy * qz);
					uint32_t rank = 0;
					for (int b = 0; b < s; b++)
						rank += (mask[c] >> b) & 1;
					out->idx[3 * tri + (uint32_t)(k % 3)] = base[c] + rank;
					if (k % 3 == 2)
						tri++;
				}
			}
	free(base);
	free(mask);
	return 0;
}
