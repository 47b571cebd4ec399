/* isoterra — GLES 3.1 capability checks, KHR_debug routing, error checks. */
#include "gpu.h"
#include "gl_limits.h"
#include "core.h"
#include "platform.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GLES2/gl2ext.h>
#include <stdio.h>
#include <string.h>

static void GL_APIENTRY debug_cb(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
				 const GLchar *message, const void *user)
{
	(void)id;
	(void)length;
	(void)user;
	enum log_level lvl = LOG_DEBUG;
	if (source == GL_DEBUG_SOURCE_SHADER_COMPILER_KHR)
		lvl = LOG_DEBUG; /* reported once, as file:line, by the loader */
	else if (type == GL_DEBUG_TYPE_ERROR_KHR || severity == GL_DEBUG_SEVERITY_HIGH_KHR)
		lvl = LOG_WARN;
	else if (severity == GL_DEBUG_SEVERITY_MEDIUM_KHR)
		lvl = LOG_INFO;
	log_msg(lvl, "GL: %s", message);
}

static bool has_ext(const char *exts, const char *name)
{
	size_t n = strlen(name);
	for (const char *p = exts; p && (p = strstr(p, name)); p += n)
		if ((p == exts || p[-1] == ' ') && (p[n] == ' ' || p[n] == 0))
			return true;
	return false;
}

int gpu_init(struct gpu_caps *caps, bool debug, char *err, size_t errlen)
{
	memset(caps, 0, sizeof(*caps));
	const char *ver = platform_check_gles31(err, errlen);
	const char *ren = (const char *)glGetString(GL_RENDERER);
	if (!ver)
		return -1;
	snprintf(caps->version, sizeof(caps->version), "%s", ver);
	snprintf(caps->renderer, sizeof(caps->renderer), "%s", ren ? ren : "?");
	/* every limit the passes rely on, or one line naming the one too small */
	if (gl_limits_check(NULL, err, errlen) < 0)
		return -1;
	glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &caps->max_ssbo_size);
	for (int i = 0; i < 3; i++)
		glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, (GLuint)i, &caps->max_group_count[i]);
	if (gpu_check("capability query") < 0) {
		snprintf(err, errlen, "querying compute limits failed (is this really GLES 3.1?)");
		return -1;
	}
	const char *exts = (const char *)glGetString(GL_EXTENSIONS);
	caps->khr_debug = has_ext(exts, "GL_KHR_debug");
	if (caps->khr_debug) {
		PFNGLDEBUGMESSAGECALLBACKKHRPROC cb =
			(PFNGLDEBUGMESSAGECALLBACKKHRPROC)eglGetProcAddress("glDebugMessageCallbackKHR");
		PFNGLDEBUGMESSAGECONTROLKHRPROC ctl =
			(PFNGLDEBUGMESSAGECONTROLKHRPROC)eglGetProcAddress("glDebugMessageControlKHR");
		if (cb && ctl) {
			cb(debug_cb, NULL);
			/* errors and warnings always; everything in debug mode */
			ctl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, NULL, debug ? GL_TRUE : GL_FALSE);
			ctl(GL_DONT_CARE, GL_DEBUG_TYPE_ERROR_KHR, GL_DONT_CARE, 0, NULL, GL_TRUE);
			ctl(GL_DONT_CARE, GL_DONT_CARE, GL_DEBUG_SEVERITY_HIGH_KHR, 0, NULL, GL_TRUE);
			if (debug)
				glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS_KHR);
			glEnable(GL_DEBUG_OUTPUT_KHR);
			(void)glGetError();
		}
	}
	/* programs issued ahead (gpu_prefetch_*) build on the driver's threads */
	if (has_ext(exts, "GL_KHR_parallel_shader_compile")) {
		PFNGLMAXSHADERCOMPILERTHREADSKHRPROC threads =
			(PFNGLMAXSHADERCOMPILERTHREADSKHRPROC)eglGetProcAddress("glMaxShaderCompilerThreadsKHR");
		if (threads) {
			threads(0xffffffffu); /* as many as the driver likes */
			gpu_check("glMaxShaderCompilerThreadsKHR");
		}
	}
	log_debug("GL: %s / %s, max SSBO %d bytes, max groups %d x %d x %d", caps->renderer, caps->version,
		  caps->max_ssbo_size, caps->max_group_count[0], caps->max_group_count[1], caps->max_group_count[2]);
	return 0;
}

int gpu_check(const char *what)
{
	GLenum e = glGetError();
	if (e == GL_NO_ERROR)
		return 0;
	log_error("%s: GL error 0x%04x", what, e);
	while (glGetError() != GL_NO_ERROR)
		;
	return -1;
}

/* Asked once per display (platform_display_software). */
bool gpu_software_rasterizer(void)
{
	static EGLDisplay asked = EGL_NO_DISPLAY;
	static bool software;
	EGLDisplay dpy = eglGetCurrentDisplay();
	if (dpy == EGL_NO_DISPLAY || dpy == asked)
		return dpy != EGL_NO_DISPLAY && software;
	asked = dpy;
	software = platform_display_software(dpy);
	log_debug("EGL device of this display: %s", software ? "software (EGL_MESA_device_software)" : "hardware");
	return software;
}

int gpu_fence_read(GLsync *fence, GLuint buf, GLsizeiptr size, void *out, bool wait)
{
	GLenum st = glClientWaitSync(*fence, wait ? GL_SYNC_FLUSH_COMMANDS_BIT : 0,
				     wait ? 10ull * 1000 * 1000 * 1000 : 0);
	if (st != GL_ALREADY_SIGNALED && st != GL_CONDITION_SATISFIED)
		return 0;
	glDeleteSync(*fence);
	*fence = 0;
	glBindBuffer(GL_COPY_READ_BUFFER, buf);
	void *m = size > 0 ? glMapBufferRange(GL_COPY_READ_BUFFER, 0, size, GL_MAP_READ_BIT) : NULL;
	if (m) {
		memcpy(out, m, (size_t)size);
		glUnmapBuffer(GL_COPY_READ_BUFFER);
	}
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	return m ? 1 : -1;
}

void gpu_texture_2d_storage(GLenum fmt, int w, int h, GLint filter)
{
	glTexStorage2D(GL_TEXTURE_2D, 1, fmt, w, h);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
	glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

int gpu_read_buffer(GLuint buf, GLintptr off, GLsizeiptr size, void *out)
{
	if (size <= 0)
		return 0;
	glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
	glBindBuffer(GL_COPY_READ_BUFFER, buf);
	void *m = glMapBufferRange(GL_COPY_READ_BUFFER, off, size, GL_MAP_READ_BIT);
	if (!m) {
		glBindBuffer(GL_COPY_READ_BUFFER, 0);
		gpu_check("glMapBufferRange (read-back)");
		return -1;
	}
	memcpy(out, m, (size_t)size);
	GLboolean ok = glUnmapBuffer(GL_COPY_READ_BUFFER);
	glBindBuffer(GL_COPY_READ_BUFFER, 0);
	return ok ? 0 : -1;
}
