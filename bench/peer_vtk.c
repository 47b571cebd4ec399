/* isoterra — the VTK peer's C side: the volumes into temporary raw files,
 * bench/peer_vtk.py under python3 as a child on two pipes, one line per
 * run (peer_vtk.py describes the protocol). */
#include "peer.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef PEER_VTK_SCRIPT
#define PEER_VTK_SCRIPT "bench/peer_vtk.py"
#endif
#define MAX_VOLS 4

struct peer_vtk {
	pid_t pid;
	FILE *to, *from;
	int nvol;
	char paths[MAX_VOLS][256];
	char info[192];
};

/* A raw float32 copy of vol in a temporary file (its name in path).  0 or -1. */
static int write_volume(const float *vol, size_t n, char *path, size_t len)
{
	const char *dir = getenv("TMPDIR");
	snprintf(path, len, "%s/isoterra-peer-XXXXXX", dir && dir[0] ? dir : "/tmp");
	int fd = mkstemp(path);
	if (fd < 0) {
		path[0] = 0;
		return -1;
	}
	FILE *f = fdopen(fd, "wb");
	if (!f) {
		close(fd);
		return -1;
	}
	size_t w = fwrite(vol, sizeof(float), n, f);
	return fclose(f) == 0 && w == n ? 0 : -1;
}

/* python3 peer_vtk.py ARGS on two pipes.  0 or -1. */
static int spawn(struct peer_vtk *v, char **argv)
{
	int in[2], out[2];
	if (pipe(in) < 0)
		return -1;
	if (pipe(out) < 0) {
		close(in[0]);
		close(in[1]);
		return -1;
	}
	signal(SIGPIPE, SIG_IGN); /* a dead child is read as EOF, not a signal */
	fflush(stdout);
	v->pid = fork();
	if (v->pid == 0) {
		dup2(in[0], 0);
		dup2(out[1], 1);
		close(in[0]);
		close(in[1]);
		close(out[0]);
		close(out[1]);
		execvp(argv[0], argv);
		_exit(127);
	}
	close(in[0]);
	close(out[1]);
	if (v->pid < 0) {
		close(in[1]);
		close(out[0]);
		return -1;
	}
	v->to = fdopen(in[1], "w");
	v->from = fdopen(out[0], "r");
	return v->to && v->from ? 0 : -1;
}

/* Why the child gave no "ready" line (err); its exit status. */
static int child_failed(struct peer_vtk *v, char *err, size_t errlen)
{
	int st = 0;
	if (v->to)
		fclose(v->to);
	v->to = NULL;
	if (v->pid > 0)
		waitpid(v->pid, &st, 0);
	v->pid = 0;
	int code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
	if (code == 3)
		snprintf(err, errlen, "VTK for Python not installed (Debian: python3-vtk9)");
	else if (code == 127)
		snprintf(err, errlen, "python3 not found");
	else
		snprintf(err, errlen, "%s failed (exit status %d)", PEER_VTK_SCRIPT, code);
	return code ? code : -1; /* never 0: 0 means started */
}

/* The child under interpreter py, up to its "vol" lines.  0, or its exit
 * status with err (the child reaped). */
static int start(struct peer_vtk *v, const char *py, char **argv, char *err, size_t errlen)
{
	char line[256], ver[64], backend[64];
	int nthr = 0;
	argv[0] = (char *)py;
	if (spawn(v, argv) < 0 || !fgets(line, sizeof(line), v->from) ||
	    sscanf(line, "ready %63s %63s %d", ver, backend, &nthr) != 3)
		return child_failed(v, err, errlen);
	snprintf(v->info, sizeof(v->info), "VTK %s under %s, SMP backend %s, %d threads", ver, py, backend, nthr);
	for (int k = 0; k < v->nvol; k++)
		if (!fgets(line, sizeof(line), v->from) || strncmp(line, "vol ", 4))
			return child_failed(v, err, errlen);
	return 0;
}

static void drop_pipes(struct peer_vtk *v)
{
	if (v->to)
		fclose(v->to);
	if (v->from)
		fclose(v->from);
	v->to = v->from = NULL;
}

struct peer_vtk *peer_vtk_open(const float *const *vols, int nvol, const int dims[3], float iso, int threads,
			       char *err, size_t errlen)
{
	struct peer_vtk *v = calloc(1, sizeof(*v));
	if (!v || nvol < 1 || nvol > MAX_VOLS) {
		snprintf(err, errlen, "out of memory");
		free(v);
		return NULL;
	}
	char num[5][32];
	char *argv[7 + MAX_VOLS + 1] = { NULL, PEER_VTK_SCRIPT, num[0], num[1], num[2], num[3], num[4] };
	snprintf(num[0], sizeof(num[0]), "%d", dims[0]);
	snprintf(num[1], sizeof(num[1]), "%d", dims[1]);
	snprintf(num[2], sizeof(num[2]), "%d", dims[2]);
	snprintf(num[3], sizeof(num[3]), "%.9g", iso);
	snprintf(num[4], sizeof(num[4]), "%d", threads);
	size_t n = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2];
	for (int k = 0; k < nvol; k++, v->nvol++) {
		if (write_volume(vols[k], n, v->paths[k], sizeof(v->paths[k])) < 0) {
			snprintf(err, errlen, "cannot write a temporary volume file");
			peer_vtk_close(v);
			return NULL;
		}
		argv[7 + k] = v->paths[k];
	}
	/* Debian's python3-vtk9 is for Debian's interpreter, which a python3
	 * earlier on PATH (a virtual environment, pyenv) may hide */
	static const char *const pythons[] = { "/usr/bin/python3", "python3" };
	for (size_t i = 0; i < sizeof(pythons) / sizeof(pythons[0]); i++) {
		int code = start(v, pythons[i], argv, err, errlen);
		if (code == 0)
			return v;
		drop_pipes(v);
		if (code != 3 && code != 127) /* VTK is there but failed: say why */
			break;
	}
	peer_vtk_close(v);
	return NULL;
}

const char *peer_vtk_info(const struct peer_vtk *v)
{
	return v->info;
}

int peer_vtk_run(struct peer_vtk *v, int k, double *wall_ms, double *cpu_ms, long *triangles, long *points)
{
	char line[256];
	int kk;
	if (!v->to || fprintf(v->to, "run %d\n", k) < 0 || fflush(v->to) != 0 || !fgets(line, sizeof(line), v->from))
		return -1;
	if (sscanf(line, "%d %lf %lf %ld %ld", &kk, wall_ms, cpu_ms, triangles, points) != 5 || kk != k) {
		fprintf(stderr, "peer_vtk: unexpected answer: %s", line);
		return -1;
	}
	return 0;
}

void peer_vtk_close(struct peer_vtk *v)
{
	if (!v)
		return;
	if (v->to)
		fclose(v->to); /* EOF: the child exits */
	if (v->from)
		fclose(v->from);
	if (v->pid > 0)
		waitpid(v->pid, NULL, 0);
	for (int k = 0; k < v->nvol; k++)
		if (v->paths[k][0])
			unlink(v->paths[k]);
	free(v);
}
