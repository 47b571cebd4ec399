/* isoterra — the form of a device option (--device, ISOTERRA_DEVICE): an
 * EGL device index or a DRM node path.  Pure text, no EGL: the command
 * line checks it when it is given, the device backend when it opens. */
#include "platform.h"

#include <stdio.h>
#include <string.h>

int platform_device_check(const char *spec, char *err, size_t errlen)
{
	if (!spec || !spec[0] || spec[0] == '/')
		return 0;
	size_t digits = strspn(spec, "0123456789");
	if (digits == strlen(spec) && digits <= 9)
		return 0;
	snprintf(err, errlen, "device: '%.200s' is neither an EGL device index (0, 1, ...) nor a DRM node path "
	         "such as /dev/dri/renderD128 (see --list-devices)", spec);
	return -1;
}
