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

#include "kernel-impl.h"
#include "assemble-impl.h"

int dtm_ref_rule_id(int type, int model, int level) {
  if (model == DTM_INTEGRATION_CALCULIX && type == DTM_TET10) return DTM_K_RULE_C3D10;
  return model == DTM_INTEGRATION_CONVERGED && dtm_ref_level_table(type, level) ? level : 0;
}

int dtm_ref_rule_at(int type, int model, int level, dtm_qrule *q) {
  int id = dtm_ref_rule_id(type, model, level);
  if (id == DTM_K_RULE_C3D10)
    dtm_ref_rule_c3d10(q);
  else if (id)
    *q = dtm_ref_level_table(type, id)->q;
  else
    dtm_ref_rule(type, q);
  return id;
}

/* Lumped masses per unit density into m[nn] and the measure, or NaN, with
 * the rule of level (as dtm_elem_rule_choose returns it) or, when level is
 * -1, the rule the model chooses (the level search of curved.c). */
static double integrate(int type, const double *x, int model, int level, double *m) {
  int d, nn;
  double xl[DTM_K_NODES][3];
  dtm_qrule q;
  if (!dtm_elem_topology(type)) return NAN;
  dtm_elem_info(type, &d, &nn);
  for (int a = 0; a < nn; a++) m[a] = 0;
  if (dtm_elem_local(type, x, xl)) return 0;
  int id = level < 0 ? dtm_elem_rule_choose(type, d, nn, (const double(*)[3])xl, model, NULL, NULL)
                     : dtm_ref_rule_id(type, model, level);
  double vol;
  if (id == 0 && dtm_affine_lumped(type, d, nn, (const double(*)[3])xl, m, &vol)) return vol; /* straight tri6, tet10 */
  const dtm_ref_table *t = dtm_ref_rule_table(type, id); /* full rules too: the shape functions evaluated once */
  if (t && dtm_memo_get(type, t, nn, nn * d, (const double(*)[3])xl, NULL, m, &vol)) return vol; /* searched just now */
  if (t) return dtm_lumped_mass_table(type, d, nn, (const double(*)[3])xl, t, m);
  dtm_ref_rule_at(type, model, id, &q); /* no memory for the table */
  return dtm_lumped_mass(type, d, nn, (const double(*)[3])xl, &q, m);
}

/* Closed forms of the linear simplices, the hot path of the nodal bound and
 * the operators: signed volume of a tet (as the rule gives it), area of a
 * triangle, length of a bar. */
static int simplex_measure(int type, const double *x, double *v) {
  double a[3], b[3], c[3];
  for (int i = 0; i < 3; i++) a[i] = x[3 + i] - x[i];
  if (type == DTM_LINE2) return *v = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), 1;
  for (int i = 0; i < 3; i++) b[i] = x[6 + i] - x[i];
  double n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  if (type == DTM_TRI3) return *v = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1;
  if (type != DTM_TET4) return 0;
  for (int i = 0; i < 3; i++) c[i] = x[9 + i] - x[i];
  return *v = (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / 6.0, 1;
}

double dtm_elem_measure_at(int type, const double *x, int level) {
  double m[DTM_K_NODES], v;
  if (simplex_measure(type, x, &v)) return v;
  return integrate(type, x, DTM_INTEGRATION_CONVERGED, level, m);
}

double dtm_elem_measure(int type, const double *x) { return dtm_elem_measure_at(type, x, -1); }

double dtm_elem_lumped_at(int type, const double *x, int model, int level, double *w) {
  if (type == DTM_LINE2 || type == DTM_TRI3 || type == DTM_TET4) {
    int nn = type == DTM_LINE2 ? 2 : type == DTM_TRI3 ? 3 : 4;
    for (int a = 0; a < nn; a++) w[a] = 1.0 / nn; /* row sums of a linear simplex */
    return dtm_elem_measure(type, x);
  }
  double m[DTM_K_NODES];
  double vol = integrate(type, x, model, level, m);
  int nn = 0;
  if (dtm_elem_topology(type)) dtm_elem_info(type, NULL, &nn);
  for (int a = 0; a < nn; a++) w[a] = m[a] / vol;
  return vol;
}

double dtm_elem_lumped_model(int type, const double *x, int model, double *w) {
  return dtm_elem_lumped_at(type, x, model, -1, w);
}

void dtm_elem_lumped_weights(int type, const double *x, double *w) {
  dtm_elem_lumped_model(type, x, DTM_INTEGRATION_CONVERGED, w);
}
