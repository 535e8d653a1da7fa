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
 * caller allows; beyond it, on the global basis, the least share that
 * works is searched for: the rule's masses (found with no limit) scaled by
 * a factor bisected between 0 and 1, each try confirmed by the global
 * estimate with the masses; the least scaled set that meets the target is
 * kept when it is within the limit, else its share is recorded as needed
 * (rr->mass_least). On the nodal basis the rule's share is already the
 * least for the nodal bound (each node gets the least mass that lifts its
 * own bound), and it is recorded as what the rule adds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

#define LEAST_STEPS 8 /* bisections of the scale: the share to 0.4 % of the rule's */

/* The global estimate of analysis a with masses s x m[nn] (none when s = 0);
 * 1 in *ok when it meets the target. */
static int try_scale(dtm_refine_result *rr, const double *m, size_t nn, double s, double *buf, int *ok) {
  dtm_analysis *a = rr->analysis;
  for (size_t v = 0; v < nn; v++) buf[v] = s * m[v];
  DTM_CHECK(dtm_analysis_set_point_masses(a, s > 0 ? buf : NULL));
  DTM_CHECK(dtm_analysis_estimate_global(a, rr->options.tol, rr->options.lanczos_max, DTM_GLOBAL_BASIS));
  *ok = dtm_analysis_recommended(a) >= rr->target;
  return DTM_OK;
}

/* On the global basis, when the rule's share is beyond the limit: the
 * least scale of the rule's masses that the global estimate confirms (see
 * above); kept when within the limit (*found updated), else recorded. */
static int least_share(dtm_refine_result *rr, dtm_mass_found *found) {
  dtm_analysis *a = rr->analysis;
  size_t nn = dtm_analysis_mesh(a)->nnodes;
  dtm_mass_aim aim = {rr->target, 1, rr->options.tol, rr->options.lanczos_max, DTM_MASS_CAP};
  dtm_mass_found all;
  DTM_CHECK(dtm_mass_points(a, &aim, &all));
  if (!all.kept) return DTM_OK;
  double *m = malloc((nn + 1) * sizeof *m), *buf = malloc((nn + 1) * sizeof *buf), lo = 0, hi = 1;
  int r = m && buf ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory"), ok = 0;
  if (r == DTM_OK) memcpy(m, dtm_analysis_point_masses(a), nn * sizeof *m);
  for (int k = 0; k < LEAST_STEPS && r == DTM_OK; k++) {
    double s = 0.5 * (lo + hi);
    r = try_scale(rr, m, nn, s, buf, &ok);
    if (ok)
      hi = s;
    else
      lo = s;
  }
  double share = hi * all.percent;
  int keep = share <= rr->options.max_added_mass;
  if (r == DTM_OK) r = try_scale(rr, m, nn, keep ? hi : 0.0, buf, &ok);
  if (r == DTM_OK && keep && ok) {
    found->kept = found->met = 1, found->percent = share, found->added = hi * all.added, found->nodes = all.nodes;
  } else if (r == DTM_OK) {
    rr->mass_needed = share, rr->mass_least = 1;
  }
  free(m), free(buf);
  return r;
}

int dtm_refine_mass_round(dtm_refine_result *rr) {
  dtm_analysis *a = rr->analysis;
  if (!(rr->options.max_added_mass > 0)) return DTM_OK;
  double t0 = dtm_wtime();
  dtm_mass_aim aim = {rr->target, rr->options.global, rr->options.tol, rr->options.lanczos_max,
                      rr->options.max_added_mass};
  dtm_mass_found found;
  DTM_CHECK(dtm_mass_points(a, &aim, &found));
  if (!found.kept && found.met && rr->options.global && !dtm_analysis_point_masses(a))
    DTM_CHECK(least_share(rr, &found));
  if (found.kept) record_mass(rr, dtm_wtime() - t0, &found);
  if (!found.kept && isfinite(dtm_analysis_dt_nodal(a))) {
    if (!rr->mass_least) rr->mass_needed = found.met ? found.percent : NAN;
    not_kept_cause(rr);
  }
  return DTM_OK;
}
