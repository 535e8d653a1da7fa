/* Private helpers around the Gmsh C API: turning a non-zero ierr into a
 * dtmap error that carries Gmsh's own last message, and counting models.
 * (White-box tests may include this header; nothing here is exported.) */
#ifndef DTM_GMSH_UTIL_H
#define DTM_GMSH_UTIL_H

#include "dtmap/error.h"

/* Raise DTM_ERR_INPUT or code with "<what>: <Gmsh's last error>". */
int dtm_gmsh_fail(int code, const char *file, int line, const char *func, const char *what);
#define DTM_GMSH_CHECK(ierr, code, what)                                                                               \
  do {                                                                                                                 \
    if (ierr) return dtm_gmsh_fail((code), __FILE__, __LINE__, __func__, (what));                                      \
  } while (0)

/* Number of models in the session: at least one once Gmsh is initialised,
 * none (silently) before gmshInitialize. */
int dtm_gmsh_model_count(void);

#endif
