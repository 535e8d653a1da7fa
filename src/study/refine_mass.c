/* The mass round of refine: where no mesh meets the target (a thin wall, a
 * wedge, a fixed extrusion, a kept clamp or a spent budget), explicit users
 * scale the mass of exactly the limiting nodes (LS-DYNA's DT2MS, Abaqus's
 * *FIXED MASS SCALING on a set, Radioss's /DT/NODA/CST). On the kept mesh,
 * dtm_mass_points (src/cost/point_masses.c) finds them:
 * point masses go to the nodes whose nodal-bound step is below the aim:
 * node a needs m_a ((aim / dt_a)^2 - 1) (src/cost/mass.c), the least that
 * lifts its bound to the aim, since the bound's numerator does not change
 * with mass. On the nodal basis the aim is the target (before safety), and
 * the bound then meets it by construction. On the global basis two ways
 * are tried and the one that adds less kept: the same rule from the
 * advice target (the nodal steps of a mesh whose global step meets the
 * target), the global estimate run again with the masses and the aim
 * raised by its shortfall; and the top mode followed, the nodes that carry
 * 95 % of its kinetic energy getting the mass that lowers its eigenvalue
 * to the target's, again until the estimate meets it (a localised top
 * mode needs mass only where it lives, where the nodal rule also feeds
 * nodes whose bound is merely pessimistic). The analysis keeps the masses
 * only when their total is within the share of the model's mass the
 * caller allows; beyond it, the analysis is put back as it was and the
 * share needed is recorded. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "dtmap/cost.h"
#include "dtmap/util.h"
#include "study-impl.h"

/* The round: the kept mesh with the masses f found. */
static void record_mass(dtm_refine_result *rr, double seconds, const dtm_mass_found *f) {
  const dtm_analysis *a = rr->analysis;
  int i = rr->nrounds++;
  dtm_refine_round *r = &rr->rounds[i];
  double d = dtm_analysis_scene(a)->duration, rec = dtm_analysis_recommended(a);
  *r = rr->rounds[rr->best]; /* the same mesh: its accuracy figures and element counts */
  r->kind = DTM_ROUND_MASS, r->basis = dtm_analysis_basis(a), r->recommended = rec, r->gap = rr->target / rec - 1.0;
  r->element_steps = d > 0 ? (double)r->elements * ceil(d / rec) : NAN, r->rate = r->elements / rec;
  r->below = dtm_analysis_below_target(a), r->seconds = seconds, r->calibration = NAN, r->counts = 0;
  r->optimise = 0, r->added_mass = f->added, r->added_percent = f->percent, r->mass_nodes = f->nodes;
  if (rec >= rr->target) rr->best = i;
}

/* Why no mass was kept: more than allowed, or estimates that did not reach
 * the target. */
static void not_kept_cause(dtm_refine_result *rr) {
  if (isfinite(rr->mass_needed)) return dtm_refine_mass_cause(rr);
  dtm_cause *c = dtm_refine_new_cause(rr, "mass-unconfirmed");
  if (c)
    snprintf(c->text, sizeof c->text,
             "point masses at the nodes did not lift the global estimate to the target within %g %% of the model's "
             "mass: no mass was kept",
             DTM_MASS_CAP);
}

int dtm_refine_mass_round(dtm_refine_result *rr) {
  dtm_analysis *a = rr->analysis;
  if (!(rr->options.max_added_mass > 0)) return DTM_OK;
  double t0 = dtm_wtime();
  dtm_mass_aim aim = {rr->target, rr->options.global, rr->options.tol, rr->options.lanczos_max,
                      rr->options.max_added_mass};
  dtm_mass_found found;
  DTM_CHECK(dtm_mass_points(a, &aim, &found));
  if (found.kept) record_mass(rr, dtm_wtime() - t0, &found);
  if (!found.kept && isfinite(dtm_analysis_dt_nodal(a))) {
    rr->mass_needed = found.met ? found.percent : NAN;
    not_kept_cause(rr);
  }
  return DTM_OK;
}
