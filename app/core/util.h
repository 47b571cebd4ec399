/* isoterra — small helpers every folder uses. */
#ifndef ISOTERRA_UTIL_H
#define ISOTERRA_UTIL_H

/* Number of elements of an array (not a pointer). */
#define ARRAY_SIZE(a) (sizeof(a) / sizeof((a)[0]))

#endif
