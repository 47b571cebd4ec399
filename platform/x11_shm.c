/* isoterra — the X11 present through MIT-SHM.  The finished frame is read
 * back (glReadPixels as BGRA, the X server's 32-bit xRGB in memory) into a
 * memfd segment the server maps (MIT-SHM 1.2, xcb_shm_attach_fd), and put
 * into the window from there: no pixel crosses the X connection.  This is
 * the present for a software rasterizer, where eglSwapBuffers (Mesa 22's
 * EGL on X11) writes the whole frame into the socket and the server reads
 * it out again.  GL's rows run bottom-up and X's top-down: one put request
 * per row, each a few bytes.  The segment holds two frames, used in turn,
 * so that the server's copy of one overlaps the drawing of the next; a
 * round trip sent after a frame's last row tells the present two frames
 * on that the server has read it. */
#define _GNU_SOURCE /* memfd_create */
#include "x11_shm.h"

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>

#include <GLES3/gl31.h>
#include <GLES2/gl2ext.h> /* GL_BGRA_EXT */
#include <xcb/shm.h>

#include "platform_util.h"

struct x11_shm {
	xcb_connection_t *conn;
	xcb_window_t win;
	xcb_gcontext_t gc;
	uint8_t depth;
	xcb_shm_seg_t seg; /* 0: none attached yet */
	uint8_t *map;
	size_t size, half; /* two frames of at most `half` bytes */
	unsigned next;     /* the half the next frame goes to */
	/* per half: a frame was put from it; fence answers once the server read it */
	bool pending[2];
	xcb_get_input_focus_cookie_t fence[2];
};

/* The pixmap format of this depth: 32 bits a pixel, rows padded to 32 bits. */
static bool format_32(xcb_connection_t *conn, uint8_t depth)
{
	const xcb_setup_t *setup = xcb_get_setup(conn);
	for (xcb_format_iterator_t f = xcb_setup_pixmap_formats_iterator(setup); f.rem; xcb_format_next(&f))
		if (f.data->depth == depth)
			return f.data->bits_per_pixel == 32 && f.data->scanline_pad == 32;
	return false;
}

struct x11_shm *x11_shm_open(xcb_connection_t *conn, xcb_window_t win, uint8_t depth, const xcb_visualtype_t *vis,
                             char *why, size_t whylen)
{
	const xcb_query_extension_reply_t *ext = xcb_get_extension_data(conn, &xcb_shm_id);
	if (!ext || !ext->present) {
		snprintf(why, whylen, "the X server has no MIT-SHM");
		return NULL;
	}
	xcb_shm_query_version_reply_t *v = xcb_shm_query_version_reply(conn, xcb_shm_query_version(conn), NULL);
	if (!v) {
		snprintf(why, whylen, "MIT-SHM QueryVersion failed");
		return NULL;
	}
	bool fd_passing = v->major_version > 1 || (v->major_version == 1 && v->minor_version >= 2);
	if (!fd_passing)
		snprintf(why, whylen, "MIT-SHM %u.%u has no segments passed as files (1.2)", v->major_version,
			 v->minor_version);
	free(v);
	if (!fd_passing)
		return NULL;
	const xcb_setup_t *setup = xcb_get_setup(conn);
	if (setup->image_byte_order != XCB_IMAGE_ORDER_LSB_FIRST || !vis || depth != 24 || !format_32(conn, depth) ||
	    vis->_class != XCB_VISUAL_CLASS_TRUE_COLOR || vis->red_mask != 0xff0000u || vis->green_mask != 0xff00u ||
	    vis->blue_mask != 0xffu) {
		snprintf(why, whylen, "the window's pixels are not 32-bit little-endian xRGB (depth %u)", depth);
		return NULL;
	}
	struct x11_shm *s = calloc(1, sizeof(*s));
	if (!s) {
		snprintf(why, whylen, "out of memory");
		return NULL;
	}
	s->conn = conn;
	s->win = win;
	s->depth = depth;
	s->gc = xcb_generate_id(conn);
	uint32_t no_exposures = 0;
	xcb_generic_error_t *e =
		xcb_request_check(conn, xcb_create_gc_checked(conn, s->gc, win, XCB_GC_GRAPHICS_EXPOSURES, &no_exposures));
	if (e) {
		snprintf(why, whylen, "xcb_create_gc failed: X error %u", e->error_code);
		free(e);
		free(s);
		return NULL;
	}
	return s;
}

/* Waits for the server to have read the frame put from half k (its
 * requests run in order: the reply to the round trip sent after them says
 * so). */
static int wait_read(struct x11_shm *s, unsigned k)
{
	if (!s->pending[k])
		return 0;
	s->pending[k] = false;
	xcb_get_input_focus_reply_t *r = xcb_get_input_focus_reply(s->conn, s->fence[k], NULL);
	if (!r) {
		plog_error("x11: the X server did not answer (connection lost?)");
		return -1;
	}
	free(r);
	return 0;
}

static void detach(struct x11_shm *s)
{
	if (s->seg) {
		xcb_shm_detach(s->conn, s->seg);
		s->seg = 0;
	}
	if (s->map && munmap(s->map, s->size) != 0)
		plog_warn("x11: munmap of the shared frame: %s", strerror(errno));
	s->map = NULL;
	s->size = s->half = 0;
}

