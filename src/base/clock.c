/* The one clock of dtmap: CLOCK_MONOTONIC in seconds, for stage timings
 * and benchmarks. */
#include <time.h>

#include "dtmap/util.h"

double dtm_wtime(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
