/* isoterra — the door of app/gpu/ (gpu.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/gpu/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../gpu.h"
