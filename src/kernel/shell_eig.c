/* Largest eigenvalue of a small dense symmetric matrix (the shell and beam
 * blocks of shell.c, 6 to 24 unknowns) in a few evaluations instead of a
 * bisection's fifty: tridiag.c's Householder reduction to tridiagonal form
 * (dtm_eig_sym_tridiagonalize: in place, lower triangle, scaled), then
 * iterations from above on the characteristic polynomial of the
 * tridiagonal T. One pass of the LDL^T pivots q_i of T - x I gives at once
 * the Sturm count (how many eigenvalues lie below x), G = sum_j 1/(x -
 * lambda_j) and H = sum_j 1/(x - lambda_j)^2 (recurrences on q_i, q_i',
 * q_i''). From x above every eigenvalue:
 *   - Laguerre's step L = x - n/(G + sqrt((n-1)(n H - G^2))) stays above
 *     lambda_max (all roots are real), cubically convergent to a simple
 *     top eigenvalue;
 *   - lambda_max >= x - n/G (each of the n terms of G is at most
 *     1/(x - lambda_max)): a lower bound;
 *   - the multiple-root step x - G/H (Newton on p/p') converges
 *     quadratically even to a double top eigenvalue, which symmetric
 *     elements (an equilateral triangle) have; it is tried first and kept
 *     only when the Sturm count proves it still above lambda_max.
 * The iteration stops when the bracket [lower, upper] is within 2e-14 of
 * lambda_max (or a few ulps of |T|), and falls back to bisection of that
 * bracket when rounding stops it or after 40 steps. The result is the
 * largest eigenvalue of the same tridiagonal as the bisection of
 * tridiag.c, to 1e-14: the two agree to about that (bench/shell_kernel.c,
 * tests/t530-shell-fast.c). */
#include <float.h>
#include <math.h>

#include "kernel-impl.h"
#include "structural.h"

typedef struct {
  int below;   /* eigenvalues below x */
  double g, h; /* sum 1/(x - l_j), sum 1/(x - l_j)^2 */
} sturm;

/* The pivots of T - x I and the log-derivatives of its determinant (one
 * division per pivot). */
static sturm evaluate(int n, const double *d, const double *e2, double x) {
  sturm s = {0, 0, 0};
  double r = 0, q1 = 0, q2 = 0; /* 1/q_{i-1} and the first two derivatives of q_{i-1} in x */
  for (int i = 0; i < n; i++) {
    double c = i ? e2[i - 1] : 0, r2 = r * r;
    double q = d[i] - x - c * r;
    double nq1 = -1 + c * q1 * r2;
    double nq2 = c * r2 * (q2 - 2 * q1 * q1 * r);
    if (q == 0) q = -DBL_EPSILON * (fabs(x) + DBL_MIN);
    r = 1 / q, q1 = nq1, q2 = nq2;
    s.below += q < 0;
    double t = q1 * r; /* d log|q_i| / dx */
    s.g += t;
    s.h -= q2 * r - t * t; /* H = -G' */
  }
  return s;
}

static double bisect(int n, const double *d, const double *e2, double lo, double hi, double tol) {
  for (int it = 0; it < 200 && hi - lo > tol; it++) {
    double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (evaluate(n, d, e2, mid).below == n)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

/* Whether the bracket [lo, hi] is narrow enough: a few ulps of the
 * matrix, or 2e-14 of lambda_max (a hundredth of the 1e-12 to which the
 * bounds must agree with the bisection's). */
static int narrow(double lo, double hi, double tol) { return hi - lo <= fmax(tol, 2e-14 * fabs(hi)); }

/* Largest eigenvalue of the tridiagonal (d, e). */
static double top(int n, const double *d, const double *e) {
  double lo = -INFINITY, hi = -INFINITY, e2[DTM_STRUCT_DOF], mag = 0;
  for (int i = 0; i < n; i++) {
    double r = (i ? fabs(e[i - 1]) : 0) + (i + 1 < n ? fabs(e[i]) : 0);
    hi = fmax(hi, d[i] + r), lo = fmax(lo, d[i]); /* Gershgorin; a diagonal entry is a Rayleigh quotient */
    mag = fmax(mag, fmax(fabs(d[i] - r), fabs(d[i] + r)));
  }
  for (int i = 0; i + 1 < n; i++) e2[i] = e[i] * e[i];
  double tol = 4 * DBL_EPSILON * mag, x = hi;
  if (n == 1 || hi - lo <= tol) return 0.5 * (lo + hi);
  sturm s = evaluate(n, d, e2, x);
  if (s.below != n) return bisect(n, d, e2, lo, hi, tol); /* rounding at the Gershgorin edge */
  for (int it = 0; it < 40; it++) {
    if (!(s.g > 0) || !isfinite(s.g)) break;
    lo = fmax(lo, x - n / s.g);
    double disc = (n - 1) * (n * s.h - s.g * s.g);
    double lag = x - n / (s.g + sqrt(fmax(disc, 0)));
    hi = fmin(hi, fmax(lag, lo));
    if (narrow(lo, hi, tol)) return 0.5 * (lo + hi);
    /* near the top, the multiple-root step: above lambda_max (kept) when
     * the top is multiple, else just below it (a lower bound) */
    double mult = fmax(x - s.g / s.h, lo + 1e-14 * fabs(lo)); /* at least just above lo: a diagonal entry
                                                                   is lambda_max when the top is double */
    if (x - mult < 1e-3 * fabs(x) && mult < hi) {
      sturm t = evaluate(n, d, e2, mult);
      if (t.below == n) {
        x = hi = mult, s = t;
        continue;
      }
      lo = mult;
      if (narrow(lo, hi, tol)) return 0.5 * (lo + hi);
    }
    double above = x; /* proved above lambda_max */
    s = evaluate(n, d, e2, hi);
    if (s.below == n) {
      x = hi;
      continue;
    }
    /* rounding near the top: Laguerre's point proved just below lambda_max;
     * a point 1e-14 above it closes the bracket, else bisect it */
    lo = hi, hi = above;
    double up = lo + 1e-14 * fabs(lo);
    if (up < hi && evaluate(n, d, e2, up).below == n) hi = up;
    break;
  }
  return bisect(n, d, e2, lo, hi, tol);
}

double dtm_struct_eig_max(int n, double *a) {
  double d[DTM_STRUCT_DOF], e[DTM_STRUCT_DOF], sc = dtm_eig_sym_tridiagonalize(n, a, d, e);
  return sc == 0 || sc != sc ? sc : sc * top(n, d, e);
}
