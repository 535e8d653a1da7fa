/* The recommended step: per limiting effect, the best estimate dtmap can
 * vouch for (the converged global estimate on its safe side, else the nodal
 * bound, else the element bound, and never below the element bound when
 * that is a bound; a length rule such as min-edge is not, and then only the
 * nodal and global estimates count), then the smallest over the effects,
 * times the scene's safety factor. */
#include <math.h>

#include "analysis-impl.h"

static double effect_safe(const dtm_effect_min *pe, const char **basis) {
  double safe = pe->min;
  *basis = "element bound";
  if (isfinite(pe->nodal) && (pe->nodal > safe || !pe->element_rigorous)) safe = pe->nodal, *basis = "nodal bound";
  if (isfinite(pe->global) && pe->global > safe) safe = pe->global, *basis = "global estimate";
  return safe;
}

void dtm_recommend(dtm_analysis *a) {
  double best = INFINITY;
  a->dt_nodal = a->dt_global = NAN;
  a->basis = "element bound";
  for (int k = 0; k < a->neffects; k++) {
    dtm_effect_min *pe = &a->per_effect[k];
    if (!a->dt_effect[k]) continue;
    const char *basis;
    pe->safe = effect_safe(pe, &basis);
    if (isfinite(pe->nodal) && !(pe->nodal >= a->dt_nodal)) a->dt_nodal = pe->nodal;
    if (isfinite(pe->global) && !(pe->global >= a->dt_global)) a->dt_global = pe->global;
    if (pe->safe < best) best = pe->safe, a->basis = basis;
  }
  a->recommended = a->scene->safety * best;
}
