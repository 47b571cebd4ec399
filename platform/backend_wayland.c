/* isoterra — Wayland display backend: wl_compositor + xdg_wm_base (the
 * xdg-shell glue is generated at build time by wayland-scanner), a
 * wl_egl_window, fullscreen on request, resize on configure, close from
 * xdg_toplevel.close; frame callbacks are counted (p->shown); with
 * --hide-cursor the pointer is hidden over the window (wl_pointer.enter ->
 * set_cursor(NULL)). */
#include "platform.h"

#include <errno.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <wayland-client.h>
#include <wayland-egl.h>

#include "platform_util.h"
#include "xdg-shell-client-protocol.h"

struct wl_state {
	struct platform *p;
	struct wl_display *display;
	struct wl_registry *registry;
	struct wl_compositor *compositor;
	struct xdg_wm_base *wm_base;
	struct wl_surface *surface;
	struct xdg_surface *xdg_surface;
	struct xdg_toplevel *toplevel;
	struct wl_egl_window *egl_window;
	struct wl_seat *seat; /* only with --hide-cursor */
	struct wl_pointer *pointer;
	int pending_w, pending_h; /* from xdg_toplevel.configure, 0 = our choice */
	bool configured, closed, want_seat;
	unsigned callbacks_pending;
};

static bool wayland_probe(void)
{
	const char *c = egl_common_client_exts();
	return egl_common_has_ext(c, "EGL_KHR_platform_wayland") || egl_common_has_ext(c, "EGL_EXT_platform_wayland");
}

static void wm_base_ping(void *data, struct xdg_wm_base *base, uint32_t serial)
{
	(void)data;
	xdg_wm_base_pong(base, serial);
}

static const struct xdg_wm_base_listener wm_base_listener = { .ping = wm_base_ping };

/* --hide-cursor: a NULL cursor surface hides the pointer while it is over
 * the window (the compositor asks on every enter). */
static void pointer_enter(void *data, struct wl_pointer *ptr, uint32_t serial, struct wl_surface *s, wl_fixed_t x,
			  wl_fixed_t y)
{
	(void)data;
	(void)s;
	(void)x;
	(void)y;
	wl_pointer_set_cursor(ptr, serial, NULL, 0, 0);
}

static void pointer_leave(void *data, struct wl_pointer *ptr, uint32_t serial, struct wl_surface *s)
{
	(void)data;
	(void)ptr;
	(void)serial;
	(void)s;
}

static void pointer_motion(void *data, struct wl_pointer *ptr, uint32_t time, wl_fixed_t x, wl_fixed_t y)
{
	(void)data;
	(void)ptr;
	(void)time;
	(void)x;
	(void)y;
}

static void pointer_button(void *data, struct wl_pointer *ptr, uint32_t serial, uint32_t time, uint32_t button,
			   uint32_t state)
{
	(void)data;
	(void)ptr;
	(void)serial;
	(void)time;
	(void)button;
	(void)state;
}

static void pointer_axis(void *data, struct wl_pointer *ptr, uint32_t time, uint32_t axis, wl_fixed_t value)
{
	(void)data;
	(void)ptr;
	(void)time;
	(void)axis;
	(void)value;
}

/* wl_seat is bound at version 1: only these pointer events exist there */
static const struct wl_pointer_listener pointer_listener = {
	.enter = pointer_enter,
	.leave = pointer_leave,
	.motion = pointer_motion,
	.button = pointer_button,
	.axis = pointer_axis,
};

static void seat_capabilities(void *data, struct wl_seat *seat, uint32_t caps)
{
	struct wl_state *w = data;
	if ((caps & WL_SEAT_CAPABILITY_POINTER) && !w->pointer) {
		w->pointer = wl_seat_get_pointer(seat);
		if (w->pointer)
			wl_pointer_add_listener(w->pointer, &pointer_listener, w);
	} else if (!(caps & WL_SEAT_CAPABILITY_POINTER) && w->pointer) {
		wl_pointer_destroy(w->pointer);
		w->pointer = NULL;
	}
}

static const struct wl_seat_listener seat_listener = { .capabilities = seat_capabilities };

