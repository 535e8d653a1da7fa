/* Point masses at the nodes that lift an analysis's recommended step to a
 * target, the least a basis allows (what refine and deck add where no
 * mesh meets a target). On the nodal basis: the nodes whose nodal-bound
 * step is below the target get m_a ((dt_t / dt_a)^2 - 1) (src/cost/
 * mass.c), the least that lifts each bound to it, since the bound's
 * numerator does not change with mass; the bound then meets it by
 * construction. On the global basis two ways are tried and the one that
 * adds less is kept: the same rule aimed at the advice target (the nodal
 * steps of a mesh whose global step meets the target), the global
 * estimate run again with the masses and the aim raised by its shortfall;
 * and the top mode followed, the nodes that carry 95 % of its kinetic
 * energy getting the mass that lowers its eigenvalue to the target's,
 * again until the estimate meets it (a localised top mode needs mass only
 * where it lives, where the nodal rule also feeds nodes whose bound is
 * merely pessimistic). The analysis keeps the masses only when they meet
 * the target within the share of the model's mass the caller allows;
 * otherwise it is put back as it was, and the share found is returned. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"

#define TRIES 8         /* global estimates with masses at most, aiming at the nodes */
#define MODE_TRIES 40   /* global estimates at most, following the top mode */
#define MODE_SHARE 0.95 /* the nodes holding this share of the top mode's kinetic energy get mass */
#define OVERSHOOT 1.002 /* the aim rises by the shortfall times this (Lanczos is within 1e-4) */
#define EDGE 1e-9       /* the aim past the target, against rounding in the nodal bound */

/* What the methods share: the analysis and the masses it carried. */
typedef struct {
  const dtm_mass_aim *aim; /* the target and the basis */
  dtm_analysis *a;         /* the analysis, whose point masses change */
  size_t nn;               /* its nodes */
  const double *kept;      /* [nn] the point masses it carried, or NULL */
  double carried;          /* their total, kg */
  double model;            /* the mass of its analysed elements, kg */
} mass_job;

static double total(const double *kg, size_t n) {
  double t = 0;
  for (size_t v = 0; kg && v < n; v++) t += kg[v];
  return t;
}

/* The share of the model's mass the point masses of a add beyond the kept ones, %. */
static double percent_added(const mass_job *j) {
  return 100.0 * (total(dtm_analysis_point_masses(j->a), j->nn) - j->carried) / j->model;
}

static int met(const mass_job *j) { return dtm_analysis_recommended(j->a) >= j->aim->target; }

/* The analysis on the caller's basis after its masses changed (with the
 * top mode when asked for). */
static int reestimate(const mass_job *j, unsigned modes) {
  const dtm_mass_aim *o = j->aim;
  if (!o->global) return DTM_OK;
  return dtm_analysis_estimate_global(j->a, o->tol > 0 ? o->tol : 1e-4, o->lanczos_max > 0 ? o->lanczos_max : 400,
                                      DTM_GLOBAL_BASIS | modes);
}

/* Set the masses kg (NULL: none) on the analysis and estimate again. */
static int put(const mass_job *j, const double *kg, unsigned modes) {
  DTM_CHECK(dtm_analysis_set_point_masses(j->a, kg));
  return reestimate(j, modes);
}

/* Masses at the nodes below an aim (s, before safety), the rule of
 * src/cost/mass.c, on top of those a carries; on the global basis the aim
 * rises by the global step's shortfall until it meets the target. */
static int by_nodes(const mass_job *j) {
  double aim = dtm_analysis_advice_target(j->a) / dtm_analysis_scene(j->a)->safety * (1 + EDGE);
  for (int tries = 0; tries < TRIES && !met(j) && percent_added(j) <= DTM_MASS_CAP; tries++) {
    dtm_mass_scaling ms;
    DTM_CHECK(dtm_mass_scaling_nodal(j->a, aim, NULL, &ms));
    const double *pm = dtm_analysis_point_masses(j->a);
    double *m = malloc((j->nn + 1) * sizeof *m);
    for (size_t v = 0; m && v < j->nn; v++) m[v] = (pm ? pm[v] : 0.0) + ms.node_added[v];
    dtm_mass_scaling_free(&ms);
    int r = m ? put(j, m, 0) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    free(m);
    DTM_CHECK(r);
    aim *= fmax(1.0, j->aim->target / dtm_analysis_recommended(j->a)) * OVERSHOOT;
  }
  return DTM_OK;
}

/* The wave effect whose global estimate holds the step down, or -1. */
static int top_effect(const dtm_analysis *a) {
  int best = -1;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const dtm_global_info *g = dtm_analysis_global(a, k);
    if (g && g->mode && (best < 0 || g->dt_low < dtm_analysis_global(a, best)->dt_low)) best = k;
  }
  return best;
}

static const double *energy_of; /* the node energies qsort compares (set just before it) */
static int by_energy(const void *x, const void *y) {
  double u = energy_of[*(const size_t *)x], w = energy_of[*(const size_t *)y];
  return u > w ? -1 : u < w;
}

/* One step: the nodes that hold MODE_SHARE of the top mode u's kinetic
 * energy m_a |u_a|^2 (u^T M u = 1) get their mass times f, the factor by
 * which the mode's eigenvalue must fall; m[] the lumped masses, e[] and
 * idx[] scratch. */
