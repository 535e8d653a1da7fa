/* The way `mesh + selective mass` of refine (issue 44): where no mesh met
 * the target, the kept mesh (the cheapest tried that the way `mesh +
 * mass` would also start from, before any point masses go on it) is
 * scaled selectively to the target by dtm_analysis_selective_mass (each
 * element's added mass leaves every rigid translation's inertia exact and
 * lifts the element's own step to target / safety), with the options'
 * Lanczos tolerance and steps and the analysis's seed, so that `dtmap run
 * --selective-mass --target T` on the written mesh gives the same
 * figures. Beside it the point masses `deck --target` would add (the
 * nodal rule, dtm_mass_scaling_nodal at target / safety), and, when asked,
 * the lowest natural frequencies under both (dtm_modes_price). Shells,
 * beams and scenes without an elastic effect are refused by the scaling:
 * the reason is kept and the refine goes on. The scaled mass is not put
 * into the analysis: the written mesh has no view of it; a solver gets it
 * from `dtmap deck --selective-mass`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/selective.h"
#include "study-impl.h"

/* The point masses of deck --target's rule on the kept mesh. */
static int conventional(dtm_refine_result *rr) {
  dtm_refine_selective *w = &rr->selective;
  const dtm_analysis *a = rr->analysis;
  dtm_mass_scaling ms;
  w->conventional_added = w->conventional_percent = NAN, w->conventional_nodes = 0;
  if (!isfinite(dtm_analysis_dt_nodal(a))) return DTM_OK;
  DTM_CHECK(dtm_mass_scaling_nodal(a, rr->target / dtm_analysis_scene(a)->safety, NULL, &ms));
  w->conventional_added = ms.total_added, w->conventional_percent = 100.0 * ms.total_added / ms.total_mass;
  w->conventional_nodes = ms.nodes;
  dtm_mass_scaling_free(&ms);
  return DTM_OK;
}

/* The frequencies of the kept mesh and their shifts under both ways. */
static int modes(dtm_refine_result *rr) {
  dtm_refine_selective *w = &rr->selective;
  if (!(rr->options.modes > 0)) return DTM_OK;
  w->modes = calloc(1, sizeof *w->modes);
  if (!w->modes) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  DTM_CHECK(dtm_modes_price_base(rr->analysis, rr->options.modes, w->modes));
  DTM_CHECK(dtm_modes_price_conventional(rr->analysis, rr->target, w->modes));
  return dtm_modes_price_selective(rr->analysis, &w->sms, w->modes);
}

int dtm_refine_selective_way(dtm_refine_result *rr) {
  dtm_refine_selective *w = &rr->selective;
  if (!rr->options.selective_mass) return DTM_OK;
  if (rr->rounds[rr->best].recommended >= rr->target) return w->state = DTM_REFINE_SMS_NOT_NEEDED, DTM_OK;
  int r = dtm_analysis_selective_mass(rr->analysis, rr->target, rr->options.tol, rr->options.lanczos_max, &w->sms);
  if (r == DTM_ERR_INPUT) { /* shells, beams, no elastic effect: said, not an error of the refine */
    snprintf(w->why, sizeof w->why, "%s", dtm_error_message());
    dtm_error_clear();
    return w->state = DTM_REFINE_SMS_REFUSED, DTM_OK;
  }
  DTM_CHECK(r);
  w->state = DTM_REFINE_SMS_DONE, w->round = rr->best, w->lumped = rr->rounds[rr->best].recommended;
  DTM_CHECK(conventional(rr));
  return modes(rr);
}

double dtm_refine_selective_cost(const dtm_refine_result *rr) {
  const dtm_refine_selective *w = &rr->selective;
  if (w->state != DTM_REFINE_SMS_DONE) return NAN;
  const dtm_refine_round *b = &rr->rounds[w->round];
  double d = rr->scene.duration, rec = w->sms.recommended;
  double c = d > 0 ? (double)b->elements * ceil(d / rec) : (double)b->elements / rec;
  return c * w->sms.runtime_factor;
}

void dtm_refine_selective_free(dtm_refine_result *rr) {
  if (rr->selective.modes) dtm_modes_price_free(rr->selective.modes);
  free(rr->selective.modes);
  rr->selective.modes = NULL;
}
