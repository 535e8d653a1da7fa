/* Subcycling levels from the dt map: element e steps at dt_min 2^k, k the
 * largest level with dt_min 2^k <= dt_e (so an element whose step is
 * exactly dt_min 2^k is on level k), clamped to DTM_MAX_LEVELS - 1. The
 * ideal speed-up over one global step dt_min is N / sum_k N_k 2^-k.
 * Elements without a finite step (no effect limits them) join the highest
 * finite level; a NaN step is put on level 0, the safe side. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/error.h"

/* Level of a finite step dt >= dt_min: floor(log2(dt/dt_min)), corrected by
 * exact comparisons with dt_min 2^k (ldexp is exact) so that rounding in
 * log2 never moves an element across a level boundary. */
static int level_of(double dt, double dt_min) {
  if (!(dt > dt_min)) return 0;
  double l = floor(log2(dt / dt_min));
  int k = l < 0 ? 0 : l > DTM_MAX_LEVELS - 1 ? DTM_MAX_LEVELS - 1 : (int)l;
  while (k > 0 && ldexp(dt_min, k) > dt) k--;
  while (k < DTM_MAX_LEVELS - 1 && ldexp(dt_min, k + 1) <= dt) k++;
  return k;
}

/* Highest level of the finite steps. */
static int top_finite_level(const double *dt, size_t n, double dt_min) {
  int top = 0;
  for (size_t i = 0; i < n; i++)
    if (isfinite(dt[i])) {
      int k = level_of(dt[i], dt_min);
      if (k > top) top = k;
    }
  return top;
}

static double speedup_of(const dtm_subcycling *sc, size_t n) {
  double work = 0.0;
  for (int k = 0; k < sc->nlevels; k++) work += ldexp((double)sc->count[k], -k);
  return work > 0 ? (double)n / work : 1.0;
}

int dtm_subcycling_compute(const dtm_analysis *a, dtm_subcycling *sc) {
  size_t n = dtm_analysis_nelements(a);
  const double *dts = dtm_analysis_dt(a), dt_min = dtm_analysis_dt_min(a, NULL);
  memset(sc, 0, sizeof *sc);
  sc->level = calloc(n + 1, sizeof *sc->level);
  if (!sc->level) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the levels of %zu elements", n);
  int ok = dt_min > 0 && isfinite(dt_min), top = ok ? top_finite_level(dts, n, dt_min) : 0;
  for (size_t i = 0; i < n; i++) {
    double dt = dts[i];
    int k = !ok ? 0 : isinf(dt) && dt > 0 ? top : level_of(dt, dt_min);
    sc->level[i] = k;
    sc->count[k]++;
    if (k + 1 > sc->nlevels) sc->nlevels = k + 1;
  }
  sc->speedup = speedup_of(sc, n);
  return DTM_OK;
}

void dtm_subcycling_free(dtm_subcycling *sc) {
  free(sc->level);
  sc->level = NULL;
}
