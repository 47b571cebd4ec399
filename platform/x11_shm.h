/* isoterra — the X11 backend's present through MIT-SHM (x11_shm.c), used
 * by backend_x11.c.  Private to platform/. */
#ifndef ISOTERRA_X11_SHM_H
#define ISOTERRA_X11_SHM_H

#include <stddef.h>
#include <stdint.h>

#include <xcb/xcb.h>

struct x11_shm;

/* A present of frames into window `win` (of depth `depth` and visual
 * `vis`) through a shared-memory segment: NULL, with the reason in why,
 * where this X server cannot take one (no MIT-SHM 1.2, which passes the
 * segment as a file descriptor: a server on another machine; a pixel
 * layout other than 32-bit little-endian xRGB). */
struct x11_shm *x11_shm_open(xcb_connection_t *conn, xcb_window_t win, uint8_t depth, const xcb_visualtype_t *vis,
                             char *why, size_t whylen);
/* Reads the current context's default framebuffer (w x h, the frame just
 * drawn) into the segment and puts it into the window, top row first.
 * The GL state it touches (the read framebuffer, the pack buffer and
 * alignment) is restored.  0, or -1 with the reason logged. */
int x11_shm_present(struct x11_shm *s, int w, int h);
/* Waits until the X server has read the last frame, detaches the segment. */
void x11_shm_close(struct x11_shm *s);

#endif