static void registry_global(void *data, struct wl_registry *reg, uint32_t name, const char *iface, uint32_t version)
{
	struct wl_state *w = data;
	if (strcmp(iface, wl_seat_interface.name) == 0 && w->want_seat && !w->seat) {
		w->seat = wl_registry_bind(reg, name, &wl_seat_interface, 1);
		if (w->seat)
			wl_seat_add_listener(w->seat, &seat_listener, w);
		return;
	}
	if (strcmp(iface, wl_compositor_interface.name) == 0 && !w->compositor) {
		w->compositor = wl_registry_bind(reg, name, &wl_compositor_interface, version < 4 ? version : 4);
	} else if (strcmp(iface, xdg_wm_base_interface.name) == 0 && !w->wm_base) {
		w->wm_base = wl_registry_bind(reg, name, &xdg_wm_base_interface, 1);
		if (w->wm_base)
			xdg_wm_base_add_listener(w->wm_base, &wm_base_listener, w);
	}
}

static void registry_remove(void *data, struct wl_registry *reg, uint32_t name)
{
	(void)data;
	(void)reg;
	(void)name;
}

static const struct wl_registry_listener registry_listener = {
	.global = registry_global,
	.global_remove = registry_remove,
};

static void toplevel_configure(void *data, struct xdg_toplevel *t, int32_t width, int32_t height,
                               struct wl_array *states)
{
	(void)t;
	(void)states;
	struct wl_state *w = data;
	w->pending_w = width;
	w->pending_h = height;
}

static void toplevel_close(void *data, struct xdg_toplevel *t)
{
	(void)t;
	struct wl_state *w = data;
	w->closed = true;
}

static const struct xdg_toplevel_listener toplevel_listener = {
	.configure = toplevel_configure,
	.close = toplevel_close,
};

static void xdg_surface_configure(void *data, struct xdg_surface *s, uint32_t serial)
{
	struct wl_state *w = data;
	struct platform *p = w->p;
	xdg_surface_ack_configure(s, serial);
	w->configured = true;
	if (w->pending_w > 0 && w->pending_h > 0 && (w->pending_w != p->width || w->pending_h != p->height)) {
		plog_debug("wayland: configured to %dx%d", w->pending_w, w->pending_h);
		p->width = w->pending_w;
		p->height = w->pending_h;
		if (w->egl_window)
			wl_egl_window_resize(w->egl_window, p->width, p->height, 0, 0);
	}
}

static const struct xdg_surface_listener xdg_surface_listener = { .configure = xdg_surface_configure };

static void frame_done(void *data, struct wl_callback *cb, uint32_t time)
{
	(void)time;
	struct wl_state *w = data;
	wl_callback_destroy(cb);
	w->callbacks_pending--;
	w->p->shown++;
}

static const struct wl_callback_listener frame_listener = { .done = frame_done };

/* Reads and dispatches whatever the compositor sent, without blocking. */
static int pump(struct wl_state *w)
{
	while (wl_display_prepare_read(w->display) != 0) {
		if (wl_display_dispatch_pending(w->display) < 0)
			return -1;
	}
	if (wl_display_flush(w->display) < 0 && errno != EAGAIN) {
		wl_display_cancel_read(w->display);
		return -1;
	}
	struct pollfd pfd = { .fd = wl_display_get_fd(w->display), .events = POLLIN };
	if (poll(&pfd, 1, 0) > 0) {
		if (wl_display_read_events(w->display) < 0)
			return -1;
	} else {
		wl_display_cancel_read(w->display);
	}
	return wl_display_dispatch_pending(w->display) < 0 ? -1 : 0;
}

static int wayland_dispatch(struct platform *p)
{
	struct wl_state *w = p->priv;
	if (pump(w) < 0) {
		plog_error("wayland: connection to the compositor lost (%s)", strerror(wl_display_get_error(w->display)));
		return -1;
	}
	if (w->closed) {
		plog_info("wayland: window closed");
		return 1;
	}
	return 0;
}

