/* isoterra — the stop signals (app/core/signals.c), in child processes:
 *  - SIGTERM twice in a row, as `timeout` sends it (to the program, then
 *    to its process group): one request, the child stops cleanly (its
 *    loop sees the flag, exit 0), in every one of many tries, the second
 *    sent once the first's handler has run;
 *  - the same for SIGINT;
 *  - a second SIGTERM two seconds after the first, to a child that does
 *    not stop (a stuck frame): the user insists, the signal kills it
 *    (sent again every 0.25 s for 5 s: the test never hangs). */
#include "app.h"
#include "tcheck.h"

#include <errno.h>
#include <signal.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define TRIES 40

static void nap_ms(long ms)
{
	struct timespec d = { ms / 1000, (ms % 1000) * 1000000L };
	while (nanosleep(&d, &d) != 0)
		;
}

/* A child with the handlers, ready (a byte on `ready`); it loops until the
 * flag says stop (exit 0), or forever when `stuck`. */
static pid_t child(bool stuck, int *ready_fd)
{
	int fds[2];
	if (pipe(fds) != 0)
		return -1;
	pid_t pid = fork();
	if (pid == 0) {
		close(fds[0]);
		if (signals_install() != 0)
			_exit(3);
		if (write(fds[1], "r", 1) != 1)
			_exit(4);
		for (;;) {
			if (!stuck && signals_quit())
				_exit(0);
			nap_ms(1);
		}
	}
	close(fds[1]);
	*ready_fd = fds[0];
	return pid;
}

/* Waits for the child's end (its status). */
static void reap(pid_t pid, int *status)
{
	while (waitpid(pid, status, 0) < 0 && errno == EINTR)
		;
}

/* Twice `sig` a moment apart (the first's handler has run: the child naps
 * 1 ms a loop); the child must exit 0 every time. */
static void twice(int sig, const char *name)
{
	int clean = 0, tries = 0;
	char last[64] = "";
	for (int i = 0; i < TRIES; i++) {
		int ready, st;
		char c;
		pid_t pid = child(false, &ready);
		if (pid < 0 || read(ready, &c, 1) != 1) {
			CHECK(0, "%s: no child", name);
			return;
		}
		close(ready);
		kill(pid, sig);
		nap_ms(i % 4); /* 0-3 ms: before and after the handler ran */
		kill(pid, sig);
		reap(pid, &st);
		tries++;
		if (WIFEXITED(st) && WEXITSTATUS(st) == 0)
			clean++;
		else
			snprintf(last, sizeof(last), WIFSIGNALED(st) ? "killed by signal %d" : "exit %d",
				 WIFSIGNALED(st) ? WTERMSIG(st) : WEXITSTATUS(st));
	}
	CHECK(clean == tries, "%s twice in a row: %d of %d children stopped cleanly (the others: %s)", name, clean,
	      tries, last);
	printf("%s twice in a row: %d of %d children stopped cleanly\n", name, clean, tries);
}

int main(void)
{
	twice(SIGTERM, "SIGTERM");
	twice(SIGINT, "SIGINT");

	/* a child that does not stop: a second SIGTERM 2.2 s on kills it */
	int ready, st;
	char c;
	pid_t pid = child(true, &ready);
	CHECK(pid > 0 && read(ready, &c, 1) == 1, "the stuck child started");
	close(ready);
	kill(pid, SIGTERM);
	nap_ms(300);
	CHECK(waitpid(pid, &st, WNOHANG) == 0, "the stuck child survives the first SIGTERM");
	nap_ms(1900);
	/* 2.2 s on, and again every 0.25 s for a loaded machine's late
	 * handler (never a wait that could hang the test): the third at most
	 * is over two whole seconds after the first's handler */
	pid_t done = 0;
	for (int i = 0; i < 20 && done == 0; i++) {
		kill(pid, SIGTERM);
		nap_ms(250);
		done = waitpid(pid, &st, WNOHANG);
	}
	if (done == 0) {
		kill(pid, SIGKILL);
		reap(pid, &st);
	}
	CHECK(done == pid && WIFSIGNALED(st) && WTERMSIG(st) == SIGTERM,
	      "a SIGTERM 2.2 s after the first kills it (status 0x%x)", (unsigned)st);
	return tc_done("signals");
}
