/* isoterra — the door of app/scene/ (scene.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/scene/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../scene.h"
