/* isoterra — Marching Cubes tables, generated from the cube's geometry.
 *
 * For every case the isosurface crosses the edges whose corners differ.  On
 * each cube face, walking the face's corners counter-clockwise seen from
 * outside, an edge going inside->outside is an "exit" and outside->inside an
 * "entry"; each entry is joined to the next exit along the walk.  That joins
 * around the inside corners, so on an ambiguous face (two diagonal inside
 * corners) the inside corners are separated.  The rule only looks at the
 * face's four corners, so the two cells sharing a face always make the same
 * choice: no cracks.  Every crossing edge is an entry on one of its faces
 * and an exit on the other, so the joins form closed, consistently oriented
 * loops; each loop becomes a triangle fan. */
#include "mc.h"

#include <stdlib.h>
#include <string.h>

static const int8_t corners[8][3] = {
	{ 0, 0, 0 }, { 0, 1, 0 }, { 1, 1, 0 }, { 1, 0, 0 }, { 0, 0, 1 }, { 0, 1, 1 }, { 1, 1, 1 }, { 1, 0, 1 },
};
static const int8_t edges[12][2] = {
	{ 0, 1 }, { 1, 2 }, { 2, 3 }, { 3, 0 }, { 4, 5 }, { 5, 6 }, { 6, 7 }, { 7, 4 },
	{ 0, 4 }, { 1, 5 }, { 2, 6 }, { 3, 7 },
};

static int edge_of(int a, int b)
{
	for (int e = 0; e < 12; e++)
		if ((edges[e][0] == a && edges[e][1] == b) || (edges[e][0] == b && edges[e][1] == a))
			return e;
	abort();
}

/* The 4 corners of face (axis, side), counter-clockwise seen from outside. */
static void face_corners(int axis, int side, int out[4])
{
	/* (u, v) basis in the face plane with u x v = outward normal */
	int u = (axis + 1) % 3, v = (axis + 2) % 3;
	if (!side) {
		int t = u;
		u = v;
		v = t;
	}
	/* corners (0,0) (1,0) (1,1) (0,1) in (u, v) are CCW around +u x v */
	static const int uv[4][2] = { { 0, 0 }, { 1, 0 }, { 1, 1 }, { 0, 1 } };
	for (int k = 0; k < 4; k++) {
		int pos[3];
		pos[axis] = side;
		pos[u] = uv[k][0];
		pos[v] = uv[k][1];
		for (int c = 0; c < 8; c++)
			if (corners[c][0] == pos[0] && corners[c][1] == pos[1] && corners[c][2] == pos[2])
				out[k] = c;
	}
}

/* Bit f of face_sets[e] is set when edge e lies on face f. */
static int shares_face(const int *face_sets, int a, int b)
{
	return (face_sets[a] & face_sets[b]) != 0;
}

/* Triangulates the polygon v[0..n-1] (keeping its orientation) so that no
 * diagonal joins two vertices on a common cube face: such a chord lies in
 * the face the neighbouring cell shares, and if that cell drew the same
 * chord the edge would have four triangles.  Returns 1 on success. */
static int triangulate(const int *v, int n, const int *face_sets, int tris[][3], int *nt)
{
	if (n < 3)
		return 1;
	if (n == 3) {
		tris[*nt][0] = v[0];
		tris[*nt][1] = v[1];
		tris[*nt][2] = v[2];
		(*nt)++;
		return 1;
	}
	/* the triangle on edge (v[n-1], v[0]) has apex v[k] */
	for (int k = 1; k < n - 1; k++) {
		if (k != 1 && shares_face(face_sets, v[0], v[k]))
			continue;
		if (k != n - 2 && shares_face(face_sets, v[k], v[n - 1]))
			continue;
		int save = *nt;
		tris[*nt][0] = v[0];
		tris[*nt][1] = v[k];
		tris[*nt][2] = v[n - 1];
		(*nt)++;
		if (triangulate(v, k + 1, face_sets, tris, nt) && triangulate(v + k, n - k, face_sets, tris, nt))
			return 1;
		*nt = save;
	}
	return 0;
}

void mc_tables_build(struct mc_tables *t)
{
	memcpy(t->corner, corners, sizeof(corners));
	memcpy(t->edge_corner, edges, sizeof(edges));
	for (int e = 0; e < 12; e++) {
		int a = edges[e][0], b = edges[e][1];
		int lo = a, axis = 0;
		for (int i = 0; i < 3; i++) {
			if (corners[a][i] != corners[b][i]) {
				axis = i;
				lo = corners[a][i] < corners[b][i] ? a : b;
			}
		}
		t->edge_owner[e][0] = corners[lo][0];
		t->edge_owner[e][1] = corners[lo][1];
		t->edge_owner[e][2] = corners[lo][2];
		t->edge_owner[e][3] = (int8_t)axis;
	}
	int fc[6][4];
	int face_sets[12] = { 0 };
	for (int f = 0; f < 6; f++) {
		face_corners(f / 2, f % 2, fc[f]);
		for (int k = 0; k < 4; k++)
			face_sets[edge_of(fc[f][k], fc[f][(k + 1) & 3])] |= 1 << f;
	}

	for (int cs = 0; cs < 256; cs++) {
		int next[12];
		for (int e = 0; e < 12; e++)
			next[e] = -1;
		for (int f = 0; f < 6; f++) {
			int in[4], fe[4];
			for (int k = 0; k < 4; k++) {
				in[k] = (cs >> fc[f][k]) & 1;
				fe[k] = edge_of(fc[f][k], fc[f][(k + 1) & 3]);
			}
			for (int k = 0; k < 4; k++) {
				if (in[k] || !in[(k + 1) & 3])
					continue; /* not an entry */
				for (int j = 1; j < 4; j++) {
					int m = (k + j) & 3;
					if (in[m] && !in[(m + 1) & 3]) {
						next[fe[k]] = fe[m];
						break;
					}
				}
			}
		}
		int used[12] = { 0 }, ntri = 0;
		for (int e0 = 0; e0 < 12; e0++) {
			if (next[e0] < 0 || used[e0])
				continue;
			int loop[12], n = 0;
			for (int e = e0; !used[e]; e = next[e]) {
				used[e] = 1;
				loop[n++] = e;
				if (next[e] < 0)
					abort(); /* open chain: impossible by construction */
			}
			int tris[12][3], nt = 0;
			if (!triangulate(loop, n, face_sets, tris, &nt))
				abort(); /* no triangulation without face chords */
			for (int i = 0; i < nt; i++) {
				if (ntri >= MC_MAX_TRIS)
					abort();
				/* loops run counter-clockwise seen from the air side */
				for (int j = 0; j < 3; j++)
					t->tri[cs][ntri * 3 + j] = (int8_t)tris[i][j];
				ntri++;
			}
		}
		t->tri_count[cs] = (uint8_t)ntri;
		for (int i = ntri * 3; i < MC_MAX_TRIS * 3; i++)
			t->tri[cs][i] = -1;
	}
}
