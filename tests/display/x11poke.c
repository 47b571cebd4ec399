/* isoterra — test helper for the X11 backend: act like a window manager /
 * user on the window named NAME.
 *   x11poke resize NAME W H    ConfigureWindow to W x H
 *   x11poke close NAME         WM_DELETE_WINDOW client message (the close button)
 * Exit 0 done, 1 window not found / X error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <xcb/xcb.h>

static xcb_atom_t intern(xcb_connection_t *c, const char *name)
{
	xcb_intern_atom_reply_t *r = xcb_intern_atom_reply(c, xcb_intern_atom(c, 0, (uint16_t)strlen(name), name), NULL);
	xcb_atom_t a = r ? r->atom : XCB_ATOM_NONE;
	free(r);
	return a;
}

/* A top-level child of root whose WM_NAME is name (no WM: no reparenting). */
static xcb_window_t find(xcb_connection_t *c, xcb_window_t root, const char *name)
{
	xcb_query_tree_reply_t *t = xcb_query_tree_reply(c, xcb_query_tree(c, root), NULL);
	xcb_window_t found = 0;
	if (!t)
		return 0;
	xcb_window_t *kids = xcb_query_tree_children(t);
	for (int i = 0; i < xcb_query_tree_children_length(t) && !found; i++) {
		xcb_get_property_reply_t *p = xcb_get_property_reply(
			c, xcb_get_property(c, 0, kids[i], XCB_ATOM_WM_NAME, XCB_ATOM_STRING, 0, 64), NULL);
		if (p && xcb_get_property_value_length(p) == (int)strlen(name) &&
		    memcmp(xcb_get_property_value(p), name, strlen(name)) == 0)
			found = kids[i];
		free(p);
	}
	free(t);
	return found;
}

int main(int argc, char **argv)
{
	if (argc < 3 || (strcmp(argv[1], "resize") == 0 && argc != 5) || (strcmp(argv[1], "close") == 0 && argc != 3)) {
		fprintf(stderr, "usage: x11poke resize NAME W H | x11poke close NAME\n");
		return 2;
	}
	int scr = 0;
	xcb_connection_t *c = xcb_connect(NULL, &scr);
	if (xcb_connection_has_error(c)) {
		fprintf(stderr, "x11poke: cannot connect to the X server\n");
		return 1;
	}
	xcb_screen_t *s = xcb_setup_roots_iterator(xcb_get_setup(c)).data;
	xcb_window_t w = find(c, s->root, argv[2]);
	if (!w) {
		fprintf(stderr, "x11poke: no window named '%s'\n", argv[2]);
		xcb_disconnect(c);
		return 1;
	}
	if (strcmp(argv[1], "resize") == 0) {
		uint32_t v[2] = { (uint32_t)atoi(argv[3]), (uint32_t)atoi(argv[4]) };
		xcb_generic_error_t *e = xcb_request_check(
			c, xcb_configure_window_checked(c, w, XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT, v));
		if (e) {
			fprintf(stderr, "x11poke: ConfigureWindow: X error %u\n", e->error_code);
			free(e);
			xcb_disconnect(c);
			return 1;
		}
	} else {
		xcb_client_message_event_t ev;
		memset(&ev, 0, sizeof(ev));
		ev.response_type = XCB_CLIENT_MESSAGE;
		ev.format = 32;
		ev.window = w;
		ev.type = intern(c, "WM_PROTOCOLS");
		ev.data.data32[0] = intern(c, "WM_DELETE_WINDOW");
		ev.data.data32[1] = XCB_CURRENT_TIME;
		xcb_generic_error_t *e =
			xcb_request_check(c, xcb_send_event_checked(c, 0, w, XCB_EVENT_MASK_NO_EVENT, (const char *)&ev));
		if (e) {
			fprintf(stderr, "x11poke: SendEvent: X error %u\n", e->error_code);
			free(e);
			xcb_disconnect(c);
			return 1;
		}
	}
	/* checked requests: the server has handled them before we disconnect
	 * (an unchecked request followed by a disconnect was sometimes lost) */
	int rc = !xcb_connection_has_error(c) ? 0 : 1;
	xcb_disconnect(c);
	return rc;
}
