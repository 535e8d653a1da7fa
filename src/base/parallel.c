/* Errors inside OpenMP regions: a worker keeps the first error with its
 * message and clears its own thread-local record; the caller re-raises it
 * on its own thread after the region, so the message and the exit code
 * survive and no stale error stays pending on a worker thread. */
#include <stdio.h>

#include "base.h"

void dtm_par_error_keep(dtm_par_error *pe, int r) {
#pragma omp critical
  if (!pe->code) {
    pe->code = r;
    snprintf(pe->msg, sizeof pe->msg, "%s", dtm_error_message());
  }
  dtm_error_clear();
}

int dtm_par_error_raise(const dtm_par_error *pe) {
  if (!pe->code) return DTM_OK;
  return DTM_ERR(pe->code, "%s", pe->msg);
}
