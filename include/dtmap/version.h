/* Versions of the libdtmap a program runs with (which may be newer than the
 * headers it was compiled with): dtmap's own release, and the effect API
 * its loader accepts is in dtmap/registry.h. The Gmsh that libdtmap runs on
 * is in dtmap/gmsh.h (dtm_gmsh_version). */
#ifndef DTMAP_VERSION_H
#define DTMAP_VERSION_H

#include "dtmap/export.h"

/* dtmap's version, "MAJOR.MINOR.PATCH" (owned by the library). */
DTM_EXPORT const char *dtm_version(void);

#endif
