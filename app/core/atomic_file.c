/* isoterra — files written atomically: a temp file in the same directory,
 * fsync, then rename over the target; on any error the temp is removed and
 * the target is untouched.  A staged file (closed, not yet renamed) waits
 * for the rest of the run's outputs. */
#include "atomic_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "log.h"

int atomic_open(struct atomic_file *af, const char *path, char *err, size_t errlen)
{
	af->f = NULL;
	af->tmp = malloc(strlen(path) + 8);
	if (!af->tmp) {
		snprintf(err, errlen, "out of memory writing '%s'", path);
		return -1;
	}
	sprintf(af->tmp, "%s.XXXXXX", path);
	int fd = mkstemp(af->tmp);
	if (fd < 0) {
		snprintf(err, errlen, "cannot write '%s': %s", path, strerror(errno));
		free(af->tmp);
		af->tmp = NULL;
		return -1;
	}
	/* mkstemp makes 0600; give the file the mode a plain fopen would. */
	mode_t mask = umask(0);
	umask(mask);
	if (fchmod(fd, 0666 & ~mask) < 0)
		log_warn("cannot chmod '%s': %s", af->tmp, strerror(errno));
	af->f = fdopen(fd, "wb");
	if (!af->f) {
		snprintf(err, errlen, "cannot write '%s': %s", path, strerror(errno));
		close(fd);
		unlink(af->tmp);
		free(af->tmp);
		af->tmp = NULL;
		return -1;
	}
	return 0;
}

void atomic_abort(struct atomic_file *af)
{
	if (af->f)
		fclose(af->f);
	if (af->tmp) {
		unlink(af->tmp);
		free(af->tmp);
	}
	af->f = NULL;
	af->tmp = NULL;
}

int atomic_close(struct atomic_file *af, const char *path, char *err, size_t errlen)
{
	if (!af->f)
		return 0;
	int e = 0;
	if (fflush(af->f) != 0 || ferror(af->f))
		e = errno ? errno : EIO;
	else if (fsync(fileno(af->f)) < 0)
		e = errno;
	int rc = fclose(af->f);
	af->f = NULL;
	if (!e && rc != 0)
		e = errno;
	if (e) {
		snprintf(err, errlen, "cannot write '%s': %s", path, strerror(e));
		atomic_abort(af);
		return -1;
	}
	return 0;
}

int atomic_commit(struct atomic_file *af, const char *path, char *err, size_t errlen)
{
	if (atomic_close(af, path, err, errlen) < 0)
		return -1;
	if (rename(af->tmp, path) < 0) {
		snprintf(err, errlen, "cannot write '%s': %s", path, strerror(errno));
		atomic_abort(af);
		return -1;
	}
	free(af->tmp);
	af->tmp = NULL;
	return 0;
}
