/* isoterra — small helpers every folder uses. */
#ifndef ISOTERRA_UTIL_H
#define ISOTERRA_UTIL_H

/* Number of elements of an array (not a pointer). */
#define ARRAY_SIZE(a) (sizeof(a) / sizeof((a)[0]))

#include <ctype.h>
#include <string.h>

/* s without its leading and trailing white space (cut in place). */
static inline char *str_trim(char *s)
{
	while (isspace((unsigned char)*s))
		s++;
	char *e = s + strlen(s);
	while (e > s && isspace((unsigned char)e[-1]))
		*--e = 0;
	return s;
}

#endif
