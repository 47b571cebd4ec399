/* isoterra — the service manager's notifications end to end: the program
 * runs with NOTIFY_SOCKET naming this test's own datagram socket (as
 * systemd runs a Type=notify unit) and WATCHDOG_USEC=200000, its Y4M
 * frames going to a pipe this test reads.  Checked: READY=1 once, after
 * the first frame; WATCHDOG=1 with a STATUS= line while frames complete;
 * when the test stops reading the pipe (the frame loop blocks in its
 * write: a real stall of a live process), the pings stop and the frames
 * they report are only those the pipe took; reading again brings them
 * back; SIGTERM ends with STOPPING=1. */
#define _GNU_SOURCE /* F_SETPIPE_SZ */
#include "tcheck.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdbool.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define FRAME_BYTES (6 + 64 * 48 * 3 / 2) /* "FRAME\n" + 4:2:0 at 64x48 */

struct watch {
	int sock, out;           /* the notify socket, the program's stdout */
	bool reading;            /* draining stdout (else the loop stalls) */
	long long bytes;         /* read from stdout */
	int msgs, ready, pings, stopping;
	int first_ready_frames;  /* STATUS frames in the READY=1 message */
	int frames;              /* the last STATUS frame count */
	bool status_missing, frames_back;
};

/* One notification or a stdout read within timeout_ms: 1 message, 0
 * stdout or nothing, -1 error. */
static int step(struct watch *w, int timeout_ms)
{
	struct pollfd pf[2] = { { w->sock, POLLIN, 0 }, { w->out, POLLIN, 0 } };
	int n = poll(pf, w->reading && w->out >= 0 ? 2 : 1, timeout_ms);
	if (n < 0)
		return errno == EINTR ? 0 : -1;
	if (w->reading && w->out >= 0 && (pf[1].revents & (POLLIN | POLLHUP))) {
		char buf[65536];
		ssize_t r = read(w->out, buf, sizeof(buf));
		if (r > 0)
			w->bytes += r;
		else if (r == 0)
			w->out = -1;
	}
	if (!(pf[0].revents & POLLIN))
		return 0;
	char msg[512];
	ssize_t r = recv(w->sock, msg, sizeof(msg) - 1, 0);
	if (r < 0)
		return -1;
	msg[r] = 0;
	w->msgs++;
	const char *st = strstr(msg, "STATUS=");
	int frames = -1;
	if (!st || sscanf(st, "STATUS=%d frames", &frames) != 1)
		w->status_missing = true;
	if (frames < w->frames)
		w->frames_back = true;
	w->frames = frames;
	if (strstr(msg, "READY=1")) {
		if (w->ready++ == 0)
			w->first_ready_frames = frames;
		CHECK(w->msgs == 1, "READY=1 is the first message");
	}
	w->pings += strstr(msg, "WATCHDOG=1") != NULL;
	w->stopping += strstr(msg, "STOPPING=1") != NULL;
	return 1;
}

/* Milliseconds on the monotonic clock.  Every wait below is by time, never
 * by the number of poll rounds: with a fast GPU the program's stdout is
 * readable almost always, and a round then lasts microseconds, not the
 * 100 ms of its timeout. */
static double now_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* Until at least min_pings pings reporting more than min_frames frames, or
 * limit_ms of wall time: whether they came. */
static bool wait_for(struct watch *w, int min_pings, int min_frames, int limit_ms)
{
	double end = now_ms() + limit_ms;
	while (!(w->pings >= min_pings && w->frames > min_frames) && now_ms() < end && step(w, 100) >= 0)
		;
	return w->pings >= min_pings && w->frames > min_frames;
}

