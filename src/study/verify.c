/* `dtmap verify` in the library: run each spectral effect's own explicit
 * integrator on the mesh at a given step, starting from the effect's top
 * Ritz mode (found by the global estimate) plus a seeded random part, so
 * that an unstable step shows up as growth of the top mode within a few
 * hundred steps, and a stable one stays bounded. Only the scene's active
 * effects are simulated; the damping effect enters as element Rayleigh
 * damping at the top frequency. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base.h"
#include "dtmap/operator.h"
#include "dtmap/verify.h"

#define RANDOM_PART 0.1 /* share of the random part in the start, M-norm */

/* u0 = mode + RANDOM_PART r, with r random and r^T M r = 1. */
static void start_field(const dtm_operator *op, const double *mode, double *u0) {
  size_t n = dtm_operator_ndof(op);
  const double *m = dtm_operator_mass(op);
  double norm = 0;
  dtm_operator_draw(op, 12345, -0.5, 0.5, u0); /* per node tag: independent of the node order */
  for (size_t i = 0; i < n; i++) u0[i] = m[i] > 0 ? u0[i] : 0, norm += m[i] * u0[i] * u0[i];
  double s = norm > 0 ? RANDOM_PART / sqrt(norm) : 0;
  for (size_t i = 0; i < n; i++) u0[i] = mode[i] + s * u0[i];
}

static int verify_effect(const dtm_analysis *a, int k, double dt, int steps, dtm_verify_effect *out) {
  const dtm_global_info *g = dtm_analysis_global(a, k);
  dtm_operator *op = NULL;
  DTM_CHECK(dtm_analysis_operator(a, k, g->omega_top, &op));
  double *u0 = malloc((dtm_operator_ndof(op) + 1) * sizeof *u0);
  dtm_verify_result r;
  memset(&r, 0, sizeof r);
  int code = u0 ? DTM_OK : DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  if (code == DTM_OK) start_field(op, g->mode, u0), code = dtm_verify_run(op, dt, steps, u0, &r);
  free(u0);
  dtm_operator_destroy(&op);
  DTM_CHECK(code);
  *out = (dtm_verify_effect){1, r.growth, r.unstable, r.seconds};
  return DTM_OK;
}

int dtm_verify(const dtm_analysis *a, double dt, int steps, dtm_verify_effect *out) {
  int any = 0;
  for (int k = 0; k < dtm_analysis_neffects(a); k++) any |= dtm_analysis_global(a, k) != NULL;
  if (!any)
    return DTM_ERR(DTM_ERR_INPUT,
                   "%s: verify: no effect of the scene has a global estimate to start from (run the "
                   "estimate first; effects without a semi-discrete problem cannot be simulated)",
                   dtm_analysis_scene(a)->path);
  for (int k = 0; k < dtm_analysis_neffects(a); k++) {
    const dtm_global_info *g = dtm_analysis_global(a, k);
    memset(&out[k], 0, sizeof out[k]);
    if (g && g->mode) DTM_CHECK(verify_effect(a, k, dt, steps, &out[k]));
  }
  return DTM_OK;
}
