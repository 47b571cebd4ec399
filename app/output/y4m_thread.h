/* isoterra — the Y4M stream written beside the frame loop: a thread
 * converts frame N to Y'CbCr and writes it while frame N+1 renders.  One
 * frame in flight: handing the next one over waits for the one before. */
#ifndef ISOTERRA_Y4M_THREAD_H
#define ISOTERRA_Y4M_THREAD_H

#include <stddef.h>

#include "core.h"
#include "y4m.h"

struct y4m_thread;

/* A writer for y (open; borrowed until y4m_thread_stop).  NULL with err. */
struct y4m_thread *y4m_thread_start(struct y4m *y, char *err, size_t errlen);
/* Hands frame `number` over (img's pixels are taken: img is emptied)
 * after the frame before is written.  0, or -1 with err when that earlier
 * frame failed (it names the frame; img is freed and the stream is done). */
int y4m_thread_put(struct y4m_thread *t, struct image *img, int number, const char *dest, char *err, size_t errlen);
/* Waits until every frame handed over is written.  0, or -1 with err. */
int y4m_thread_drain(struct y4m_thread *t, const char *dest, char *err, size_t errlen);
/* Drains (an error is dropped: the stream is not committed then) and
 * ends the thread.  NULL is fine. */
void y4m_thread_stop(struct y4m_thread *t);

#endif
