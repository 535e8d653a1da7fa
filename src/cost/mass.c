/* Mass scaling, the alternative to remeshing for a target step, in the two
 * forms of include/dtmap/cost.h. Element by element: every element whose
 * own wave step dt_e (the smallest over the wave-type effects, exponent 1,
 * damping already applied) is below the target dt_t gets
 * m_e ((dt_t/dt_e)^2 - 1) of added mass, m_e = rho_e V_e with V_e the
 * element's measure (per unit thickness in 2D, per unit cross-section in
 * 1D). At the nodes: node a of lumped mass m_a = sum_e m_e w_ea (w the
 * element's lumped weights) whose nodal-bound step dt_a (the smallest over
 * the spectral wave effects) is below dt_t needs m_a (dt_t/dt_a)^2 in all;
 * the non-spectral wave effects are first met element by element, which
 * already adds to the node masses. Node mass is attributed to the elements
 * around the node in proportion to their share of it. Reported per
 * element, per physical group (the last slot collects the elements in no
 * group) and in total. Elements whose material has no density count no
 * mass; elements without a finite wave step get none. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "dtmap/kernel.h"

/* The element's own wave step: min over the wave-type effects (only the
 * non-spectral ones when spectral_too is 0), s; +inf when none limits it. */
static double wave_dt_of(const dtm_analysis *a, size_t i, int spectral_too) {
  double dt = INFINITY;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const double *dk = dtm_analysis_effect_dt(a, k);
    if (!spectral_too && dtm_analysis_effect_nodal(a, k)) continue;
    if (dk && dtm_effect_is_wave(dtm_analysis_effect(a, k)) && dk[i] < dt) dt = dk[i];
  }
  return dt;
}

static double wave_dt(const dtm_analysis *a, size_t i) { return wave_dt_of(a, i, 1); }

/* rho V of element e of block blk, kg (0 without a density), and its lumped
 * weights w[nn] when w is not NULL. */
static double element_mass_w(const dtm_analysis *a, const dtm_block *blk, size_t e, int irho, double *w) {
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
  if (w) dtm_elem_lumped_weights(blk->type, x, w);
  return isfinite(v) ? dtm_material_get(m, irho) * v : 0.0;
}

static double element_mass(const dtm_analysis *a, const dtm_block *blk, size_t e, int irho) {
  return element_mass_w(a, blk, e, irho, NULL);
}

/* Index of the density among the scene's properties. */
static int rho_index(const dtm_analysis *a) { return dtm_scene_property_index(dtm_analysis_scene(a), "rho"); }

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

/* Node fields of the nodal form. */
typedef struct {
  double *m0;  /* [nnodes] lumped mass before scaling, kg */
  double *m1;  /* [nnodes] after the element-by-element part, kg */
  double *add; /* [nnodes] mass added at the node, kg */
  char *in;    /* [nnodes] 1 for a node of a selected element */
} node_mass;

/* Ratio by which element i's mass grows for the non-spectral wave effects. */
static double element_ratio(const dtm_analysis *a, size_t i, double target) {
  double dt = wave_dt_of(a, i, 0), r = target / dt;
  return dt > 0 && isfinite(dt) && dt < target ? r * r : 1.0;
}

/* Pass 0: node masses before and after the element part (and that part
 * into ms); pass 1: attribute the node additions to the elements. */
static void node_pass(const dtm_analysis *a, const unsigned char *only, node_mass *nm, dtm_mass_scaling *ms, int pass) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t first = 0;
  int irho = rho_index(a);
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++) {
    const dtm_block *blk = &m->blocks[b];
    for (size_t e = 0; e < blk->n; e++) {
      size_t i = first + e;
      double w[DTM_MAX_NODES], me = element_mass_w(a, blk, e, irho, w);
      double r = only && !only[i] ? 1.0 : element_ratio(a, i, ms->target);
      for (int c = 0; c < blk->nn && me > 0; c++) {
        size_t v = blk->conn[e * blk->nn + c];
        if (pass == 0) nm->m0[v] += me * w[c], nm->m1[v] += r * me * w[c], nm->in[v] |= !only || only[i];
        if (pass == 1 && nm->m1[v] > 0) ms->added[i] += nm->add[v] * r * me * w[c] / nm->m1[v];
      }
      if (pass == 0) ms->added[i] = (r - 1.0) * me;
    }
  }
}

