/* isoterra — the pipeline benchmark's peers, outside isoterra: libnoise
 * 1.0's Perlin module (peer_libnoise.cpp, built when Debian's libnoise-dev
 * is installed; peer_libnoise_none.c otherwise) and VTK's
 * vtkFlyingEdges3D (peer_vtk.c runs bench/peer_vtk.py under python3 when
 * python3-vtk9 is installed).  Bench-only, optional. */
#ifndef ISOTERRA_PEER_H
#define ISOTERRA_PEER_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* d(x, y, z) = -slope * y + amp * Perlin(x, y, z) at origin + (i, j, k) *
 * cell, dims[0] x dims[1] x dims[2] samples, x fastest; Perlin: libnoise's
 * module (QUALITY_BEST: quintic fade) with these octaves, frequency,
 * lacunarity, persistence and seed. */
struct peer_fbm {
	int octaves, seed;
	double freq, lacunarity, persistence;
	double amp, slope;
	double origin[3], cell;
	int dims[3];
	int threads;
};

/* NULL when libnoise is built in, else a line that says it is not. */
const char *peer_libnoise_missing(void);
/* Fills the volume with `threads` threads (slabs of z).  0, or -1. */
int peer_libnoise_volume(const struct peer_fbm *f, float *out);
/* The standard deviation of one octave of the basis (frequency 1) over n
 * pseudo-random points in a 256-cell cube. */
double peer_libnoise_basis_std(int seed, int n);

/* VTK's flying edges, in a python3 child fed through a pipe: nvol raw
 * float32 volumes of dims (x fastest) contoured at iso with normals, on
 * `threads` threads of VTK's SMP backend. */
struct peer_vtk;
/* NULL with err: the reason (python3-vtk9 not installed, ...). */
struct peer_vtk *peer_vtk_open(const float *const *vols, int nvol, const int dims[3], float iso, int threads,
			       char *err, size_t errlen);
/* "VTK 9.1.0, SMP backend X, N threads" */
const char *peer_vtk_info(const struct peer_vtk *v);
/* One timed Update() of volume k (the child's wall and CPU ms); its
 * triangle and point counts.  0, or -1. */
int peer_vtk_run(struct peer_vtk *v, int k, double *wall_ms, double *cpu_ms, long *triangles, long *points);
void peer_vtk_close(struct peer_vtk *v);

#ifdef __cplusplus
}
#endif

#endif
