/* CHOLMOD's functions looked up at first use (cholmod_dl.h says why): one
 * dlopen of the library the build linked against before, by its soname,
 * and one dlsym per function, under a once-only guard so that threads
 * asking together load it once. A machine without the library (it is a
 * dependency of the package, so only a broken install) gets an error from
 * the certificate or --modes, not from every command at start. */
#define DTM_CHOLMOD_DL_IMPL
#include "cholmod_dl.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>

#include "dtmap/error.h"

#ifndef DTM_CHOLMOD_SONAME
#define DTM_CHOLMOD_SONAME "libcholmod.so.3"
#endif

dtm_cholmod_table dtm_cholmod_fns;

static pthread_once_t once = PTHREAD_ONCE_INIT;
static char failure[512]; /* why the load failed, "" when it did not */

static void load(void) {
  void *h = dlopen(DTM_CHOLMOD_SONAME, RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    snprintf(failure, sizeof failure, "%s", dlerror());
    return;
  }
#define DTM_CHOLMOD_LOOKUP(f)                                                                                          \
  if (!failure[0] && !(*(void **)&dtm_cholmod_fns.f = dlsym(h, #f)))                                                   \
    snprintf(failure, sizeof failure, "%s has no %s", DTM_CHOLMOD_SONAME, #f);
  DTM_CHOLMOD_FUNCTIONS(DTM_CHOLMOD_LOOKUP)
#undef DTM_CHOLMOD_LOOKUP
}

int dtm_cholmod_load(void) {
  pthread_once(&once, load);
  if (!failure[0]) return DTM_OK;
  return DTM_ERR(DTM_ERR_INTERNAL, "CHOLMOD (SuiteSparse, the sparse factorisation) cannot be loaded: %s", failure);
}
