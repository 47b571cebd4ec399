/* isoterra — X11 display backend: an xcb window (through Xlib's display
 * for EGL_KHR_platform_x11, which is what Mesa 22 offers), WM_DELETE_WINDOW
 * closes, ConfigureNotify resizes, _NET_WM_STATE_FULLSCREEN (and, with no
 * window manager, a window the size of the screen), optional hidden cursor.
 * Frames reach the window through eglSwapBuffers or, for a software
 * renderer, drawn into a pbuffer and put through MIT-SHM (x11_shm.c). */
#include "platform.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GLES3/gl31.h>
#include <X11/Xlib.h>
#include <X11/Xlib-xcb.h>
#include <xcb/xcb.h>

#include "platform_util.h"
#include "x11_shm.h"

struct x11_state {
	Display *xdpy;
	xcb_connection_t *conn;
	xcb_screen_t *screen;
	xcb_window_t win;
	Window native; /* what eglCreatePlatformWindowSurfaceEXT gets a pointer to */
	xcb_colormap_t cmap;
	xcb_cursor_t cursor;
	xcb_atom_t wm_protocols, wm_delete;
	bool mapped;
	/* the MIT-SHM present: frames drawn into a pbuffer of pb_w x pb_h */
	struct x11_shm *shm;
	int pb_w, pb_h;
};

static bool x11_probe(void)
{
	const char *c = egl_common_client_exts();
	return egl_common_has_ext(c, "EGL_KHR_platform_x11") || egl_common_has_ext(c, "EGL_EXT_platform_x11");
}

static xcb_atom_t intern(xcb_connection_t *c, const char *name)
{
	xcb_intern_atom_reply_t *r =
		xcb_intern_atom_reply(c, xcb_intern_atom(c, 0, (uint16_t)strlen(name), name), NULL);
	xcb_atom_t a = r ? r->atom : XCB_ATOM_NONE;
	free(r);
	return a;
}

/* Visual v of the screen and its depth (NULL, 0 when not there). */
static const xcb_visualtype_t *find_visual(const xcb_screen_t *s, xcb_visualid_t v, uint8_t *depth)
{
	for (xcb_depth_iterator_t d = xcb_screen_allowed_depths_iterator(s); d.rem; xcb_depth_next(&d))
		for (xcb_visualtype_iterator_t vi = xcb_depth_visuals_iterator(d.data); vi.rem; xcb_visualtype_next(&vi))
			if (vi.data->visual_id == v) {
				*depth = d.data->depth;
				return vi.data;
			}
	*depth = 0;
	return NULL;
}

/* Handles one event; 1 when the window was asked to close. */
static int handle_event(struct platform *p, struct x11_state *x, xcb_generic_event_t *ev)
{
	switch (ev->response_type & 0x7f) {
	case XCB_CONFIGURE_NOTIFY: {
		xcb_configure_notify_event_t *c = (xcb_configure_notify_event_t *)ev;
		if (c->window == x->win && c->width > 0 && c->height > 0 &&
		    (c->width != p->width || c->height != p->height)) {
			plog_debug("x11: window resized to %ux%u", c->width, c->height);
			p->width = c->width;
			p->height = c->height;
		}
		break;
	}
	case XCB_MAP_NOTIFY:
		x->mapped = true;
		break;
	case XCB_CLIENT_MESSAGE: {
		xcb_client_message_event_t *m = (xcb_client_message_event_t *)ev;
		if (m->window == x->win && m->type == x->wm_protocols && m->format == 32 &&
		    m->data.data32[0] == x->wm_delete) {
			plog_info("x11: window closed");
			return 1;
		}
		break;
	}
	default:
		break;
	}
	return 0;
}

static int x11_dispatch(struct platform *p)
{
	struct x11_state *x = p->priv;
	int quit = 0;
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(x->conn)) != NULL) {
		quit |= handle_event(p, x, ev);
		free(ev);
	}
	if (xcb_connection_has_error(x->conn)) {
		plog_error("x11: connection to the X server lost");
		return -1;
	}
	if (x->shm && (p->width != x->pb_w || p->height != x->pb_h)) {
		/* the next frame is drawn at the window's new size */
		char err[256];
		const struct platform_options none = { 0 }; /* read only to make a context: it exists */
		if (egl_common_make_pbuffer_context(p, &none, p->width, p->height, err, sizeof(err)) < 0) {
			plog_error("x11: a %dx%d frame for the resized window: %s", p->width, p->height, err);
			return -1;
		}
		x->pb_w = p->width;
		x->pb_h = p->height;
	}
	return quit;
}

