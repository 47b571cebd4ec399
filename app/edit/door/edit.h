/* isoterra — the door of app/edit/ (edit.h) as the folders above it see it: this
 * folder is on their include path, the rest of app/edit/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../edit.h"
