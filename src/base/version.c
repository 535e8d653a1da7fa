/* The version of libdtmap itself, fixed at build time from the project's
 * version in CMakeLists.txt. */
#include "dtmap/version.h"

const char *dtm_version(void) { return DTM_VERSION; }
