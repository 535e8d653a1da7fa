/* The cost object: what a run of the scene's duration costs on the
 * analysed mesh in element-steps, with one global step (the recommended
 * step) and with ideal subcycling, plus the subcycling levels and, when the
 * scene has a target, the mass scaling that would reach it. */
#include <math.h>
#include <stdlib.h>

#include "dtmap/cost.h"

double dtm_cost_element_steps(const dtm_analysis *a) {
  double d = dtm_analysis_scene(a)->duration;
  return d > 0 ? (double)dtm_analysis_nelements(a) * ceil(d / dtm_analysis_recommended(a)) : NAN;
}

double dtm_cost_element_steps_subcycled(const dtm_analysis *a, const dtm_subcycling *sc) {
  const dtm_scene *s = dtm_analysis_scene(a);
  if (!(s->duration > 0)) return NAN;
  double step = s->safety * dtm_analysis_dt_min(a, NULL);
  return (double)dtm_analysis_nelements(a) * ceil(s->duration / step) / sc->speedup;
}

void dtm_cost_destroy(dtm_cost **pc) {
  dtm_cost *c = *pc;
  if (!c) return;
  dtm_subcycling_free(&c->subcycling);
  if (c->mass) dtm_mass_scaling_free(c->mass);
  free(c->mass);
  free(c);
  *pc = NULL;
}

int dtm_cost_create(const dtm_analysis *a, dtm_cost **out) {
  const dtm_scene *s = dtm_analysis_scene(a);
  dtm_cost *c = calloc(1, sizeof *c);
  if (!c) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int r = dtm_subcycling_compute(a, &c->subcycling);
  c->duration = s->duration;
  c->element_steps = dtm_cost_element_steps(a);
  c->element_steps_subcycled = r ? NAN : dtm_cost_element_steps_subcycled(a, &c->subcycling);
  if (r == DTM_OK && s->target > 0) {
    c->mass = calloc(1, sizeof *c->mass);
    r = c->mass ? dtm_mass_scaling_compute(a, s->target / s->safety, c->mass)
                : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  }
  if (r) {
    dtm_cost_destroy(&c);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = c;
  return DTM_OK;
}
