/* The recommended step: per limiting effect, the best estimate dtmap can
 * vouch for (the converged global estimate on its safe side when the
 * caller lets it be the basis, else the nodal bound, else the element
 * bound, and never below the element bound when that is a bound; a length
 * rule such as min-edge is not, and then only the nodal and global
 * estimates count), then the smallest over the effects, times the scene's
 * safety factor. Where an effect's basis is the global estimate with no
 * deterministic proof (global.c: the probable layer), its step is the
 * smaller of safety x the global step and the probable bound's certified
 * step, and never below safety x its element or nodal bound (both proofs):
 * the recommended step is then safe with probability at least 1 - 1e-12
 * for any spectrum, at any safety (at safety 1, the certified step).
 * Also each element's own safe step, the same rule taken locally: per
 * effect the larger of the element's step (when a bound) and the smallest
 * nodal bound at its nodes. Its minimum over the elements is at least the
 * basis whenever the global estimate is not the basis, since
 * min_e max(x_e, y_e) >= max(min_e x_e, min_e y_e).
 * The advice (size suggestion, the elements below the target and why,
 * mass scaling) holds those local steps against the target. On the global
 * basis it holds them against the target scaled by the bound basis over the
 * global one: a mesh whose global step meets the target has its nodal-bound
 * steps at that fraction of it, so a target the global step already meets
 * asks nothing of any element, and no element is reported below it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"

static double effect_safe(const dtm_effect_min *pe, int use_global, const char **basis) {
  double safe = pe->min;
  *basis = "element bound";
  if (isfinite(pe->nodal) && (pe->nodal >= safe || !pe->element_rigorous)) safe = pe->nodal, *basis = "nodal bound";
  if (use_global && isfinite(pe->global) && pe->global > safe) safe = pe->global, *basis = "global estimate";
  return safe;
}

/* Effect pe's step, safety included: safety x its safe step, capped by
 * the probable bound's certified step when the global estimate is its
 * basis, but never below safety x its bound (element or nodal). */
static double effect_step(const dtm_effect_min *pe, double safety, double bound, const char *basis, int *capped) {
  double step = safety * pe->safe;
  *capped = 0;
  if (strcmp(basis, "global estimate") || !(pe->certified < step)) return step;
  double floor = safety * bound;
  *capped = pe->certified > floor;
  return fmax(pe->certified, floor);
}

void dtm_recommend(dtm_analysis *a) {
  double best = INFINITY, bound = INFINITY, rec = INFINITY, safety = a->scene->safety;
  a->dt_nodal = a->dt_global = NAN;
  a->basis = "element bound";
  a->rec_certified = 0;
  for (int k = 0; k < a->neffects; k++) {
    dtm_effect_min *pe = &a->per_effect[k];
    if (!a->dt_effect[k]) continue;
    const char *basis, *unused;
    int capped;
    pe->safe = effect_safe(pe, a->global_basis, &basis);
    double own = effect_safe(pe, 0, &unused), step = effect_step(pe, safety, own, basis, &capped);
    bound = fmin(bound, own);
    if (isfinite(pe->nodal) && !(pe->nodal >= a->dt_nodal)) a->dt_nodal = pe->nodal;
    if (isfinite(pe->global) && !(pe->global >= a->dt_global)) a->dt_global = pe->global;
    if (pe->safe < best) best = pe->safe, a->basis = basis;
    if (step < rec) rec = step, a->rec_certified = capped;
  }
  a->best = best;
  a->recommended = isfinite(rec) ? rec : safety * best;
  double t = a->scene->target;
  a->advice_target = t > 0 && isfinite(best) && bound < best ? t * bound / best : t > 0 ? t : 0;
}

/* Own safe step of element e (local index) of block b for effect k. */
static double local_of(const dtm_analysis *a, int k, const dtm_block *blk, size_t e, size_t i) {
  double dt = a->dt_effect[k][i];
  if (!a->node_dt || !a->node_dt[k] || isinf(dt)) return dt;
  double nodal = INFINITY;
  for (int c = 0; c < blk->nn; c++) nodal = fmin(nodal, a->node_dt[k][blk->conn[e * blk->nn + c]]);
  return a->per_effect[k].element_rigorous ? fmax(dt, nodal) : nodal;
}

int dtm_local_steps(dtm_analysis *a) {
  a->local = malloc((a->nel + 1) * sizeof *a->local);
  if (!a->local) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int b = 0; b < a->mesh->nblocks; b++) {
    const dtm_block *blk = &a->mesh->blocks[b];
#pragma omp parallel for schedule(static)
    for (size_t e = 0; e < blk->n; e++) {
      size_t i = a->offset[b] + e;
      a->local[i] = INFINITY;
      for (int k = 0; k < a->neffects; k++)
        if (a->dt_effect[k]) a->local[i] = fmin(a->local[i], local_of(a, k, blk, e, i));
    }
  }
  return DTM_OK;
}