static void mode_step(const mass_job *j, const double *u, double f, const double *m, double *e, size_t *idx,
                      double *add) {
  int d = dtm_analysis_mesh(j->a)->space_dim;
  double sum = 0, acc = 0;
  for (size_t v = 0; v < j->nn; v++) {
    e[v] = 0, idx[v] = v;
    for (int c = 0; c < d; c++) e[v] += m[v] * u[v * d + c] * u[v * d + c];
    sum += e[v];
  }
  energy_of = e;
  qsort(idx, j->nn, sizeof *idx, by_energy);
  for (size_t k = 0; k < j->nn && acc < MODE_SHARE * sum; k++) acc += e[idx[k]], add[idx[k]] += (f - 1) * m[idx[k]];
}

/* The global basis: follow the top mode. While the global step falls short,
 * the nodes that carry the top mode get the mass that lowers its
 * eigenvalue to the target's, and the estimate is run again (the next
 * mode may be elsewhere). */
static int by_modes(const mass_job *j) {
  double *m = malloc((j->nn + 1) * sizeof *m), *e = malloc((j->nn + 1) * sizeof *e), *add = NULL;
  size_t *idx = malloc((j->nn + 1) * sizeof *idx);
  int r = m && e && idx ? reestimate(j, DTM_GLOBAL_MODES) : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (int tries = 0; r == DTM_OK && tries < MODE_TRIES && !met(j) && percent_added(j) <= DTM_MASS_CAP; tries++) {
    int k = top_effect(j->a);
    const double *pm = dtm_analysis_point_masses(j->a);
    double ratio = j->aim->target / dtm_analysis_recommended(j->a);
    if (k < 0) break;
    r = dtm_mass_lumped(j->a, m);
    free(add), add = calloc(j->nn + 1, sizeof *add);
    if (r == DTM_OK && !add) r = DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
    if (r == DTM_OK) mode_step(j, dtm_analysis_global(j->a, k)->mode, ratio * ratio * OVERSHOOT, m, e, idx, add);
    for (size_t v = 0; r == DTM_OK && v < j->nn; v++) add[v] += pm ? pm[v] : 0.0;
    if (r == DTM_OK) r = put(j, add, DTM_GLOBAL_MODES);
  }
  free(m), free(e), free(idx), free(add);
  return r;
}

/* The result of one method: whether it met, the share it added and a copy
 * of its masses (NULL when it did not meet). */
typedef struct {
  int met;        /* the target met */
  double percent; /* the share added, % */
  double *masses; /* [nn] its point masses (owned), or NULL */
} outcome;

static int try_method(const mass_job *j, int (*method)(const mass_job *), outcome *out) {
  DTM_CHECK(put(j, j->kept, 0));
  DTM_CHECK(method(j));
  out->met = met(j), out->percent = percent_added(j), out->masses = NULL;
  if (!out->met) return DTM_OK;
  out->masses = malloc((j->nn + 1) * sizeof *out->masses);
  if (!out->masses) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  memcpy(out->masses, dtm_analysis_point_masses(j->a), j->nn * sizeof *out->masses);
  return DTM_OK;
}

/* The least of the methods the basis has (the nodal rule; on the global
 * basis the top modes too), put on the analysis when within the limit. */
static int least(mass_job *j, outcome *best) {
  outcome o[2] = {{0, INFINITY, NULL}, {0, INFINITY, NULL}};
  int n = j->aim->global ? 2 : 1, r = DTM_OK, pick = -1;
  for (int k = 0; k < n && r == DTM_OK; k++) r = try_method(j, k ? by_modes : by_nodes, &o[k]);
  for (int k = 0; k < n; k++)
    if (o[k].met && (pick < 0 || o[k].percent < o[pick].percent)) pick = k;
  *best = pick >= 0 ? o[pick] : (outcome){0, fmin(o[0].percent, o[1].percent), NULL};
  for (int k = 0; k < n; k++)
    if (k != pick) free(o[k].masses);
  if (r == DTM_OK && !(best->met && best->percent <= j->aim->max_percent)) return put(j, j->kept, 0);
  return r == DTM_OK ? put(j, best->masses, 0) : r;
}

int dtm_mass_points(dtm_analysis *a, const dtm_mass_aim *aim, dtm_mass_found *out) {
  memset(out, 0, sizeof *out);
  out->percent = NAN;
  if (!isfinite(dtm_analysis_dt_nodal(a))) return DTM_OK; /* no nodal bound: no mass at the nodes */
  double *m = NULL;
  mass_job j = {aim, a, dtm_analysis_mesh(a)->nnodes, NULL, 0, 0};
  const double *pm = dtm_analysis_point_masses(a);
  double *kept = pm ? malloc((j.nn + 1) * sizeof *kept) : NULL;
  int r = (pm && !kept) || !(m = malloc((j.nn + 1) * sizeof *m)) ? DTM_ERR(DTM_ERR_INTERNAL, "out of memory") : DTM_OK;
  if (kept) memcpy(kept, pm, j.nn * sizeof *kept);
  j.kept = kept, j.carried = total(kept, j.nn);
  if (r == DTM_OK) r = dtm_mass_lumped(a, m);
  j.model = total(m, j.nn) - j.carried;
  outcome best = {0, NAN, NULL};
  if (r == DTM_OK) r = least(&j, &best);
  out->met = best.met, out->percent = best.percent, out->model_mass = j.model;
  out->kept = r == DTM_OK && best.met && best.percent <= aim->max_percent;
  for (size_t v = 0; out->kept && v < j.nn; v++)
    if (best.masses[v] > (kept ? kept[v] : 0.0)) out->nodes++, out->added += best.masses[v] - (kept ? kept[v] : 0.0);
  free(kept), free(m), free(best.masses);
  return r;
}
