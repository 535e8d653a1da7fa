/* Largest eigenvalue of a small dense symmetric matrix by the cyclic Jacobi
 * method (Rutishauser's rotation formulas). Used for the element problems
 * of the linear non-simplex elements (at most 24 x 24) and by the tests as
 * an independent check of the simplex closed forms and of tridiag.c, which
 * serves the larger second-order problems. Jacobi is slow next to a
 * tridiagonal QR but robust, needs no workspace and gives every eigenvalue
 * to a small multiple of eps times the norm of the matrix. */
#include <float.h>
#include <math.h>

#include "dtmap/kernel.h"

/* Zero a[p][q] (row-major n x n, symmetric) with one rotation. */
static void rotate(int n, double *a, int p, int q) {
  double apq = a[p * n + q];
  double theta = (a[q * n + q] - a[p * n + p]) / (2 * apq);
  double t = fabs(theta) > 1e150 ? 0.5 / theta : (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
  double c = 1 / sqrt(t * t + 1), s = t * c, tau = s / (1 + c);
  a[p * n + p] -= t * apq;
  a[q * n + q] += t * apq;
  a[p * n + q] = a[q * n + p] = 0;
  for (int r = 0; r < n; r++) {
    if (r == p || r == q) continue;
    double g = a[r * n + p], h = a[r * n + q];
    a[r * n + p] = a[p * n + r] = g - s * (h + g * tau);
    a[r * n + q] = a[q * n + r] = h + s * (g - h * tau);
  }
}

static double off_diagonal(int n, const double *a) {
  double off = 0;
  for (int p = 0; p < n; p++)
    for (int q = p + 1; q < n; q++) off += a[p * n + q] * a[p * n + q];
  return off;
}

double dtm_eig_sym_max(int n, double *a) {
  double fro = 0;
  for (int i = 0; i < n * n; i++) fro += a[i] * a[i];
  /* Stop when the off-diagonal part, which bounds the eigenvalue error,
   * is below eps^2/100 of the squared norm; 50 sweeps is far beyond the
   * quadratic convergence of cyclic Jacobi on n <= 81. */
  double tol = 0.01 * DBL_EPSILON * DBL_EPSILON * fro;
  for (int sweep = 0; sweep < 50 && off_diagonal(n, a) > tol; sweep++)
    for (int p = 0; p < n; p++)
      for (int q = p + 1; q < n; q++)
        if (a[p * n + q] != 0) rotate(n, a, p, q);
  double m = -INFINITY;
  for (int i = 0; i < n; i++) m = fmax(m, a[i * n + i]);
  return m;
}