static void x11_close(struct platform *p)
{
	struct x11_state *x = p->priv;
	if (x) {
		x11_shm_close(x->shm);
		x->shm = NULL;
	}
	egl_common_release(p);
	if (!x)
		return;
	if (x->conn) {
		if (x->win)
			xcb_destroy_window(x->conn, x->win);
		if (x->cursor)
			xcb_free_cursor(x->conn, x->cursor);
		if (x->cmap)
			xcb_free_colormap(x->conn, x->cmap);
		xcb_flush(x->conn);
	}
	if (x->xdpy)
		XCloseDisplay(x->xdpy);
	free(x);
	p->priv = NULL;
}

static xcb_cursor_t blank_cursor(xcb_connection_t *c, xcb_window_t root)
{
	xcb_pixmap_t pix = xcb_generate_id(c);
	xcb_cursor_t cur = xcb_generate_id(c);
	xcb_create_pixmap(c, 1, pix, root, 1, 1);
	xcb_create_cursor(c, cur, pix, pix, 0, 0, 0, 0, 0, 0, 0, 0);
	xcb_free_pixmap(c, pix);
	return cur;
}

/* Xlib display (for EGL), its xcb connection (for everything else) and the
 * default screen. */
static int x11_connect(struct x11_state *x, char *err, size_t errlen)
{
	const char *name = getenv("DISPLAY");
	x->xdpy = XOpenDisplay(NULL);
	if (!x->xdpy) {
		snprintf(err, errlen, "cannot connect to the X server '%s'", name && name[0] ? name : "(DISPLAY unset)");
		return -1;
	}
	x->conn = XGetXCBConnection(x->xdpy);
	if (!x->conn || xcb_connection_has_error(x->conn)) {
		snprintf(err, errlen, "no xcb connection to the X server '%s'", name ? name : "");
		return -1;
	}
	XSetEventQueueOwner(x->xdpy, XCBOwnsEventQueue);
	int screen_no = DefaultScreen(x->xdpy);
	xcb_screen_iterator_t si = xcb_setup_roots_iterator(xcb_get_setup(x->conn));
	for (int i = 0; i < screen_no && si.rem; i++)
		xcb_screen_next(&si);
	if (!si.rem) {
		snprintf(err, errlen, "X server '%s' has no screen %d", name ? name : "", screen_no);
		return -1;
	}
	x->screen = si.data;
	return 0;
}

/* The EGL display and config; the X visual of that config and its depth. */
static int x11_egl_visual(struct platform *p, struct x11_state *x, const struct platform_options *opt, EGLint *vid,
                          const xcb_visualtype_t **vis, uint8_t *depth, char *err, size_t errlen)
{
	if (egl_common_open_display(p, EGL_PLATFORM_X11_KHR, x->xdpy, err, errlen) < 0 ||
	    egl_common_make_window_context(p, opt, 0, NULL, err, errlen) < 0)
		return -1;
	*vid = 0;
	if (!eglGetConfigAttrib(p->dpy, p->config, EGL_NATIVE_VISUAL_ID, vid) || *vid == 0) {
		snprintf(err, errlen, "the EGLConfig has no X visual");
		return -1;
	}
	*vis = find_visual(x->screen, (xcb_visualid_t)*vid, depth);
	if (!*vis) {
		snprintf(err, errlen, "X visual 0x%x of the EGLConfig is not on the screen", (unsigned)*vid);
		return -1;
	}
	return 0;
}