/* A segment of two frames of at least `need` bytes, shared with the
 * server (read-only there); the server done with the old one.  0, or -1
 * logged. */
static int attach(struct x11_shm *s, size_t need)
{
	if (need <= s->half)
		return 0;
	if (wait_read(s, 0) < 0 || wait_read(s, 1) < 0)
		return -1;
	detach(s);
	size_t half = (need + 65535) & ~(size_t)65535, size = 2 * half;
	int fd = memfd_create("isoterra-x11-frame", MFD_CLOEXEC);
	if (fd < 0) {
		plog_error("x11: memfd_create for the shared frame: %s", strerror(errno));
		return -1;
	}
	if (ftruncate(fd, (off_t)size) != 0) {
		plog_error("x11: a shared frame of %zu bytes: %s", size, strerror(errno));
		close(fd);
		return -1;
	}
	void *map = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
	if (map == MAP_FAILED) {
		plog_error("x11: mmap of the shared frame (%zu bytes): %s", size, strerror(errno));
		close(fd);
		return -1;
	}
	xcb_shm_seg_t seg = xcb_generate_id(s->conn);
	/* xcb sends the descriptor and closes it */
	xcb_generic_error_t *e = xcb_request_check(s->conn, xcb_shm_attach_fd_checked(s->conn, seg, fd, 1));
	if (e) {
		plog_error("x11: the X server refused the shared frame (MIT-SHM AttachFd): X error %u", e->error_code);
		free(e);
		munmap(map, size);
		return -1;
	}
	s->seg = seg;
	s->map = map;
	s->size = size;
	s->half = half;
	plog_debug("x11: shared frame of %zu KiB attached", size >> 10);
	return 0;
}

/* glReadPixels of the default framebuffer into dst, tightly packed; the
 * caller's read framebuffer, pack buffer and pack parameters put back. */
static int read_frame(int w, int h, void *dst)
{
	GLint fb = 0, pbo = 0, align = 4, row = 0, skip_px = 0, skip_rows = 0;
	glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &fb);
	glGetIntegerv(GL_PIXEL_PACK_BUFFER_BINDING, &pbo);
	glGetIntegerv(GL_PACK_ALIGNMENT, &align);
	glGetIntegerv(GL_PACK_ROW_LENGTH, &row);
	glGetIntegerv(GL_PACK_SKIP_PIXELS, &skip_px);
	glGetIntegerv(GL_PACK_SKIP_ROWS, &skip_rows);
	glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
	glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
	glPixelStorei(GL_PACK_ALIGNMENT, 4);
	glPixelStorei(GL_PACK_ROW_LENGTH, 0);
	glPixelStorei(GL_PACK_SKIP_PIXELS, 0);
	glPixelStorei(GL_PACK_SKIP_ROWS, 0);
	glReadPixels(0, 0, w, h, GL_BGRA_EXT, GL_UNSIGNED_BYTE, dst);
	GLenum err = glGetError();
	glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)fb);
	glBindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)pbo);
	glPixelStorei(GL_PACK_ALIGNMENT, align);
	glPixelStorei(GL_PACK_ROW_LENGTH, row);
	glPixelStorei(GL_PACK_SKIP_PIXELS, skip_px);
	glPixelStorei(GL_PACK_SKIP_ROWS, skip_rows);
	if (err != GL_NO_ERROR) {
		plog_error("x11: reading the frame back (glReadPixels %dx%d BGRA): GL error 0x%04x", w, h, err);
		return -1;
	}
	return 0;
}

int x11_shm_present(struct x11_shm *s, int w, int h)
{
	if (w <= 0 || h <= 0 || w > 32767 || h > 32767) {
		plog_error("x11: a frame of %dx%d cannot be put", w, h);
		return -1;
	}
	unsigned k = s->next;
	if (attach(s, (size_t)w * (size_t)h * 4) < 0 || wait_read(s, k) < 0 ||
	    read_frame(w, h, s->map + k * s->half) < 0)
		return -1;
	for (int y = 0; y < h; y++)
		xcb_shm_put_image(s->conn, s->win, s->gc, (uint16_t)w, (uint16_t)h, 0, (uint16_t)(h - 1 - y), (uint16_t)w,
				  1, 0, (int16_t)y, s->depth, XCB_IMAGE_FORMAT_Z_PIXMAP, 0, s->seg,
				  (uint32_t)(k * s->half));
	s->fence[k] = xcb_get_input_focus(s->conn);
	s->pending[k] = true;
	s->next = k ^ 1;
	if (xcb_flush(s->conn) <= 0) {
		plog_error("x11: sending the frame failed (connection lost?)");
		return -1;
	}
	return 0;
}

void x11_shm_close(struct x11_shm *s)
{
	if (!s)
		return;
	if (!xcb_connection_has_error(s->conn)) {
		(void)wait_read(s, 0);
		(void)wait_read(s, 1);
		detach(s);
		xcb_free_gc(s->conn, s->gc);
		xcb_flush(s->conn);
	} else if (s->map) {
		munmap(s->map, s->size);
	}
	free(s);
}