static int wayland_present(struct platform *p)
{
	struct wl_state *w = p->priv;
	struct wl_callback *cb = wl_surface_frame(w->surface);
	if (!cb) {
		plog_error("wayland: wl_surface_frame failed");
		return -1;
	}
	wl_callback_add_listener(cb, &frame_listener, w);
	w->callbacks_pending++;
	if (!eglSwapBuffers(p->dpy, p->surface)) {
		plog_error("wayland: eglSwapBuffers failed: %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	return 0;
}

static void wayland_close(struct platform *p)
{
	struct wl_state *w = p->priv;
	egl_common_release(p);
	if (!w)
		return;
	if (w->display && w->callbacks_pending) {
		/* collect the callbacks of frames already sent (bounded wait) */
		for (int i = 0; i < 10 && w->callbacks_pending; i++)
			if (wl_display_roundtrip(w->display) < 0)
				break;
	}
	if (w->egl_window)
		wl_egl_window_destroy(w->egl_window);
	if (w->toplevel)
		xdg_toplevel_destroy(w->toplevel);
	if (w->xdg_surface)
		xdg_surface_destroy(w->xdg_surface);
	if (w->surface)
		wl_surface_destroy(w->surface);
	if (w->pointer)
		wl_pointer_destroy(w->pointer);
	if (w->seat)
		wl_seat_destroy(w->seat);
	if (w->wm_base)
		xdg_wm_base_destroy(w->wm_base);
	if (w->compositor)
		wl_compositor_destroy(w->compositor);
	if (w->registry)
		wl_registry_destroy(w->registry);
	if (w->display) {
		wl_display_flush(w->display);
		wl_display_disconnect(w->display);
	}
	free(w);
	p->priv = NULL;
}

static int wayland_open(struct platform *p, const struct platform_options *opt, char *err, size_t errlen)
{
	if (!wayland_probe()) {
		snprintf(err, errlen, "EGL_KHR_platform_wayland not supported by this EGL");
		return -1;
	}
	struct wl_state *w = calloc(1, sizeof(*w));
	if (!w) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	w->p = p;
	w->want_seat = opt->hide_cursor;
	p->priv = w;
	const char *name = getenv("WAYLAND_DISPLAY");
	w->display = wl_display_connect(NULL);
	if (!w->display) {
		snprintf(err, errlen, "cannot connect to the Wayland compositor '%s'",
		         name && name[0] ? name : "wayland-0");
		goto fail;
	}
	w->registry = wl_display_get_registry(w->display);
	if (!w->registry || wl_registry_add_listener(w->registry, &registry_listener, w) < 0 ||
	    wl_display_roundtrip(w->display) < 0) {
		snprintf(err, errlen, "wayland: reading the registry failed");
		goto fail;
	}
	if (!w->compositor || !w->wm_base) {
		snprintf(err, errlen, "the Wayland compositor lacks %s", !w->compositor ? "wl_compositor" : "xdg_wm_base (xdg-shell)");
		goto fail;
	}
	w->surface = wl_compositor_create_surface(w->compositor);
	w->xdg_surface = w->surface ? xdg_wm_base_get_xdg_surface(w->wm_base, w->surface) : NULL;
	w->toplevel = w->xdg_surface ? xdg_surface_get_toplevel(w->xdg_surface) : NULL;
	if (!w->toplevel) {
		snprintf(err, errlen, "wayland: cannot create the xdg_toplevel");
		goto fail;
	}
	xdg_surface_add_listener(w->xdg_surface, &xdg_surface_listener, w);
	xdg_toplevel_add_listener(w->toplevel, &toplevel_listener, w);
	xdg_toplevel_set_title(w->toplevel, "isoterra");
	xdg_toplevel_set_app_id(w->toplevel, "isoterra");
	if (opt->fullscreen)
		xdg_toplevel_set_fullscreen(w->toplevel, NULL);
	p->width = opt->width;
	p->height = opt->height;
	wl_surface_commit(w->surface);
	while (!w->configured && !w->closed)
		if (wl_display_dispatch(w->display) < 0) {
			snprintf(err, errlen, "wayland: connection lost waiting for the first configure");
			goto fail;
		}
	if (w->closed) {
		snprintf(err, errlen, "wayland: window closed before it was shown");
		goto fail;
	}
	w->egl_window = wl_egl_window_create(w->surface, p->width, p->height);
	if (!w->egl_window) {
		snprintf(err, errlen, "wl_egl_window_create %dx%d failed", p->width, p->height);
		goto fail;
	}
	if (egl_common_open_display(p, EGL_PLATFORM_WAYLAND_KHR, w->display, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, 0, NULL, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, 0, w->egl_window, err, errlen) < 0)
		goto fail;
	plog_debug("wayland: %dx%d%s on '%s'", p->width, p->height, opt->fullscreen ? " fullscreen" : "",
	          name ? name : "wayland-0");
	return 0;
fail:
	wayland_close(p);
	return -1;
}

const struct platform_backend platform_backend_wayland = {
	.name = "wayland",
	.probe = wayland_probe,
	.open = wayland_open,
	.close = wayland_close,
	.present = wayland_present,
	.dispatch = wayland_dispatch,
};
