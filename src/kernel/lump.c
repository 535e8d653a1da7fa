/* Lumped (diagonal) mass of one element, per unit density. Linear types
 * keep the row sums m_a = integral N_a: positive for them, equal to HRZ
 * on linear simplices and on parallelogram quad4 / parallelepiped hex8, so
 * existing results do not move. Row sums fail for second-order types: on
 * a tet10 the corner row sum is integral L (2L - 1) = -V/20 < 0, and a
 * zero or negative mass has no explicit time step. Those use HRZ lumping
 * (Hinton, Rock and Zienkiewicz 1976): the diagonal of the consistent
 * mass, d_a = integral N_a^2 > 0, scaled so that the total is the
 * element's measure, m_a = d_a V / sum_b d_b. Every mass is positive and
 * the total (rigid translation) mass is exact. The rule must integrate
 * N_a^2 exactly on straight-sided elements (quadrature.c). Hand values on
 * straight-sided elements: tri6 corners 3/57, mid-edges 16/57 of V; tet10
 * corners 1/36, mid-edges 4/27; quad9 1/36, 1/9 and 4/9 (the tensor
 * product of the 1D Simpson weights 1/6, 2/3, 1/6). */
#include "kernel-impl.h"

double dtm_lumped_mass(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, double *m) {
  double N[DTM_K_NODES], g[DTM_K_NODES][3], dv, vol = 0, sum = 0;
  int hrz = dtm_elem_parent(type) != type;
  for (int a = 0; a < nn; a++) m[a] = 0;
  for (int k = 0; k < q->n; k++) {
    dtm_map_eval(type, d, nn, xl, q->p[k], q->w[k], N, g, &dv);
    for (int a = 0; a < nn; a++) m[a] += (hrz ? N[a] * N[a] : N[a]) * dv;
    vol += dv;
  }
  if (!hrz) return vol;
  for (int a = 0; a < nn; a++) sum += m[a];
  for (int a = 0; a < nn; a++) m[a] = sum != 0 ? m[a] * (vol / sum) : 0;
  return vol;
}