/* The window (w x h, with its colormap and optional blank cursor). */
static int x11_create_window(struct x11_state *x, const struct platform_options *opt, EGLint vid, uint8_t depth,
                             int w, int h, char *err, size_t errlen)
{
	int px = 0, py = 0;
	x->cmap = xcb_generate_id(x->conn);
	xcb_create_colormap(x->conn, XCB_COLORMAP_ALLOC_NONE, x->cmap, x->screen->root, (xcb_visualid_t)vid);
	if (opt->hide_cursor)
		x->cursor = blank_cursor(x->conn, x->screen->root);
	uint32_t mask = XCB_CW_BACK_PIXEL | XCB_CW_BORDER_PIXEL | XCB_CW_EVENT_MASK | XCB_CW_COLORMAP;
	uint32_t values[5] = { 0, 0, XCB_EVENT_MASK_STRUCTURE_NOTIFY | XCB_EVENT_MASK_EXPOSURE, x->cmap, 0 };
	if (x->cursor) {
		mask |= XCB_CW_CURSOR;
		values[4] = x->cursor;
	}
	x->win = xcb_generate_id(x->conn);
	xcb_void_cookie_t ck = xcb_create_window_checked(x->conn, depth, x->win, x->screen->root, (int16_t)px,
	                                                 (int16_t)py, (uint16_t)w, (uint16_t)h, 0,
	                                                 XCB_WINDOW_CLASS_INPUT_OUTPUT, (xcb_visualid_t)vid, mask, values);
	xcb_generic_error_t *xe = xcb_request_check(x->conn, ck);
	if (xe) {
		snprintf(err, errlen, "xcb_create_window %dx%d failed: X error %u", w, h, xe->error_code);
		free(xe);
		x->win = 0;
		return -1;
	}
	return 0;
}

/* Title, class, WM_DELETE_WINDOW and, when asked, _NET_WM_STATE_FULLSCREEN. */
static int x11_set_properties(struct x11_state *x, const struct platform_options *opt, char *err, size_t errlen)
{
	static const char title[] = "isoterra";
	static const char wm_class[] = "isoterra\0isoterra";
	xcb_change_property(x->conn, XCB_PROP_MODE_REPLACE, x->win, XCB_ATOM_WM_NAME, XCB_ATOM_STRING, 8,
	                    sizeof(title) - 1, title);
	xcb_change_property(x->conn, XCB_PROP_MODE_REPLACE, x->win, XCB_ATOM_WM_CLASS, XCB_ATOM_STRING, 8,
	                    sizeof(wm_class), wm_class);
	x->wm_protocols = intern(x->conn, "WM_PROTOCOLS");
	x->wm_delete = intern(x->conn, "WM_DELETE_WINDOW");
	if (!x->wm_protocols || !x->wm_delete) {
		snprintf(err, errlen, "cannot intern WM_PROTOCOLS / WM_DELETE_WINDOW");
		return -1;
	}
	xcb_change_property(x->conn, XCB_PROP_MODE_REPLACE, x->win, x->wm_protocols, XCB_ATOM_ATOM, 32, 1,
	                    &x->wm_delete);
	if (opt->fullscreen) {
		xcb_atom_t state = intern(x->conn, "_NET_WM_STATE");
		xcb_atom_t full = intern(x->conn, "_NET_WM_STATE_FULLSCREEN");
		if (state && full)
			xcb_change_property(x->conn, XCB_PROP_MODE_REPLACE, x->win, state, XCB_ATOM_ATOM, 32, 1, &full);
	}
	return 0;
}

/* Maps the window and waits until it is on screen: a first frame drawn
 * before that would be lost (and --count 1 would show nothing). */
static int x11_map(struct platform *p, struct x11_state *x, int w, int h, char *err, size_t errlen)
{
	xcb_map_window(x->conn, x->win);
	if (xcb_flush(x->conn) <= 0) {
		snprintf(err, errlen, "x11: flushing the requests failed");
		return -1;
	}
	p->width = w;
	p->height = h;
	while (!x->mapped) {
		xcb_generic_event_t *ev = xcb_wait_for_event(x->conn);
		if (!ev) {
			snprintf(err, errlen, "x11: connection lost while mapping the window");
			return -1;
		}
		int q = handle_event(p, x, ev);
		free(ev);
		if (q) {
			snprintf(err, errlen, "x11: window closed before it was shown");
			return -1;
		}
	}
	return 0;
}

/* The MIT-SHM present on a pbuffer of the window's size: 0, or -1 with
 * the reason in why (nothing of it left then but, perhaps, the context). */
