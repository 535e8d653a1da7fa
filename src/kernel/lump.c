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
 * product of the 1D Simpson weights 1/6, 2/3, 1/6).
 *
 * A tet10 integrated with CalculiX's 4-point C3D10 rule (the "calculix"
 * model, curved.c; no other model gives a tet10 a 4-point rule) is lumped
 * as CalculiX 2.20 lumps C3D10 for explicit dynamics (docs/curved.md): the
 * diagonal d_a = sum_k N_a^2 dv_k of the consistent mass at the 4 points,
 * scaled separately over the corners and over the mid-edge nodes so that
 * the corners carry ALP/(1 + ALP) of the element's 4-point measure and
 * the mid-edge nodes 1/(1 + ALP), with CalculiX's constant ALP = 0.1203.
 * On a straight-sided tet10: corners ALP/(4 (1 + ALP)) = 0.026846 V,
 * mid-edge nodes 1/(6 (1 + ALP)) = 0.148770 V (HRZ: 1/36 and 4/27). */
#if defined(__GNUC__) && !defined(__clang__)
/* Let GCC vectorise the loops with a varying trip count (axpy updates of
 * the element matrices): -O2's very-cheap cost model leaves them scalar.
 * Lanes are independent, so every sum is rounded as before. */
#pragma GCC optimize("vect-cost-model=dynamic")
#endif
#include "kernel-impl.h"

#define C3D10_ALP 0.1203 /* corner / mid-edge mass ratio of CalculiX's C3D10 lumping */

/* CalculiX's C3D10 lumping of the diagonal m[10] (d_a above) to vol. */
static void lump_c3d10(double vol, double *m) {
  double se = 0, sm = 0;
  for (int a = 0; a < 4; a++) se += m[a];
  for (int a = 4; a < 10; a++) sm += m[a];
  double fe = se != 0 ? vol * C3D10_ALP / (1 + C3D10_ALP) / se : 0;
  double fm = sm != 0 ? vol / (1 + C3D10_ALP) / sm : 0;
  for (int a = 0; a < 10; a++) m[a] *= a < 4 ? fe : fm;
}

/* The masses of the rule q, with the shape functions of table t when
 * there is one (else evaluated here). */
static double lumped(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, const dtm_ref_table *t,
                     double *m) {
  double Nk[DTM_K_NODES], dN[DTM_K_NODES][3], dv, vol = 0;
  int hrz = dtm_elem_parent(type) != type;
  for (int a = 0; a < nn; a++) m[a] = 0;
  double dvs[4];
  for (int k = 0; k < q->n; k++) {
    if (!t) dtm_ref_eval(type, q->p[k], Nk, dN);
    const double *N = t ? t->N[k] : Nk;
    if (t && d == 3 && k % 4 == 0 && k + 4 <= q->n) /* the next four points' det J side by side */
      dtm_map_dv_dn4(nn, xl, (const dtm_v4d(*)[3])t->dN4[k / 4], &q->w[k], dvs);
    if (t && d == 3 && k - k % 4 + 4 <= q->n)
      dv = dvs[k % 4];
    else
      dtm_map_dv_dn(d, nn, xl, t ? (const double(*)[3])t->dN[k] : (const double(*)[3])dN, q->w[k], &dv);
    for (int a = 0; a < nn; a++) m[a] += (hrz ? N[a] * N[a] : N[a]) * dv;
    vol += dv;
  }
  dtm_lumped_finish(type, nn, q->n, vol, m);
  return vol;
}

void dtm_lumped_finish(int type, int nn, int npoints, double vol, double *m) {
  double sum = 0;
  if (dtm_elem_parent(type) == type) return;
  if (type == DTM_TET10 && npoints == 4) {
    lump_c3d10(vol, m);
    return;
  }
  for (int a = 0; a < nn; a++) sum += m[a];
  for (int a = 0; a < nn; a++) m[a] = sum != 0 ? m[a] * (vol / sum) : 0;
}

double dtm_lumped_mass(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, double *m) {
  return lumped(type, d, nn, xl, q, NULL, m);
}

double dtm_lumped_mass_table(int type, int d, int nn, const double (*xl)[3], const dtm_ref_table *t, double *m) {
  return lumped(type, d, nn, xl, &t->q, t, m);
}
