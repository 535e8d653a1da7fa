/* The cost object: what a run of the scene's duration costs on the
 * analysed mesh in element-steps, with one global step (the recommended
 * step) and with ideal subcycling, plus the subcycling levels and, when the
 * scene has a target, the mass scaling that would reach it and the mass
 * the shape-limited elements need, the run time in hours and the accuracy
 * measures. Everything rests on one step, dt.recommended, and its basis. */
#include <math.h>
#include <stdlib.h>

#include "dtmap/cost.h"
#include "dtmap/util.h"

double dtm_cost_element_steps(const dtm_analysis *a) {
  double d = dtm_analysis_scene(a)->duration;
  return d > 0 ? (double)dtm_analysis_nelements(a) * ceil(d / dtm_analysis_recommended(a)) : NAN;
}

double dtm_cost_element_steps_subcycled(const dtm_analysis *a, const dtm_subcycling *sc) {
  return dtm_cost_element_steps(a) / sc->speedup;
}

void dtm_cost_destroy(dtm_cost **pc) {
  dtm_cost *c = *pc;
  if (!c) return;
  dtm_subcycling_free(&c->subcycling);
  if (c->mass) dtm_mass_scaling_free(c->mass);
  if (c->shape_mass) dtm_mass_scaling_free(c->shape_mass);
  free(c->mass);
  free(c->shape_mass);
  if (c->layer_mass) dtm_mass_scaling_free(c->layer_mass);
  free(c->layer_mass);
  dtm_measures_destroy(&c->measures);
  free(c);
  *pc = NULL;
}

/* The step the advice aims the element and nodal steps at, before the
 * safety factor: the scene's target, or its equivalent on the global
 * basis (dtm_analysis_advice_target). */
static double aim(const dtm_analysis *a) { return dtm_analysis_advice_target(a) / dtm_analysis_scene(a)->safety; }

/* Mass scaling to the scene's target from the basis: at the nodes whenever
 * there is a nodal bound (then the recommendation, never below it, reaches
 * the target too; on the global basis, the nodal steps reach the advice
 * target, which a global estimate with the masses confirms only when it is
 * run: refine does), element by element when the element bound is all
 * there is. */
static int target_mass(const dtm_analysis *a, dtm_cost *c) {
  c->mass = calloc(1, sizeof *c->mass);
  if (!c->mass) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (!isfinite(dtm_analysis_dt_nodal(a))) return dtm_mass_scaling_compute(a, aim(a), c->mass);
  return dtm_mass_scaling_nodal(a, aim(a), NULL, c->mass);
}

/* The mass the nodes of the shape-limited elements (thin: only those of
 * the thin feature, the thickness-limited ones) need, into *out; NULL when
 * there are none. */
static int shape_mass(const dtm_analysis *a, int thin, dtm_mass_scaling **out) {
  size_t n, k = 0;
  const dtm_shape_limited *sl = dtm_analysis_shape_limited(a, &n);
  for (size_t j = 0; j < n; j++) k += !thin || sl[j].feature == DTM_FEATURE_THIN;
  if (!k) return DTM_OK;
  unsigned char *only = calloc(dtm_analysis_nelements(a) + 1, 1);
  *out = calloc(1, sizeof **out);
  if (!only || !*out) return free(only), DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t j = 0; j < n; j++) only[sl[j].element] |= !thin || sl[j].feature == DTM_FEATURE_THIN;
  int r = dtm_mass_scaling_nodal(a, aim(a), only, *out);
  free(only);
  return r;
}

/* Hours from element-steps and the cost of one. */
static int time_cost(const dtm_analysis *a, dtm_cost *c) {
  DTM_CHECK(dtm_cost_per_element_step(a, &c->per_element_step, c->per_element_step_source,
                                      sizeof c->per_element_step_source));
  c->hours = c->element_steps * c->per_element_step / 3600;
  c->hours_subcycled = c->element_steps_subcycled * c->per_element_step / 3600;
  return DTM_OK;
}

int dtm_cost_create(const dtm_analysis *a, dtm_cost **out) {
  const dtm_scene *s = dtm_analysis_scene(a);
  dtm_cost *c = calloc(1, sizeof *c);
  if (!c) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  double t0 = dtm_wtime();
  int r = dtm_subcycling_compute(a, &c->subcycling);
  c->duration = s->duration;
  c->basis = dtm_analysis_recommended(a);
  c->steps = s->duration > 0 ? ceil(s->duration / c->basis) : NAN;
  c->element_steps = dtm_cost_element_steps(a);
  c->element_steps_subcycled = r ? NAN : dtm_cost_element_steps_subcycled(a, &c->subcycling);
  int aimed = dtm_analysis_advice_target(a) > 0;
  if (r == DTM_OK && aimed) r = target_mass(a, c);
  if (r == DTM_OK && aimed) r = shape_mass(a, 0, &c->shape_mass);
  if (r == DTM_OK && aimed) r = shape_mass(a, 1, &c->layer_mass);
  if (r == DTM_OK) r = time_cost(a, c);
  double t1 = dtm_wtime();
  if (r == DTM_OK) r = dtm_measures_compute(a, 0, NULL, &c->measures);
  c->seconds_measures = dtm_wtime() - t1, c->seconds = dtm_wtime() - t0;
  if (r) {
    dtm_cost_destroy(&c);
    return dtm_error_trace(r, __FILE__, __LINE__, __func__);
  }
  *out = c;
  return DTM_OK;
}
