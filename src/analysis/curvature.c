/* How curved the second-order elements of the mesh are, and how much
 * their steps depend on the integration rule (the view "curvature" and the
 * report's curvature block). Per second-order element the kernel gives the
 * node offset and the ratio min det J / max det J (a Bernstein bound on
 * tri6 and tet10: dtm_kernel_curvature). For every curved element (node
 * offset above 1e-9 of its edge, the kernel's own test) and the first
 * elastic effect whose step is the element bound, the element step is
 * computed in the effect's model and in another (the full rules against
 * the converged integration; the converged against the "full" and
 * "calculix" models): when they differ by more than 1e-3 the element is "rule
 * sensitive", counted, and the report and the CLI warn, since a solver
 * that integrates it with another rule has another stable step. An
 * element whose ratio is below DTM_CURVED_STRONG is "strongly curved".
 * Counts and extremes are reduced over the parts of a distributed run;
 * the worst elements are named by the part that holds them. Meshes
 * without second-order elements cost nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "reference.h"

#define OFFSET_CURVED 1e-9  /* node offset above which an element is curved (curved.c) */
#define RULE_SENSITIVE 1e-3 /* relative step change that makes an element rule sensitive */
#define RANGE 256           /* elements per task of the curvature pass */

static int second_order(int type) {
  switch (type) {
  case DTM_TRI6:
  case DTM_TET10:
  case DTM_QUAD8:
  case DTM_QUAD9:
  case DTM_HEX20:
  case DTM_HEX27:
  case DTM_PRISM15:
  case DTM_PRISM18:
  case DTM_PYR13:
  case DTM_PYR14: return 1;
  default: return 0;
  }
}

/* Each second-order element's converged rule level, once (the kernel's
 * level search: src/kernel/curved.c), for the element map's measures, the
 * nodal bound's masses and the global operator, which took it by searching
 * again each, and the remaining quadrature error the search estimates at
 * that level (rem). Levelled blocks only; a straight-sided element costs
 * its node offset test. The arrays are made here; compute.c fills them a
 * chunk at a time (dtm_analysis_levels_chunk) just before mapping the
 * chunk, so that the kernel's memo (src/kernel/memo.c) still holds what
 * the search integrated when the element map and the measures ask for it. */
