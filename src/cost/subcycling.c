/* Subcycling levels from the recommended step: element e steps at b 2^k,
 * b the basis of dt.recommended (before safety), k the largest level with
 * b 2^k <= s_e, s_e the element's own safe step (the larger of its element
 * bound and the smallest nodal bound at its nodes, per effect: the two
 * estimators the recommendation combines, taken locally), so an element
 * whose step is exactly b 2^k is on level k; clamped to DTM_MAX_LEVELS - 1.
 * Level 0 is the recommended step itself, and no element is below it: s_e
 * >= b whenever the basis is a bound (min_e max(x_e, y_e) >= max(min x,
 * min y)), and with the global estimate as the basis the whole mesh is
 * stable at b, so an element below it stays on level 0. Every level is
 * >= 0, hence the ideal speed-up N / sum_k N_k 2^-k is >= 1 and the
 * subcycled cost never exceeds the plain one. Elements without a finite
 * step (no effect limits them) join the highest finite level; a NaN step is
 * put on level 0, the safe side. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/error.h"

/* Level of a finite step dt against the basis b, whose levels' steps are
 * at[k] = b 2^k (exact): the largest k with at[k] <= dt, 0 below b. The
 * binary exponent of dt / b guesses it, exact comparisons with at[] settle
 * it, so rounding in the division never moves an element across a level
 * boundary. */
static int level_of(double dt, const double *at) {
  if (!(dt > at[0])) return 0;
  int k = ilogb(dt / at[0]);
  k = k < 0 ? 0 : k > DTM_MAX_LEVELS - 1 ? DTM_MAX_LEVELS - 1 : k;
  while (k > 0 && at[k] > dt) k--;
  while (k < DTM_MAX_LEVELS - 1 && at[k + 1] <= dt) k++;
  return k;
}

static double speedup_of(const dtm_subcycling *sc, size_t n) {
  double work = 0.0;
  for (int k = 0; k < sc->nlevels; k++) work += ldexp((double)sc->count[k], -k);
  return work > 0 ? (double)n / work : 1.0;
}

int dtm_subcycling_compute(const dtm_analysis *a, dtm_subcycling *sc) {
  DTM_CHECK(
      dtm_subcycling_levels(dtm_analysis_local_step(a), dtm_analysis_nelements(a), dtm_analysis_basis_step(a), sc));
  sc->basis = dtm_analysis_recommended(a);
  return DTM_OK;
}

int dtm_subcycling_levels(const double *own, size_t n, double b, dtm_subcycling *sc) {
  double at[DTM_MAX_LEVELS];
  memset(sc, 0, sizeof *sc);
  sc->level = calloc(n + 1, sizeof *sc->level);
  if (!sc->level) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the levels of %zu elements", n);
  int ok = b > 0 && isfinite(b), top = 0, infinite = 0;
  for (int k = 0; k < DTM_MAX_LEVELS; k++) at[k] = ldexp(b, k);
  size_t count[DTM_MAX_LEVELS] = {0};
  int nlevels = 0;
  /* every loop is per element; the reductions are counts and maxima: any order gives the same */
  if (ok) { /* else every element at level 0 */
#pragma omp parallel for schedule(static) reduction(max : top) reduction(| : infinite)
    for (size_t i = 0; i < n; i++) {
      int inf = isinf(own[i]) && own[i] > 0, k = inf ? 0 : level_of(own[i], at);
      sc->level[i] = k, infinite |= inf;
      if (!inf && isfinite(own[i]) && k > top) top = k;
    }
  }
#pragma omp parallel for schedule(static) reduction(+ : count[:DTM_MAX_LEVELS]) reduction(max : nlevels)
  for (size_t i = 0; i < n; i++) {
    if (infinite && isinf(own[i]) && own[i] > 0) sc->level[i] = top; /* no finite step: the highest finite level */
    int k = sc->level[i];
    count[k]++;
    if (k + 1 > nlevels) nlevels = k + 1;
  }
  memcpy(sc->count, count, sizeof count);
  sc->nlevels = nlevels;
  sc->speedup = speedup_of(sc, n);
  sc->basis = b;
  return DTM_OK;
}

void dtm_subcycling_free(dtm_subcycling *sc) {
  free(sc->level);
  sc->level = NULL;
}
