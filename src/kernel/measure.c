/* Measure (length, area, volume) and lumped weights of an element
 * (row sums for linear types, HRZ for second-order ones: lump.c),
 * integrated with the element's full rule in its own frame. The measure is
 * the integral of det J: exact for every linear type and for straight-sided
 * second-order elements with mid-side nodes at the middle (the Jacobian
 * determinant is within each rule's degree; a curved element's is a
 * polynomial of higher degree, integrated approximately), negative for an
 * inverted 3D element, and for a 2D element the area of its projection on
 * the mean plane of its corners. Neither function raises errors: they return NaN for an unknown
 * type or for nodes that span no line or plane. */
#include <math.h>

#include "kernel/kernel_impl.h"

/* Lumped masses per unit density into m[nn] and the measure, or NaN. */
static double integrate(int type, const double *x, double *m) {
  int d, nn;
  double xl[DTM_K_NODES][3];
  dtm_qrule q;
  if (!dtm_elem_topology(type)) return NAN;
  dtm_elem_info(type, &d, &nn);
  for (int a = 0; a < nn; a++) m[a] = 0;
  if (dtm_elem_local(type, x, xl)) return 0;
  dtm_ref_rule(type, &q);
  return dtm_lumped_mass(type, d, nn, (const double (*)[3])xl, &q, m);
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