int dtm_analysis_levels(dtm_analysis *a) {
  for (int b = 0; b < a->mesh->nblocks; b++) {
    const dtm_block *blk = &a->mesh->blocks[b];
    if (!dtm_ref_levelled(blk->type)) continue;
    if (!a->level) a->level = calloc((size_t)a->mesh->nblocks + 1, sizeof *a->level);
    if (!a->level_rem) a->level_rem = calloc((size_t)a->mesh->nblocks + 1, sizeof *a->level_rem);
    if (a->level) a->level[b] = malloc(blk->n + 1);
    if (a->level_rem) a->level_rem[b] = malloc((blk->n + 1) * sizeof(double));
    if (!a->level || !a->level[b] || !a->level_rem || !a->level_rem[b])
      return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  return DTM_OK;
}

void dtm_analysis_levels_chunk(const dtm_analysis *a, int b, size_t e0, size_t n, const double *x) {
  const dtm_block *blk = &a->mesh->blocks[b];
  if (!a->level || !a->level[b]) return;
  for (size_t e = 0; e < n; e++)
    a->level[b][e0 + e] =
        (unsigned char)dtm_ref_level_elem(blk->type, x + 3 * (size_t)blk->nn * e, &a->level_rem[b][e0 + e]);
}

/* How much a change dT of the mass-scaled tensor T (Frobenius norm) can
 * move the largest eigenvalue of an element's M^-1/2 K M^-1/2 under the
 * coefficients c, per unit of |dT|_F (curved.c's header): elastic
 * (|lam| + mu (1 + sqrt d)) / rho, diffusion k sqrt(d) / capacity. */
static double lipschitz(const dtm_operator_coeffs *c, int d) {
  if (c->kind == DTM_OP_ELASTIC) return (fabs(c->mod.lam) + c->mod.mu * (1 + sqrt(d))) / c->capacity;
  if (c->kind == DTM_OP_DIFFUSION) return c->conductivity * sqrt(d) / c->capacity;
  return 0;
}

/* The bound behind dtm_analysis_quadrature_margin. With the lumped masses
 * M = sum_e P_e^T m_e P_e (exact at every level, and equal in both models)
 * and the change of the assembled operator dA = sum_e M^-1/2 P_e^T dK_e P_e
 * M^-1/2, for any x: x^T dA x = sum_e y_e^T dB_e y_e with dB_e = m_e^-1/2
 * dK_e m_e^-1/2 (the element's own scaling) and y_e = m_e^1/2 P_e M^-1/2 x,
 * and sum_e |y_e|^2 = sum_a x_a^2 sum_e m_ea / M_a <= |x|^2 (point masses
 * and added mass only make M larger). So lambda_max(A + dA) <= lambda_max(A)
 * + max_e |dB_e|_2, and |dB_e|_2 <= lipschitz x |dT_e|_F. */
/* 1 when the operator integrates type with the converged model's levels
 * under c (the other models are their own fixed rules: nothing left to
 * converge). */
static int converged_model(const dtm_operator_coeffs *c, int type) {
  if (c->kind != DTM_OP_ELASTIC) return 1; /* diffusion: always converged */
  return c->mod.integration == DTM_INTEGRATION_CONVERGED ||
         (c->mod.integration == DTM_INTEGRATION_CALCULIX && type != DTM_TET10);
}

/* The margin of block b into *margin (the larger of it and *margin); best
 * [nslots] is scratch. */
static int block_margin(const dtm_analysis *a, int k, int b, double *best, double *margin) {
  const dtm_block *blk = &a->mesh->blocks[b];
  int ns = dtm_analysis_nslots(a), d = 3;
  dtm_elem_info(blk->type, &d, NULL);
  for (int s = 0; s < ns; s++) best[s] = 0;
  for (size_t e = 0; e < blk->n; e++) {
    int s = dtm_analysis_slot(a, blk, e);
    best[s] = fmax(best[s], a->level_rem[b][e]);
  }
  for (int s = 0; s < ns; s++) {
    dtm_operator_coeffs c;
    if (!(best[s] > 0)) continue;
    DTM_CHECK(dtm_analysis_coefficients(a, k, s, &c));
    if (!converged_model(&c, blk->type)) continue;
    *margin = fmax(*margin, lipschitz(&c, d) * best[s]);
  }
  return DTM_OK;
}

int dtm_analysis_quadrature_margin(const dtm_analysis *a, int k, double *margin) {
  double *best = NULL;
  int r = DTM_OK;
  *margin = 0;
  for (int b = 0; a->level_rem && b < a->mesh->nblocks && r == DTM_OK; b++) {
    if (!a->level_rem[b]) continue;
    if (!best && !(best = calloc((size_t)dtm_analysis_nslots(a) + 1, sizeof *best)))
      return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    r = block_margin(a, k, b, best, margin);
  }
  free(best);
  return r;
}

int dtm_analysis_level(const dtm_analysis *a, int b, size_t e) { return a->level && a->level[b] ? a->level[b][e] : -1; }

int dtm_analysis_elastic_bound_effect(const dtm_analysis *a) {
  for (int k = 0; k < a->neffects; k++) {
    if (!a->dt_effect[k] || !a->effects[k].cls->coefficients) continue;
    for (int i = 0; i < dtm_analysis_nslots(a); i++) {
      dtm_operator_coeffs c;
      if (dtm_analysis_coefficients(a, k, i, &c)) { /* a slot no element uses may lack properties */
        dtm_error_clear();
        continue;
      }
      if (c.kind == DTM_OP_ELASTIC && c.dt_is_bound) return k;
      break;
    }
  }
  return -1;
}

/* |dt_other / dt - 1| of an element whose undamped element step in the
 * effect's model is dt, dt_other in the other model; NaN when not
 * computable. */
static double dependence(const dtm_operator_coeffs *c, int type, const double *x, int level, double dt) {
  dtm_elastic_moduli m = c->mod;
  double l;
  m.integration = m.integration == DTM_INTEGRATION_CONVERGED ? DTM_INTEGRATION_FULL : DTM_INTEGRATION_CONVERGED;
  if (dtm_kernel_elastic_lambda_at(type, &m, x, level, &l)) return dtm_error_clear(), NAN;
  return fabs(2 / sqrt(l) / dt - 1);
}

/* Curved elements waiting for their dependence, up to DTM_KERNEL_LANES. */
typedef struct {
  int held;
  size_t e[DTM_KERNEL_LANES];
  double x[DTM_KERNEL_LANES][DTM_MAX_NODES * 3];
} lane_group;

/* The dependence of the group's elements into dep, side by side in the
 * kernel's lanes (the same bits as one at a time); an element the lanes
 * refuse is taken alone, as dependence() does. */
static void group_dependence(const dtm_analysis *a, int b, int k, const dtm_operator_coeffs *coef, lane_group *q,
                             double *dep) {
  const dtm_block *blk = &a->mesh->blocks[b];
  size_t g0 = a->offset[b];
  const double *dt = a->dt_bare && a->dt_bare[k] ? a->dt_bare[k] : a->dt_effect[k];
  dtm_elastic_moduli m[DTM_KERNEL_LANES];
  const dtm_elastic_moduli *mp[DTM_KERNEL_LANES];
  const double *xp[DTM_KERNEL_LANES];
  int lv[DTM_KERNEL_LANES], failed = -1;
  double l[DTM_KERNEL_LANES];
  for (int i = 0; i < q->held; i++) {
    m[i] = coef[dtm_analysis_slot(a, blk, q->e[i])].mod, mp[i] = &m[i], xp[i] = q->x[i];
    m[i].integration = m[i].integration == DTM_INTEGRATION_CONVERGED ? DTM_INTEGRATION_FULL : DTM_INTEGRATION_CONVERGED;
    lv[i] = dtm_analysis_level(a, b, q->e[i]); /* the converged model's kept level (ignored by the others) */
  }
  int r = dtm_kernel_elastic_lambda_lanes(blk->type, q->held, mp, xp, lv, l, &failed);
  if (r) dtm_error_clear();
  for (int i = 0; i < q->held; i++) {
    size_t g = g0 + q->e[i];
    dep[g] = !r || i < failed ? fabs(2 / sqrt(l[i]) / dt[g] - 1)
                              : dependence(&coef[dtm_analysis_slot(a, blk, q->e[i])], blk->type, q->x[i], lv[i], dt[g]);
  }
  q->held = 0;
}

/* Per element of block b in [e0, e1) (global indices from g0): ratio and
 * dependence. */
static void range_pass(const dtm_analysis *a, int b, int k, const dtm_operator_coeffs *coef, double *dep, size_t e0,
                       size_t e1) {
  const dtm_block *blk = &a->mesh->blocks[b];
  size_t g0 = a->offset[b];
  lane_group q = {0};
  for (size_t e = e0; e < e1; e++) {
    double *x = q.x[q.held];
    dtm_curvature c;
    dtm_mesh_gather_one(a->mesh, blk, e, x);
    dep[g0 + e] = NAN;
    if (dtm_kernel_curvature_shape(blk->type, x, &c)) { /* the levels are kept: dtm_analysis_levels */
      a->curv_ratio[g0 + e] = NAN, a->curv_offset[g0 + e] = NAN;
      continue;
    }
    a->curv_ratio[g0 + e] = c.jac_ratio, a->curv_offset[g0 + e] = c.offset;
    if (!(c.offset > OFFSET_CURVED) || !coef) continue;
    q.e[q.held++] = e;
    if (q.held == DTM_KERNEL_LANES) group_dependence(a, b, k, coef, &q, dep);
  }
  if (q.held) group_dependence(a, b, k, coef, &q, dep);
}

/* Per element of block b: ratio and dependence, RANGE elements per task. */
static void block_pass(const dtm_analysis *a, int b, int k, const dtm_operator_coeffs *coef, double *dep) {
  const dtm_block *blk = &a->mesh->blocks[b];
  long nr = (long)((blk->n + RANGE - 1) / RANGE);
#pragma omp parallel for schedule(dynamic, 1)
  for (long i = 0; i < nr; i++) {
    size_t e0 = (size_t)i * RANGE, e1 = e0 + RANGE < blk->n ? e0 + RANGE : blk->n;
    range_pass(a, b, k, coef, dep, e0, e1);
  }
}

/* The summary of the per-element values, over this part. */
static void summarize_part(dtm_analysis *a, const double *dep) {
  dtm_curvature_summary *s = &a->curv;
  for (int b = 0; b < a->mesh->nblocks; b++) {
    if (!second_order(a->mesh->blocks[b].type)) continue;
    for (size_t g = a->offset[b]; g < a->offset[b + 1]; g++) {
      s->second_order++;
      if (!(a->curv_offset[g] > OFFSET_CURVED)) continue;
      s->curved++;
      s->strong += a->curv_ratio[g] < DTM_CURVED_STRONG;
      s->sensitive += dep[g] > RULE_SENSITIVE;
      if (a->curv_ratio[g] < s->worst_ratio) s->worst_ratio = a->curv_ratio[g], s->worst_element = g;
      if (a->curv_offset[g] > s->max_offset) s->max_offset = a->curv_offset[g];
      if (dep[g] > s->max_dependence) s->max_dependence = dep[g], s->dependence_element = g;
    }
  }
}

/* Coefficients of effect k for every slot (NULL when k < 0). */
static dtm_operator_coeffs *slot_coeffs(const dtm_analysis *a, int k) {
  int ns = dtm_analysis_nslots(a);
  dtm_operator_coeffs *c = k >= 0 ? calloc((size_t)ns + 1, sizeof *c) : NULL;
  for (int i = 0; c && i < ns; i++)
    if (dtm_analysis_coefficients(a, k, i, &c[i])) dtm_error_clear();
  return c;
}

int dtm_analysis_curvature_pass(dtm_analysis *a) {
  int any = 0, r = DTM_OK;
  a->curv = (dtm_curvature_summary){0, 0, 0, 0, 1, (size_t)-1, 0, 0, (size_t)-1, DTM_INTEGRATION_CONVERGED};
  for (int b = 0; b < a->mesh->nblocks; b++) any |= second_order(a->mesh->blocks[b].type);
  double *dep = NULL;
  if (any) {
    a->curv_ratio = malloc((a->nel + 1) * sizeof *a->curv_ratio);
    a->curv_offset = malloc((a->nel + 1) * sizeof *a->curv_offset);
    dep = malloc((a->nel + 1) * sizeof *dep);
    r = a->curv_ratio && a->curv_offset && dep ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  int k = any && r == DTM_OK ? dtm_analysis_elastic_bound_effect(a) : -1;
  dtm_operator_coeffs *coef = slot_coeffs(a, k);
  if (k >= 0) a->curv.model = coef[0].mod.integration;
  for (int b = 0; b < a->mesh->nblocks && any && r == DTM_OK; b++)
    if (second_order(a->mesh->blocks[b].type))
      block_pass(a, b, k, coef, dep);
    else
      for (size_t g = a->offset[b]; g < a->offset[b + 1]; g++) a->curv_ratio[g] = a->curv_offset[g] = NAN;
  if (r == DTM_OK && any) summarize_part(a, dep);
  free(coef), free(dep);
  double v[5] = {(double)a->curv.second_order, (double)a->curv.curved, (double)a->curv.strong,
                 (double)a->curv.sensitive, 0};
  r = dtm_x_reduce(a, r, v, 4, DTM_X_SUM);
  a->curv.second_order = (size_t)v[0], a->curv.curved = (size_t)v[1], a->curv.strong = (size_t)v[2];
  a->curv.sensitive = (size_t)v[3];
  double hi[2] = {a->curv.max_offset, a->curv.max_dependence}, lo = a->curv.worst_ratio;
  r = dtm_x_reduce(a, r, hi, 2, DTM_X_MAX);
  r = dtm_x_reduce(a, r, &lo, 1, DTM_X_MIN);
  if (lo < a->curv.worst_ratio) a->curv.worst_ratio = lo, a->curv.worst_element = (size_t)-1;
  if (hi[1] > a->curv.max_dependence) a->curv.dependence_element = (size_t)-1;
  a->curv.max_offset = hi[0], a->curv.max_dependence = hi[1];
  return r;
}

const dtm_curvature_summary *dtm_analysis_curvature(const dtm_analysis *a) { return &a->curv; }
const double *dtm_analysis_curvature_ratio(const dtm_analysis *a) { return a->curv_ratio; }