/* Mass node v needs on top of m1 for the spectral wave effects. */
static double node_need(const dtm_analysis *a, const node_mass *nm, size_t v, double target) {
  double ratio = 1.0;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const double *nd = dtm_analysis_effect_nodal(a, k);
    if (!nd || !dtm_effect_is_wave(dtm_analysis_effect(a, k)) || !(nd[v] < target) || !(nd[v] > 0)) continue;
    ratio = fmax(ratio, (target / nd[v]) * (target / nd[v]));
  }
  return fmax(0.0, ratio * nm->m0[v] - nm->m1[v]);
}

/* Totals, groups and counts from ms->added. */
static void tally(const dtm_analysis *a, dtm_mass_scaling *ms) {
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t first = 0;
  int irho = rho_index(a);
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++) {
    const dtm_block *blk = &m->blocks[b];
    for (size_t e = 0; e < blk->n; e++) {
      size_t i = first + e;
      double me = element_mass(a, blk, e, irho);
      int g = blk->group[e] >= 0 && blk->group[e] < ms->ngroups - 1 ? blk->group[e] : ms->ngroups - 1;
      ms->total_mass += me, ms->total_added += ms->added[i];
      ms->group_mass[g] += me, ms->group_added[g] += ms->added[i];
      ms->scaled += ms->added[i] > 0;
    }
  }
}

int dtm_mass_scaling_nodal(const dtm_analysis *a, double target, const unsigned char *only, dtm_mass_scaling *ms) {
  memset(ms, 0, sizeof *ms);
  ms->target = target, ms->nodal = 1;
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "mass scaling: the target step must be positive and finite, got %g s", target);
  DTM_CHECK(alloc_scaling(a, ms));
  size_t nn = dtm_analysis_mesh(a)->nnodes + 1;
  node_mass nm = {calloc(nn, sizeof(double)), calloc(nn, sizeof(double)), calloc(nn, sizeof(double)), calloc(nn, 1)};
  int r = nm.m0 && nm.m1 && nm.add && nm.in ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (r == DTM_OK) {
    node_pass(a, only, &nm, ms, 0);
    for (size_t v = 0; v + 1 < nn; v++) nm.add[v] = nm.in[v] ? node_need(a, &nm, v, target) : 0.0;
    node_pass(a, only, &nm, ms, 1);
    tally(a, ms);
  }
  free(nm.m0), free(nm.m1), free(nm.add), free(nm.in);
  if (r) dtm_mass_scaling_free(ms);
  return r;
}

int dtm_mass_scaling_compute(const dtm_analysis *a, double target, dtm_mass_scaling *ms) {
  memset(ms, 0, sizeof *ms);
  ms->target = target;
  if (!(target > 0) || !isfinite(target))
    return DTM_ERR(DTM_ERR_INPUT, "mass scaling: the target step must be positive and finite, got %g s", target);
  DTM_CHECK(alloc_scaling(a, ms));
  const dtm_mesh *m = dtm_analysis_mesh(a);
  size_t first = 0;
  int irho = rho_index(a);
  for (int b = 0; b < m->nblocks; first += m->blocks[b].n, b++)
    for (size_t e = 0; e < m->blocks[b].n; e++)
      ms->added[first + e] = added_mass(element_mass(a, &m->blocks[b], e, irho), wave_dt(a, first + e), target);
  tally(a, ms);
  return DTM_OK;
}

void dtm_mass_scaling_free(dtm_mass_scaling *ms) {
  free(ms->added);
  free(ms->group_mass);
  free(ms->group_added);
  ms->added = ms->group_mass = ms->group_added = NULL;
  ms->ngroups = 0;
}
