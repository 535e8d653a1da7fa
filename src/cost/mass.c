/* Mass scaling, the alternative to remeshing for a target step: every
 * element whose own wave step dt_e (the smallest over the wave-type effects,
 * exponent 1, damping already applied) is below the target dt_t gets
 * m_e ((dt_t/dt_e)^2 - 1) of added mass, m_e = rho_e V_e with V_e the
 * element's measure (per unit thickness in 2D, per unit cross-section in
 * 1D). Reported per element, per physical group (the last slot collects the
 * elements in no group) and in total. Elements whose material has no
 * density count no mass; elements without a finite wave step get none. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/kernel.h"

/* The element's own wave step: min over the wave-type effects, s; +inf
 * when no wave-type effect limits it. */
static double wave_dt(const dtm_analysis *a, size_t i) {
  double dt = INFINITY;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const double *dk = dtm_analysis_effect_dt(a, k);
    if (dk && dtm_effect_is_wave(dtm_analysis_effect(a, k)) && dk[i] < dt) dt = dk[i];
  }
  return dt;
}

/* rho V of element e of block blk, kg (0 without a density). */
static double element_mass(const dtm_analysis *a, const dtm_block *blk, size_t e, int irho) {
  int mi = blk->mat[e];
  if (mi < 0) return 0.0;
  const dtm_material *m = &dtm_analysis_scene(a)->materials[mi].m;
  if (!dtm_material_has(m, irho)) return 0.0;
  double x[DTM_MAX_NODES * 3];
  dtm_block one = *blk;
  one.n = 1;
  one.conn = blk->conn + e * (size_t)blk->nn;
  dtm_mesh_gather(dtm_analysis_mesh(a), &one, x);
  double v = fabs(dtm_elem_measure(blk->type, x));
  return isfinite(v) ? dtm_material_get(m, irho) * v : 0.0;
}

/* Mass to add to an element of mass m and wave step dt to reach target. */
static double added_mass(double m, double dt, double target) {
  if (!(dt > 0) || !isfinite(dt) || dt >= target) return 0.0;
  double r = target / dt;
  return m * (r * r - 1.0);
}

static int alloc_scaling(const dtm_analysis *a, dtm_mass_scaling *ms) {
  size_t nel = dtm_analysis_nelements(a);
  ms->ngroups = dtm_analysis_mesh(a)->ngroups + 1;
  ms->added = calloc(nel + 1, sizeof *ms->added);
  ms->group_mass = calloc((size_t)ms->ngroups, sizeof *ms->group_mass);
  ms->group_added = calloc((size_t)ms->ngroups, sizeof *ms->group_added);
  if (!ms->added || !ms->group_mass || !ms->group_added) {
    dtm_mass_scaling_free(ms);
    return DTM_ERR(DTM_ERR_INTERNAL, "out of memory for the mass scaling of %zu elements", nel);
  }
  return DTM_OK;
}

static void scale_block(const dtm_analysis *a, int b, size_t first, dtm_mass_scaling *ms) {
  const dtm_block *blk = &dtm_analysis_mesh(a)->blocks[b];
  int irho = dtm_scene_property_index(dtm_analysis_scene(a), "rho");
  for (size_t e = 0; e < blk->n; e++) {
    size_t i = first + e;
    double m = element_mass(a, blk, e, irho), add = added_mass(m, wave_dt(a, i), ms->target);
    int g = blk->group[e] >= 0 && blk->group[e] < ms->ngroups - 1 ? blk->group[e] : ms->ngroups - 1;
    ms->added[i] = add;
    ms->total_mass += m;
    ms->total_added += add;
    ms->group_mass[g] += m;
    ms->group_added[g] += add;
    ms->scaled += add > 0;
  }
}

int dtm_mass_scaling_compute(const dtm_analysis *a, double target, dtm_mass_scaling *ms) {
  memset(ms, 0, sizeof *ms);
  ms->target = target;
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "mass scaling: the target step must be positive and finite, got %g s", target);
  DTM_CHECK(alloc_scaling(a, ms));
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t first = 0;
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++) scale_block(a, b, first, ms);
  return DTM_OK;
}

void dtm_mass_scaling_free(dtm_mass_scaling *ms) {
  free(ms->added);
  free(ms->group_mass);
  free(ms->group_added);
  ms->added = ms->group_mass = ms->group_added = NULL;
  ms->ngroups = 0;
}
