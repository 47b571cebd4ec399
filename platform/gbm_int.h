/* isoterra — the GBM/KMS backend's insides, shared by backend_gbm.c (the
 * surface, modesets, the connector, present and close) and gbm_flip.c (page
 * flips, pipelined with fences).  Private to platform/. */
#ifndef ISOTERRA_GBM_INT_H
#define ISOTERRA_GBM_INT_H

#include "kms.h"
#include "platform.h"

#include <stdbool.h>
#include <stdint.h>

#include <gbm.h>
#include <xf86drmMode.h>

#define FLIP_TIMEOUT_MS 5000
#define EBUSY_RETRIES 100 /* of 1 ms, should the kernel still be busy with the flip before */

/* One output: its connector, CRTC and mode (kms.x, kms.y: its rectangle
 * of the surface), the atomic plane and properties of its CRTC. */
struct gbm_head {
	struct kms_output kms;     /* h[0]'s owns the card fd and the hotplug events */
	struct kms_atomic at;
	drmModeCrtc *saved;        /* the CRTC as we found it, put back on close */
	bool connected;            /* the connector, as last asked */
	bool modeset_done;         /* scanning out our frames */
	bool off;                  /* its CRTC turned off while it is gone (several outputs) */
	char want_mode[32];        /* --mode ("" = the preferred one; several outputs: the
	                              common size), chosen again on return */
	int fence;                 /* pipelined: the out-fence of the flip in flight on its CRTC (-1: none) */
	unsigned long flips;       /* flips (and modesets) its CRTC confirmed */
};

struct gbm_state {
	int n;                     /* outputs, h[0..n) */
	struct gbm_head h[PLATFORM_MAX_OUTPUTS];
	bool mirror;               /* several outputs: one picture each (else a row) */
	int turned;                /* one output: quarter turns the plane applies (--rotate), else 0 */
	struct gbm_device *gbm;
	struct gbm_surface *surf;
	struct gbm_bo *front;      /* on screen */
	bool atomic, flip_pending, restore_done;
	int events;                /* page-flip events still to come for the flip in flight */
	/* pipelined flips (atomic with out-fences): the bo committed last and
	 * the out-fences of its flip (each head's fence); with in-fences, the
	 * EGL entry points for the GPU's render fence */
	bool pipelined, in_fences, flips_said, fence_proven;
	const char *no_in_fence;   /* why there are none, for the info line */
	struct gbm_bo *pending;
	PFNEGLCREATESYNCKHRPROC create_sync;
	PFNEGLDESTROYSYNCKHRPROC destroy_sync;
	PFNEGLDUPNATIVEFENCEFDANDROIDPROC dup_fence;
	struct platform *p;
	bool lost;                 /* the last gbm_watch_connector saw an output go */
	double next_poll;          /* platform_clock_ms() of the next question */
};

/* Is any output connected (as last asked)? */
bool gbm_any_connected(const struct gbm_state *g);

/* ---- gbm_flip.c ---------------------------------------------------------- */

/* Waits for the page-flip events of the flip in flight (flip_pending: one per CRTC). */
int gbm_wait_flip(struct gbm_state *g);
/* bo is on screen now: the one before goes back to the surface. */
void gbm_show(struct gbm_state *g, struct gbm_bo *bo);
/* Closes a fence fd (>= 0) and sets it to -1. */
void gbm_close_fd(int *fd);
/* Pipelined: waits for the flip in flight, if any; 0, or -1 (logged; the
 * flip is then taken as done, unconfirmed). */
int gbm_finish_flip(struct gbm_state *g);
/* The flip path, said once at info level. */
void gbm_say_flips(struct gbm_state *g);
/* Chooses the flip path after the atomic setup (pipelined, in-fences). */
void gbm_choose_flips(struct gbm_state *g);
/* In-fences: the GPU's render fence, made before eglSwapBuffers, and its
 * fd after it (-1 when none). */
EGLSyncKHR gbm_render_sync(struct gbm_state *g);
int gbm_render_fence_fd(struct gbm_state *g, EGLSyncKHR s);
/* A page flip of bo (fb): 0 committed (bo is the front now, or in flight
 * when pipelined), 1 refused because the display is gone, -1 error. */
int gbm_flip(struct gbm_state *g, uint32_t fb, struct gbm_bo *bo, int in_fence);

/* ---- backend_gbm.c ------------------------------------------------------- */

/* Are the connectors still there (asked once a second, or at once)?  0,
 * or -1 when the surface cannot follow a new size.  g->lost: one went. */
int gbm_watch_connector(struct gbm_state *g, bool at_once);

#endif
