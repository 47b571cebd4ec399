/* isoterra — the door of app/terrain/ (terrain.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/terrain/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../terrain.h"
