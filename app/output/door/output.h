/* isoterra — the door of app/output/ (output.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/output/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../output.h"
