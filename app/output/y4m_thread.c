/* isoterra — the Y4M stream written beside the frame loop (y4m_thread.h).
 * The read-back stays on the GL thread; the colour conversion (a pass over
 * every pixel) and the write (1.5 bytes a pixel, to a file or a pipe that
 * may block) move to this thread, so they overlap the next frame's
 * rendering instead of adding to it. */
#include "y4m_thread.h"

#include <errno.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct y4m_thread {
	struct y4m *y;
	pthread_t thread;
	pthread_mutex_t lock;
	pthread_cond_t cond;
	struct image job;   /* the frame to write (rgba NULL: none) */
	int job_number;
	bool busy, quit;
	int failed;         /* errno of the first frame that failed, else 0 */
	int failed_number;
};

static void *writer(void *arg)
{
	struct y4m_thread *t = arg;
	pthread_mutex_lock(&t->lock);
	for (;;) {
		while (!t->busy && !t->quit)
			pthread_cond_wait(&t->cond, &t->lock);
		if (!t->busy)
			break; /* quit, nothing left */
		struct image img = t->job;
		int number = t->job_number;
		pthread_mutex_unlock(&t->lock);
		int rc = t->failed ? 0 : y4m_write(t->y, &img); /* (after a failure: dropped) */
		int e = errno;
		image_free(&img);
		pthread_mutex_lock(&t->lock);
		if (rc < 0 && !t->failed) {
			t->failed = e ? e : EIO;
			t->failed_number = number;
		}
		memset(&t->job, 0, sizeof(t->job));
		t->busy = false;
		pthread_cond_broadcast(&t->cond);
	}
	pthread_mutex_unlock(&t->lock);
	return NULL;
}

struct y4m_thread *y4m_thread_start(struct y4m *y, char *err, size_t errlen)
{
	struct y4m_thread *t = calloc(1, sizeof(*t));
	if (!t) {
		snprintf(err, errlen, "out of memory");
		return NULL;
	}
	t->y = y;
	int rc = pthread_mutex_init(&t->lock, NULL);
	if (rc == 0 && (rc = pthread_cond_init(&t->cond, NULL)) != 0)
		pthread_mutex_destroy(&t->lock);
	if (rc == 0 && (rc = pthread_create(&t->thread, NULL, writer, t)) != 0) {
		pthread_cond_destroy(&t->cond);
		pthread_mutex_destroy(&t->lock);
	}
	if (rc != 0) {
		snprintf(err, errlen, "cannot start the Y4M writer thread: %s", strerror(rc));
		free(t);
		return NULL;
	}
	return t;
}

/* Waits for the frame in flight; the lock held.  0, or -1 with err. */
static int wait_idle(struct y4m_thread *t, const char *dest, char *err, size_t errlen)
{
	while (t->busy)
		pthread_cond_wait(&t->cond, &t->lock);
	if (!t->failed)
		return 0;
	bool out = !strcmp(dest, "-");
	snprintf(err, errlen, "writing frame %d to %s%s%s failed: %s", t->failed_number, out ? "" : "'",
		 out ? "stdout" : dest, out ? "" : "'", strerror(t->failed));
	return -1;
}

int y4m_thread_put(struct y4m_thread *t, struct image *img, int number, const char *dest, char *err, size_t errlen)
{
	pthread_mutex_lock(&t->lock);
	int rc = wait_idle(t, dest, err, errlen);
	if (rc == 0) {
		t->job = *img;
		t->job_number = number;
		t->busy = true;
		pthread_cond_broadcast(&t->cond);
	} else {
		image_free(img);
	}
	pthread_mutex_unlock(&t->lock);
	memset(img, 0, sizeof(*img));
	return rc;
}

int y4m_thread_drain(struct y4m_thread *t, const char *dest, char *err, size_t errlen)
{
	pthread_mutex_lock(&t->lock);
	int rc = wait_idle(t, dest, err, errlen);
	pthread_mutex_unlock(&t->lock);
	return rc;
}

void y4m_thread_stop(struct y4m_thread *t)
{
	if (!t)
		return;
	pthread_mutex_lock(&t->lock);
	t->quit = true;
	pthread_cond_broadcast(&t->cond);
	pthread_mutex_unlock(&t->lock);
	pthread_join(t->thread, NULL);
	image_free(&t->job);
	pthread_cond_destroy(&t->cond);
	pthread_mutex_destroy(&t->lock);
	free(t);
}
