/* isoterra — the door of app/render/ (render.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/render/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../render.h"
