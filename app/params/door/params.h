/* isoterra — the door of app/params/ (params.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/params/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../params.h"
