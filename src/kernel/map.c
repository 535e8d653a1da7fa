/* The isoparametric map from the reference element to the element in its
 * own frame: Jacobian, its determinant, physical gradients of the shape
 * functions, and the validity check that rejects degenerate or inverted
 * elements. A Jacobian is taken as valid when det J > 32 eps times its
 * Hadamard bound (the product of its column lengths): below that the sign
 * of the determinant is not trustworthy in double precision, so the element
 * is flat to rounding. Slivers of any realistic flatness pass. The check
 * covers every quadrature point and every node. */
#include <float.h>
#include <math.h>

#include "kernel-impl.h"

/* J[i][j] = d x_i / d xi_j, i, j < d. */
static void jacobian(int d, int nn, const double (*xl)[3], const double (*dN)[3], double J[3][3]) {
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) {
      J[i][j] = 0;
      for (int a = 0; a < nn; a++) J[i][j] += xl[a][i] * dN[a][j];
    }
}

double dtm_map_eval(int type, int d, int nn, const double (*xl)[3], const double p[3], double wq, double *N,
                    double (*g)[3], double *dv) {
  double dN[DTM_K_NODES][3], J[3][3], K[3][3];
  dtm_ref_eval(type, p, N, dN);
  jacobian(d, nn, xl, (const double(*)[3])dN, J);
  double dj = dtm_mat_det(d, (const double(*)[3])J);
  dtm_mat_inverse(d, (const double(*)[3])J, dj, K);
  for (int a = 0; a < nn; a++)
    for (int i = 0; i < 3; i++) {
      g[a][i] = 0;
      for (int j = 0; j < d && i < d; j++) g[a][i] += K[j][i] * dN[a][j];
    }
  *dv = dj * wq;
  return dj;
}

/* 0 when det J at rule coordinates p is safely positive. */
static int valid_at(int type, int d, int nn, const double (*xl)[3], const double p[3], double *dj) {
  double N[DTM_K_NODES], dN[DTM_K_NODES][3], J[3][3];
  dtm_ref_eval(type, p, N, dN);
  jacobian(d, nn, xl, (const double(*)[3])dN, J);
  *dj = dtm_mat_det(d, (const double(*)[3])J);
  return *dj > 32 * DBL_EPSILON * dtm_mat_hadamard(d, (const double(*)[3])J) && isfinite(*dj) ? 0 : -1;
}

int dtm_map_first_bad(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, double *dj) {
  double p[3];
  for (int k = 0; k < q->n + nn; k++) {
    const double *pk = p;
    if (k < q->n)
      pk = q->p[k];
    else
      dtm_ref_node(type, k - q->n, p);
    if (valid_at(type, d, nn, xl, pk, dj)) return k;
  }
  return -1;
}
