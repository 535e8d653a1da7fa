/* The mass round of refine: where no mesh meets the target (a thin wall, a
 * wedge, a fixed extrusion, a kept clamp or a spent budget), explicit users
 * scale the mass of exactly the limiting nodes (LS-DYNA's DT2MS, Abaqus's
 * *FIXED MASS SCALING on a set, Radioss's /DT/NODA/CST). On the kept mesh,
 * point masses go to the nodes whose nodal-bound step is below the aim:
 * node a needs m_a ((aim / dt_a)^2 - 1) (src/cost/mass.c), the least that
 * lifts its bound to the aim, since the bound's numerator does not change
 * with mass. On the nodal basis the aim is the target (before safety), and
 * the bound then meets it by construction. On the global basis it starts at
 * the advice target (the nodal steps of a mesh whose global step meets the
 * target) and the global estimate is run again with the masses: while it
 * falls short, the aim rises by the shortfall and the nodes below it get
 * more. The analysis keeps the masses only when their total is within the
 * share of the model's mass the caller allows; beyond it, the analysis is
 * put back as it was and the share needed is recorded. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/util.h"
#include "study-impl.h"

#define TRIES 8         /* global estimates with masses at most */
#define OVERSHOOT 1.002 /* the aim rises by the shortfall times this (Lanczos is within 1e-4) */
#define EDGE 1e-9       /* the aim past the target, against rounding in the nodal bound */

/* The point masses of a (carried, or 0) plus the mass scaling's. */
static double *sum_masses(const dtm_analysis *a, const dtm_mass_scaling *ms) {
  size_t nn = dtm_analysis_mesh(a)->nnodes;
  const double *pm = dtm_analysis_point_masses(a);
  double *m = malloc((nn + 1) * sizeof *m);
  for (size_t v = 0; m && v < nn; v++) m[v] = (pm ? pm[v] : 0.0) + ms->node_added[v];
  return m;
}

static double total(const double *kg, size_t n) {
  double t = 0;
  for (size_t v = 0; kg && v < n; v++) t += kg[v];
  return t;
}

/* The analysis on the caller's basis after its masses changed. */
static int reestimate(const dtm_refine_result *rr, dtm_analysis *a) {
  if (!rr->options.global) return DTM_OK;
  return dtm_analysis_estimate_global(a, rr->options.tol, rr->options.lanczos_max, DTM_GLOBAL_BASIS);
}

/* One step: the masses that lift the nodes below aim (s, before safety),
 * on top of those a carries, set on a; *percent gets the share of the
 * model's mass they add beyond what the kept mesh carried (carried kg). */
static int add_step(const dtm_refine_result *rr, dtm_analysis *a, double aim, double carried, double *percent) {
  dtm_mass_scaling ms;
  DTM_CHECK(dtm_mass_scaling_nodal(a, aim, NULL, &ms));
  double *m = sum_masses(a, &ms), model = ms.total_mass;
  dtm_mass_scaling_free(&ms);
  if (!m) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  *percent = 100.0 * (total(m, dtm_analysis_mesh(a)->nnodes) - carried) / model;
  int r = *percent <= rr->options.max_added_mass ? dtm_analysis_set_point_masses(a, m) : DTM_OK;
  free(m);
  if (r == DTM_OK && *percent <= rr->options.max_added_mass) r = reestimate(rr, a);
  return r;
}

/* Put the analysis back as the loop kept it. */
static int restore(const dtm_refine_result *rr, dtm_analysis *a, const double *kept) {
  DTM_CHECK(dtm_analysis_set_point_masses(a, kept));
  return reestimate(rr, a);
}

/* The round: its masses against the kept mesh's, the share they add. */
static int record_mass(dtm_refine_result *rr, const double *kept, double seconds, double percent) {
  const dtm_analysis *a = rr->analysis;
  size_t nn = dtm_analysis_mesh(a)->nnodes, nodes = 0;
  const double *pm = dtm_analysis_point_masses(a);
  for (size_t v = 0; v < nn; v++) nodes += pm[v] > (kept ? kept[v] : 0.0);
  int i = rr->nrounds++;
  dtm_refine_round *r = &rr->rounds[i];
  double d = dtm_analysis_scene(a)->duration, rec = dtm_analysis_recommended(a);
  *r = rr->rounds[rr->best]; /* the same mesh: its accuracy figures and element counts */
  r->kind = DTM_ROUND_MASS, r->basis = dtm_analysis_basis(a), r->recommended = rec, r->gap = rr->target / rec - 1.0;
  r->element_steps = d > 0 ? (double)r->elements * ceil(d / rec) : NAN, r->rate = r->elements / rec;
  r->below = dtm_analysis_below_target(a), r->seconds = seconds, r->calibration = NAN, r->counts = 0;
  r->optimise = 0, r->added_mass = total(pm, nn) - total(kept, nn), r->added_percent = percent, r->mass_nodes = nodes;
  if (rec >= rr->target) rr->best = i;
  return DTM_OK;
}

/* Why the masses were not kept: more than allowed, or a global estimate
 * that did not reach the target in TRIES steps. */
static void unconfirmed_cause(dtm_refine_result *rr, int tries) {
  if (isfinite(rr->mass_needed)) return dtm_refine_mass_cause(rr);
  dtm_cause *c = dtm_refine_new_cause(rr, "mass-unconfirmed");
  if (c)
    snprintf(c->text, sizeof c->text,
             "point masses at the nodes below the target did not lift the global estimate to it in %d step(s): no "
             "mass was kept",
             tries);
}

int dtm_refine_mass_round(dtm_refine_result *rr) {
  dtm_analysis *a = rr->analysis;
  if (!(rr->options.max_added_mass > 0) || !isfinite(dtm_analysis_dt_nodal(a))) return DTM_OK;
  double t0 = dtm_wtime(), safety = dtm_analysis_scene(a)->safety, percent = 0;
  size_t nn = dtm_analysis_mesh(a)->nnodes;
  const double *pm = dtm_analysis_point_masses(a);
  double *kept = pm ? malloc((nn + 1) * sizeof *kept) : NULL, carried = total(pm, nn);
  if (pm && !kept) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (kept) memcpy(kept, pm, nn * sizeof *kept);
  double aim = dtm_analysis_advice_target(a) / safety * (1 + EDGE);
  int r = DTM_OK, tries = 0, set = 0;
  while (r == DTM_OK && tries++ < TRIES && dtm_analysis_recommended(a) < rr->target) {
    r = add_step(rr, a, aim, carried, &percent);
    if (r == DTM_OK && percent > rr->options.max_added_mass) break;
    set = 1;
    aim *= fmax(1.0, rr->target / dtm_analysis_recommended(a)) * OVERSHOOT;
  }
  int enough = r == DTM_OK && dtm_analysis_recommended(a) >= rr->target;
  if (r == DTM_OK && enough) r = record_mass(rr, kept, dtm_wtime() - t0, percent);
  if (r == DTM_OK && !enough) {
    rr->mass_needed = percent > rr->options.max_added_mass ? percent : NAN;
    unconfirmed_cause(rr, tries - 1);
    if (set) r = restore(rr, a, kept);
  }
  free(kept);
  return r;
}
