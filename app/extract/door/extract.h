/* isoterra — the door of app/extract/ (extract.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/extract/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../extract.h"