static int x11_shm_start(struct platform *p, struct x11_state *x, const struct platform_options *opt,
                         const xcb_visualtype_t *vis, uint8_t depth, char *why, size_t whylen)
{
	x->shm = x11_shm_open(x->conn, x->win, depth, vis, why, whylen);
	if (!x->shm)
		return -1;
	EGLConfig window_config = p->config;
	if (egl_common_make_pbuffer_context(p, opt, p->width, p->height, why, whylen) == 0) {
		const char *gl_exts = (const char *)glGetString(GL_EXTENSIONS);
		if (egl_common_has_ext(gl_exts, "GL_EXT_read_format_bgra")) {
			x->pb_w = p->width;
			x->pb_h = p->height;
			return 0;
		}
		snprintf(why, whylen, "the GL cannot read a frame back as BGRA (no GL_EXT_read_format_bgra)");
	}
	/* the window's config for its surface and a context of that config */
	egl_common_drop_context(p);
	p->config = window_config;
	x11_shm_close(x->shm);
	x->shm = NULL;
	return -1;
}

/* How frames reach the window (opt->x11_present), and the context current
 * on the surface that takes them. */
static int x11_start_present(struct platform *p, struct x11_state *x, const struct platform_options *opt,
                             const xcb_visualtype_t *vis, uint8_t depth, char *err, size_t errlen)
{
	char why[256] = "--x11-present swap";
	int mode = opt->x11_present;
	bool software = platform_display_software(p->dpy);
	if (mode == PLATFORM_X11_PRESENT_AUTO && !software)
		snprintf(why, sizeof(why), "the renderer is a GPU");
	else if (mode != PLATFORM_X11_PRESENT_SWAP && x11_shm_start(p, x, opt, vis, depth, why, sizeof(why)) == 0) {
		plog_info("x11: frames put through MIT-SHM (%s: read back into memory the X server shares)",
			  software ? "a software renderer" : "asked for");
		p->present_how = "MIT-SHM";
		return 0;
	}
	if (mode == PLATFORM_X11_PRESENT_SHM) {
		snprintf(err, errlen, "--x11-present shm: %s", why);
		return -1;
	}
	x->native = (Window)x->win;
	if (egl_common_make_window_context(p, opt, 0, &x->native, err, errlen) < 0)
		return -1;
	p->present_how = "eglSwapBuffers";
	if (software)
		plog_info("x11: frames presented with eglSwapBuffers (%s)", why);
	else
		plog_debug("x11: frames presented with eglSwapBuffers (%s)", why);
	return 0;
}

static int x11_open(struct platform *p, const struct platform_options *opt, char *err, size_t errlen)
{
	if (!x11_probe()) {
		snprintf(err, errlen, "EGL_KHR_platform_x11 not supported by this EGL");
		return -1;
	}
	struct x11_state *x = calloc(1, sizeof(*x));
	if (!x) {
		snprintf(err, errlen, "out of memory");
		return -1;
	}
	p->priv = x;
	EGLint vid;
	uint8_t depth;
	const xcb_visualtype_t *vis;
	if (x11_connect(x, err, errlen) < 0 || x11_egl_visual(p, x, opt, &vid, &vis, &depth, err, errlen) < 0)
		goto fail;
	int w = opt->width, h = opt->height;
	if (opt->fullscreen) {
		/* the window manager maximises it; without one, this size is it */
		w = x->screen->width_in_pixels;
		h = x->screen->height_in_pixels;
	}
	if (x11_create_window(x, opt, vid, depth, w, h, err, errlen) < 0 || x11_set_properties(x, opt, err, errlen) < 0 ||
	    x11_map(p, x, w, h, err, errlen) < 0)
		goto fail;
	if (x11_start_present(p, x, opt, vis, depth, err, errlen) < 0)
		goto fail;
	plog_debug("x11: window 0x%x %dx%d, visual 0x%x depth %u%s", (unsigned)x->win, p->width, p->height,
	          (unsigned)vid, depth, opt->fullscreen ? ", fullscreen" : "");
	return 0;
fail:
	x11_close(p);
	return -1;
}

static int x11_present(struct platform *p)
{
	struct x11_state *x = p->priv;
	if (x->shm) {
		if (x11_shm_present(x->shm, x->pb_w, x->pb_h) < 0)
			return -1;
		p->shown++;
		return 0;
	}
	if (!eglSwapBuffers(p->dpy, p->surface)) {
		plog_error("x11: eglSwapBuffers failed: %s", egl_common_error_name(eglGetError()));
		return -1;
	}
	p->shown++;
	return 0;
}

const struct platform_backend platform_backend_x11 = {
	.name = "x11",
	.probe = x11_probe,
	.open = x11_open,
	.close = x11_close,
	.present = x11_present,
	.dispatch = x11_dispatch,
};
