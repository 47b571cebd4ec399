/* isoterra — the door of app/probe/ (probe.h) as main.c sees it: this
 * folder is on its include path, the rest of app/probe/ is not
 * (app/meson.build; docs/ARCHITECTURE.md, "Dependencies point one way"). */
#include "../probe.h"
