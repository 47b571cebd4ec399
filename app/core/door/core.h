/* isoterra — the door of app/core/ (core.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/core/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../core.h"
