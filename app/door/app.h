/* isoterra — the door of app/ (app.h) as main.c sees it: this
 * folder is on its include path, the rest of app/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../app.h"
