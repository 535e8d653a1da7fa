/* Measure (length, area, volume) and row-sum lumped weights of an element,
 * integrated with the element's full rule in its own frame. The measure is
 * the integral of det J: exact for every supported type (the Jacobian
 * determinant is within each rule's degree), negative for an inverted 3D
 * element, and for a 2D element the area of its projection on its mean
 * plane. Neither function raises errors: they return NaN for an unknown
 * type or for nodes that span no line or plane. */
#include <math.h>

#include "kernel/kernel_impl.h"

/* Integrals of N_a into m[nn] and the measure, or NaN. */
static double integrate(int type, const double *x, double *m) {
  int d, nn;
  double xl[DTM_K_NODES][3], N[DTM_K_NODES], g[DTM_K_NODES][3], dv, vol = 0;
  dtm_qrule q;
  if (!dtm_elem_topology(type)) return NAN;
  dtm_elem_info(type, &d, &nn);
  for (int a = 0; a < nn; a++) m[a] = 0;
  if (dtm_elem_local(type, x, xl)) return 0;
  dtm_ref_rule(type, &q);
  for (int k = 0; k < q.n; k++) {
    dtm_map_eval(type, d, nn, (const double (*)[3])xl, q.p[k], q.w[k], N, g, &dv);
    for (int a = 0; a < nn; a++) m[a] += N[a] * dv;
    vol += dv;
  }
  return vol;
}

double dtm_elem_measure(int type, const double *x) {
  double m[DTM_K_NODES];
  return integrate(type, x, m);
}

void dtm_elem_lumped_weights(int type, const double *x, double *w) {
  double m[DTM_K_NODES];
  double vol = integrate(type, x, m);
  int nn = 0;
  if (dtm_elem_topology(type)) dtm_elem_info(type, NULL, &nn);
  for (int a = 0; a < nn; a++) w[a] = m[a] / vol;
}