static pid_t start(const char *bin, const char *sockpath, int out_fd)
{
	pid_t pid = fork();
	if (pid != 0)
		return pid;
	dup2(out_fd, STDOUT_FILENO);
	setenv("NOTIFY_SOCKET", sockpath, 1);
	setenv("WATCHDOG_USEC", "200000", 1);
	unsetenv("WATCHDOG_PID");
	execl(bin, bin, "--size", "64x48", "--grid", "8", "--count", "1000000", "--out", "-", (char *)NULL);
	_exit(127);
}

int main(int argc, char **argv)
{
	const char *bin = argc > 1 ? argv[1] : getenv("ISOTERRA_BIN");
	char dir[] = "/tmp/isoterra-notify-XXXXXX";
	if (!bin || !mkdtemp(dir)) {
		fprintf(stderr, "test_notify: needs the program's path and a temporary folder\n");
		return 1;
	}
	struct sockaddr_un sa = { .sun_family = AF_UNIX };
	snprintf(sa.sun_path, sizeof(sa.sun_path), "%s/notify", dir);
	struct watch w = { .sock = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0), .reading = true };
	int p[2];
	if (w.sock < 0 || bind(w.sock, (struct sockaddr *)&sa, sizeof(sa)) < 0 || pipe2(p, O_CLOEXEC) < 0) {
		perror("test_notify: socket/bind/pipe");
		return 1;
	}
	/* the smallest pipe: a frame cannot complete unless this test reads it */
	int cap = fcntl(p[0], F_SETPIPE_SZ, 4096);
	CHECK(cap >= 4096 && cap < FRAME_BYTES, "pipe of %d bytes, less than a frame", cap);
	pid_t pid = start(bin, sa.sun_path, p[1]);
	close(p[1]);
	w.out = p[0];

	CHECK(wait_for(&w, 3, 0, 120000), "READY=1 then 3 pings while frames complete (%d, %d)", w.ready,
	      w.pings);
	CHECK(w.ready == 1 && w.first_ready_frames == 1, "READY=1 once, after the first frame (%d, at %d)", w.ready,
	      w.first_ready_frames);

	/* stall: stop reading; the pings that were on their way arrive, then none */
	w.reading = false;
	int before = w.msgs;
	double end = now_ms() + 120000, last_msg = now_ms();
	while (now_ms() - last_msg < 2000 && now_ms() < end)
		if (step(&w, 100) > 0)
			last_msg = now_ms();
	CHECK(now_ms() - last_msg >= 2000, "no ping for 2 s (10 watchdog intervals) while the frame loop is stalled");
	/* what was read, the pipe and a stdio buffer (up to 1 MiB) can hold */
	long long most = (w.bytes + cap + (1 << 20)) / FRAME_BYTES + 1;
	CHECK(w.frames <= most, "the pings report only frames that were written (%d, at most %lld; %d messages)",
	      w.frames, most, w.msgs - before);
	CHECK(waitpid(pid, NULL, WNOHANG) == 0, "the program is alive, only stalled");

	/* resume: the pings come back with new frames */
	int stalled_at = w.frames, pings = w.pings;
	w.reading = true;
	CHECK(wait_for(&w, pings + 2, stalled_at, 120000), "pings again once frames complete");

	kill(pid, SIGTERM);
	int status = 0;
	pid_t ended = 0;
	end = now_ms() + 120000;
	while ((ended = waitpid(pid, &status, WNOHANG)) == 0 && now_ms() < end)
		step(&w, 100);
	CHECK(ended == pid, "SIGTERM ends the run");
	if (ended != pid) {
		kill(pid, SIGKILL);
		waitpid(pid, &status, 0);
	}
	while (step(&w, 200) > 0)
		;
	CHECK(WIFEXITED(status), "exited (status %#x)", status);
	CHECK(w.stopping == 1, "STOPPING=1 once at the end (%d)", w.stopping);
	CHECK(!w.status_missing && !w.frames_back, "every message has STATUS= with a frame count that never goes back");
	close(w.sock);
	if (w.out >= 0)
		close(w.out);
	unlink(sa.sun_path);
	rmdir(dir);
	return tc_done("notify");
}
