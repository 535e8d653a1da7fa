/* Largest eigenvalue of a larger dense symmetric matrix: Householder
 * reduction to tridiagonal form, then bisection on Sturm counts. This is
 * the path of the second-order element problems (30 x 30 for tet10 up to
 * 81 x 81 for hex27), where cyclic Jacobi (jacobi.c, ~n^3 per sweep and
 * several sweeps, ~30 ms at n = 81) is far too slow; the reduction costs
 * about 2 n^3 flops once and the bisection O(n) per step. Both stages
 * are backward stable: the result is the largest eigenvalue of a matrix
 * within a small multiple of n eps |A| of A, so it is within that of the
 * exact one, like Jacobi's. The matrix is scaled by its largest entry
 * first, so neither stage can overflow or underflow for any element size.
 * No allocation: the reduction works in place on the lower triangle, the
 * tridiagonal part lives on the stack (n <= DTM_K_DOF). */
#include <float.h>
#include <math.h>

#include "kernel-impl.h"

/* Reduce the trailing block of a (rows/columns k+1.. of the n x n matrix,
 * of which only the lower triangle is read and written) with one
 * Householder reflection H = I - beta v v^T that zeroes a[k+2..][k];
 * returns the new subdiagonal entry a[k+1][k]. With p = beta A v and
 * q = p - (beta/2)(v.p) v, H A H = A - v q^T - q v^T. */
static double reflect(int n, double *a, int k) {
  double v[DTM_K_DOF], p[DTM_K_DOF], xx = 0;
  int m = n - k - 1;                   /* size of the trailing block, >= 2 */
  double *b = a + (k + 1) * n + k + 1; /* its first entry; row stride n */
  v[0] = a[(k + 1) * n + k];
  for (int i = 1; i < m; i++) v[i] = a[(k + 1 + i) * n + k], xx += v[i] * v[i];
  xx += v[0] * v[0];
  double alpha = v[0] > 0 ? -sqrt(xx) : sqrt(xx);
  double vv = xx - v[0] * v[0] + (v[0] - alpha) * (v[0] - alpha);
  v[0] -= alpha;
  if (!(vv > 0)) return v[0] + alpha; /* column already zero */
  double beta = 2 / vv, K = 0;
  for (int i = 0; i < m; i++) p[i] = 0;
  for (int i = 0; i < m; i++) { /* p = A v from the lower triangle */
    const double *row = b + i * n;
    double s = 0;
    for (int j = 0; j < i; j++) s += row[j] * v[j], p[j] += row[j] * v[i];
    p[i] += s + row[i] * v[i];
  }
  for (int i = 0; i < m; i++) p[i] *= beta, K += v[i] * p[i];
  K *= beta / 2;
  for (int i = 0; i < m; i++) p[i] -= K * v[i]; /* q */
  for (int i = 0; i < m; i++) {
    double *row = b + i * n;
    for (int j = 0; j <= i; j++) row[j] -= v[i] * p[j] + p[i] * v[j];
  }
  return alpha;
}

/* Number of eigenvalues of the tridiagonal (d, e) below x (Sturm count of
 * the LDL^T pivots; a zero pivot is nudged off zero); e2[i] = e[i]^2. */
static int below(int n, const double *d, const double *e2, double x) {
  int c = 0;
  double q = 1;
  for (int i = 0; i < n; i++) {
    q = d[i] - x - (i ? e2[i - 1] / q : 0);
    if (q == 0) q = -DBL_EPSILON * (fabs(x) + DBL_MIN);
    c += q < 0;
  }
  return c;
}

/* Largest eigenvalue of the tridiagonal: bisection inside the Gershgorin
 * interval down to a few ulps. */
static double tri_max(int n, const double *d, const double *e) {
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < n; i++) {
    double r = (i ? fabs(e[i - 1]) : 0) + (i + 1 < n ? fabs(e[i]) : 0);
    lo = fmin(lo, d[i] - r), hi = fmax(hi, d[i] + r);
  }
  double tol = 4 * DBL_EPSILON * fmax(fabs(lo), fabs(hi)), e2[DTM_K_DOF];
  for (int i = 0; i + 1 < n; i++) e2[i] = e[i] * e[i]; /* once, not at every step */
  for (int it = 0; it < 200 && hi - lo > tol; it++) {
    double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (below(n, d, e2, mid) == n)
      hi = mid; /* all below: max < mid */
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

double dtm_eig_sym_max_tridiag(int n, double *a) {
  double d[DTM_K_DOF], e[DTM_K_DOF], s = 0;
  for (int i = 0; i < n * n; i++) {
    if (!isfinite(a[i])) return NAN; /* a NaN would not compare */
    s = fabs(a[i]) > s ? fabs(a[i]) : s;
  }
  if (s == 0) return 0;
  for (int i = 0; i < n * n; i++) a[i] /= s;
  for (int k = 0; k + 2 < n; k++) e[k] = reflect(n, a, k);
  if (n >= 2) e[n - 2] = a[(n - 1) * n + n - 2];
  for (int i = 0; i < n; i++) d[i] = a[i * n + i];
  return s * tri_max(n, d, e);
}
