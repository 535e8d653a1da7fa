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
#if defined(__GNUC__) && !defined(__clang__)
/* Let GCC vectorise the loops with a varying trip count (axpy updates of
 * the element matrices): -O2's very-cheap cost model leaves them scalar.
 * Lanes are independent, so every sum is rounded as before. */
#pragma GCC optimize("vect-cost-model=dynamic")
#endif
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

/* At x: 1 when every pivot of the LDL^T factors of x I - T is positive
 * (x above every eigenvalue), with *g = p'/p and *h = (p'/p)^2 - p''/p of
 * p(x) = det(x I - T); else 0. */
static int laguerre_sums(int n, const double *d, const double *e2, double x, double *g, double *h) {
  double p = 1, dp = 0, ddp = 0;
  *g = *h = 0;
  for (int i = 0; i < n; i++) {
    double r = i ? e2[i - 1] / p : 0, s = i ? r / p : 0;
    double q = x - d[i] - r, dq = 1 + s * dp, ddq = i ? s * (ddp - 2 * dp * dp / p) : 0;
    if (!(q > 0)) return 0;
    double u = dq / q;
    *g += u, *h += u * u - ddq / q;
    p = q, dp = dq, ddp = ddq;
  }
  return 1;
}

/* The largest eigenvalue of the tridiagonal by Laguerre's iteration on
 * its characteristic polynomial p(x) = det(x I - T), from the Gershgorin
 * bound down. p has only real roots, so from above the largest one each
 * step stays above it and converges monotonically (cubically to a simple
 * root); every iterate is checked by the LDL^T pivots of x I - T, all
 * positive exactly when x is above every eigenvalue (Sturm), and that
 * makes the last checked iterate an upper bound. The pivots d_i, their
 * derivatives d_i' and d_i'' in x give p'/p = sum d_i'/d_i and
 * (p'/p)^2 - p''/p = sum (d_i'/d_i)^2 - d_i''/d_i. A few steps replace the
 * ~55 bisection steps of tri_max (each a chain of n divisions); a root
 * that does not settle within 16 steps (a cluster at the top) is finished
 * by bisection between the largest diagonal entry (a lower bound) and the
 * last upper bound. Against tri_max: the same eigenvalue within a few eps
 * of |T| (tests/t521). */
/* tri_max_fast's start: the Gershgorin bounds *lo, *hi, the largest
 * diagonal entry *dmax and e2[i] = e[i]^2. */
static void gershgorin(int n, const double *d, const double *e, double *lo, double *hi, double *dmax, double *e2) {
  *lo = INFINITY, *hi = -INFINITY, *dmax = -INFINITY;
  for (int i = 0; i < n; i++) {
    double r = (i ? fabs(e[i - 1]) : 0) + (i + 1 < n ? fabs(e[i]) : 0);
    *hi = fmax(*hi, d[i] + r), *dmax = fmax(*dmax, d[i]);
    *lo = fmin(*lo, d[i] - r);
  }
  for (int i = 0; i + 1 < n; i++) e2[i] = e[i] * e[i];
}

/* tri_max_fast's end, when Laguerre's steps did not settle: bisection
 * between the largest diagonal entry (or the last iterate x) and the last
 * upper bound. */
static double bisect_tail(int n, const double *d, const double *e2, double x, double dmax, double above, double tol) {
  double lo = fmin(dmax, x), hi = above;
  for (int it = 0; it < 200 && hi - lo > 2 * tol; it++) {
    double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    if (below(n, d, e2, mid) == n)
      hi = mid;
    else
      lo = mid;
  }
  return 0.5 * (lo + hi);
}

/* One of Laguerre's steps from x (p'/p = g, (p'/p)^2 - p''/p = h), x above
 * the top: 1 with the result in *out when it is settled, else 0 with the
 * next iterate in *x (and *above = the old x). */
static int laguerre_step(int n, double g, double h, double tol, double dmax, double *x, double *above, double *out) {
  *above = *x;
  double disc = (n - 1) * (n * h - g * g);
  double step = n / (g + sqrt(disc > 0 ? disc : 0));
  if (!(step > tol)) return *out = *above, 1;
  *x = fmax(*x - step, dmax);
  if (*x >= *above) return *out = *above, 1;
  return 0;
}

static double tri_max_fast(int n, const double *d, const double *e) {
  double lo, hi, dmax, e2[DTM_K_DOF], out;
  gershgorin(n, d, e, &lo, &hi, &dmax, e2);
  double tol = 2 * DBL_EPSILON * fmax(fabs(lo), fabs(hi)), x = hi, above = hi;
  for (int it = 0; it < 16; it++) {
    double g, h;
    if (!laguerre_sums(n, d, e2, x, &g, &h)) {
      /* x is not above the top, which lies in [x, above]: rounding in the
       * last, converged step, as a rule; then x + 4 tol is above it */
      if (x + 4 * tol < above && laguerre_sums(n, d, e2, x + 4 * tol, &g, &h)) return x + 4 * tol;
      break;
    }
    if (laguerre_step(n, g, h, tol, dmax, &x, &above, &out)) return out;
  }
  return bisect_tail(n, d, e2, x, dmax, above, tol);
}

/* Reduce a (scaled by its largest entry s, returned) to the tridiagonal
 * (d, e); 0 for the zero matrix, NaN with a non-finite entry. divide:
 * scale by dividing by s, as before (bitwise the old reduction), else by
 * multiplying by 1/s (faster; rounding differs by an ulp). */
static double reduce(int n, double *a, double *d, double *e, int divide) {
  double s = 0;
  for (int i = 0; i < n * n; i++) {
    if (!isfinite(a[i])) return NAN; /* a NaN would not compare */
    s = fabs(a[i]) > s ? fabs(a[i]) : s;
  }
  if (s == 0) return 0;
  double r = 1 / s;
  if (divide)
    for (int i = 0; i < n * n; i++) a[i] /= s;
  else
    for (int i = 0; i < n * n; i++) a[i] *= r;
  for (int k = 0; k + 2 < n; k++) e[k] = reflect(n, a, k);
  if (n >= 2) e[n - 2] = a[(n - 1) * n + n - 2];
  for (int i = 0; i < n; i++) d[i] = a[i * n + i];
  return s;
}

double dtm_eig_sym_max_tridiag(int n, double *a) {
  double d[DTM_K_DOF], e[DTM_K_DOF], s = reduce(n, a, d, e, 0);
  return s == 0 || s != s ? s : s * tri_max_fast(n, d, e);
}

double dtm_eig_sym_tridiagonalize(int n, double *a, double *d, double *e) { return reduce(n, a, d, e, 1); }

double dtm_eig_sym_max_tridiag_bisect(int n, double *a) {
  double d[DTM_K_DOF], e[DTM_K_DOF], s = reduce(n, a, d, e, 1);
  return s == 0 || s != s ? s : s * tri_max(n, d, e);
}

/* ---- four matrices at once, one per vector lane ----
 * The same reduction as reduce() with divide = 0, written on vectors of
 * four doubles (GCC's vector extension, as src/spectral/operator.c): lane
 * l of every vector belongs to matrix l, and every operation is the
 * scalar one applied lane by lane in the same order, so each lane's
 * tridiagonal is bitwise the one reduce() gives its matrix alone. Only
 * the lower triangle is kept, packed by rows (row r starts at r (r + 1) /
 * 2), which holds n = 81 in 104 kB. The one branch of reflect (a column
 * already zero) becomes a per-lane choice: such a lane gets beta = 0,
 * which leaves its trailing block unchanged, as the early return does.
 * Laguerre's search stays scalar per lane: O(n) per step against the
 * reduction's 4 n^3 / 3. */
typedef dtm_v4d v4d;
#define LANES 4

static v4d *packed_row(v4d *a, int r) { return a + r * (r + 1) / 2; }

/* reflect() on the four lanes of the packed a (n x n): the new subdiagonal
 * entries into e_k[4]. */
#define INLINE static inline __attribute__((always_inline))

INLINE void reflect4(int n, v4d *a, int k, double e_k[LANES]) {
  v4d v[DTM_K_DOF], p[DTM_K_DOF], xx = {0, 0, 0, 0}, K = {0, 0, 0, 0};
  int m = n - k - 1;
  v[0] = packed_row(a, k + 1)[k];
  for (int i = 1; i < m; i++) v[i] = packed_row(a, k + 1 + i)[k], xx += v[i] * v[i];
  xx += v[0] * v[0];
  v4d alpha, beta;
  for (int l = 0; l < LANES; l++) alpha[l] = v[0][l] > 0 ? -sqrt(xx[l]) : sqrt(xx[l]);
  v4d vv = xx - v[0] * v[0] + (v[0] - alpha) * (v[0] - alpha);
  v[0] -= alpha;
  for (int l = 0; l < LANES; l++) {
    int live = vv[l] > 0; /* else the column is already zero: no reflection in this lane */
    e_k[l] = live ? alpha[l] : v[0][l] + alpha[l];
    beta[l] = live ? 2 / vv[l] : 0;
  }
  for (int i = 0; i < m; i++) p[i] = (v4d){0, 0, 0, 0};
  for (int i = 0; i < m; i++) {
    const v4d *row = packed_row(a, k + 1 + i) + k + 1;
    v4d s = {0, 0, 0, 0};
    for (int j = 0; j < i; j++) s += row[j] * v[j], p[j] += row[j] * v[i];
    p[i] += s + row[i] * v[i];
  }
  for (int i = 0; i < m; i++) p[i] *= beta, K += v[i] * p[i];
  K *= beta / 2;
  for (int i = 0; i < m; i++) p[i] -= K * v[i];
  for (int i = 0; i < m; i++) {
    v4d *row = packed_row(a, k + 1 + i) + k + 1;
    for (int j = 0; j <= i; j++) row[j] -= v[i] * p[j] + p[i] * v[j];
  }
}

/* The reflections of the four lanes, subdiagonals into e[l][k]. */
INLINE void reflections4(int n, v4d *A, double (*e)[DTM_K_DOF]) {
  double ek[LANES];
  for (int k = 0; k + 2 < n; k++) {
    reflect4(n, A, k, ek);
    for (int l = 0; l < LANES; l++) e[l][k] = ek[l];
  }
}

/* The build targets the x86-64 baseline (SSE2: a vector of four doubles is
 * two instructions); where the processor has AVX the same code compiled
 * for it does each in one. AVX has no fused multiply-add (and C11 mode does
 * not contract), so both give the same bits. */
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx"))) static void reflections4_avx(int n, v4d *A, double (*e)[DTM_K_DOF]) {
  reflections4(n, A, e);
}
#endif

static void reduce4(int n, v4d *A, double (*e)[DTM_K_DOF]) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx")) {
    reflections4_avx(n, A, e);
    return;
  }
#endif
  reflections4(n, A, e);
}

typedef long long v4l __attribute__((vector_size(32)));

/* laguerre_sums at x[l] on the tridiagonal of every lane (D[i], E2[i]
 * holding the lanes' d[i], e2[i]): g, h per lane, ok[l] = 0 where a pivot
 * is not positive (that lane's g, h are then meaningless, as laguerre_sums
 * returns 0 there). Lane by lane the scalar operations in their order. */
INLINE void laguerre_sums4(int n, const v4d *D, const v4d *E2, const double x[LANES], double g[LANES], double h[LANES],
                           int ok[LANES]) {
  const v4d zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
  v4d X = {x[0], x[1], x[2], x[3]}, p = one, dp = zero, ddp = zero, G = zero, H = zero;
  v4l good = {-1, -1, -1, -1};
  for (int i = 0; i < n; i++) {
    v4d r = i ? E2[i - 1] / p : zero, sp = i ? r / p : zero;
    v4d q = X - D[i] - r, dq = one + sp * dp, ddq = i ? sp * (ddp - 2 * dp * dp / p) : zero;
    good &= q > zero;
    v4d u = dq / q;
    G += u, H += u * u - ddq / q;
    p = q, dp = dq, ddp = ddq;
  }
  for (int l = 0; l < LANES; l++) g[l] = G[l], h[l] = H[l], ok[l] = good[l] != 0;
}

/* laguerre_sums4 compiled for AVX where the processor has it, as
 * reflections4: in SSE2 its eleven vectors of four do not fit the sixteen
 * registers and spill to the stack at every pivot. Divisions and
 * subtractions round alike in both. */
#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx"))) static void laguerre_sums4_avx(int n, const v4d *D, const v4d *E2, const double x[LANES],
                                                              double g[LANES], double h[LANES], int ok[LANES]) {
  laguerre_sums4(n, D, E2, x, g, h, ok);
}
#endif

static void laguerre4(int n, const v4d *D, const v4d *E2, const double x[LANES], double g[LANES], double h[LANES],
                      int ok[LANES]) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx")) {
    laguerre_sums4_avx(n, D, E2, x, g, h, ok);
    return;
  }
#endif
  laguerre_sums4(n, D, E2, x, g, h, ok);
}

/* tri_max_fast of the live lanes of (d, e), their Laguerre sums four at a
 * time (a chain of divisions each: four chains in flight instead of one);
 * every lane takes the scalar steps and ends as tri_max_fast does. */
static void tri_max_fast4(int n, double (*d)[DTM_K_DOF], double (*e)[DTM_K_DOF], const int *live, double *out) {
  v4d D[DTM_K_DOF], E2[DTM_K_DOF];
  double e2[LANES][DTM_K_DOF], lo, hi, dmax[LANES], tol[LANES], x[LANES], above[LANES], g[LANES], h[LANES];
  int state[LANES], ok[LANES], going = 0; /* state: 0 Laguerre, 1 done, 2 bisection */
  for (int l = 0; l < LANES; l++) {
    state[l] = live[l] ? 0 : 1, going += live[l];
    if (!live[l]) { /* a harmless tridiagonal: zeros, x = 1 */
      for (int i = 0; i < n; i++) d[l][i] = e2[l][i] = 0;
      x[l] = 1;
      continue;
    }
    gershgorin(n, d[l], e[l], &lo, &hi, &dmax[l], e2[l]);
    tol[l] = 2 * DBL_EPSILON * fmax(fabs(lo), fabs(hi)), x[l] = above[l] = hi;
  }
  for (int i = 0; i < n; i++)
    for (int l = 0; l < LANES; l++) D[i][l] = d[l][i], E2[i][l] = i + 1 < n ? e2[l][i] : 0;
  for (int it = 0; it < 16 && going; it++) {
    laguerre4(n, D, E2, x, g, h, ok);
    for (int l = 0; l < LANES; l++) {
      if (state[l]) continue;
      if (!ok[l]) {
        double t = x[l] + 4 * tol[l], gg, hh;
        state[l] = t < above[l] && laguerre_sums(n, d[l], e2[l], t, &gg, &hh) ? (out[l] = t, 1) : 2;
      } else if (laguerre_step(n, g[l], h[l], tol[l], dmax[l], &x[l], &above[l], &out[l]))
        state[l] = 1;
      going -= state[l] != 0;
    }
  }
  for (int l = 0; l < LANES; l++)
    if (state[l] != 1) out[l] = bisect_tail(n, d[l], e2[l], x[l], dmax[l], above[l], tol[l]);
}

/* The largest |entry| of x[0..len), NaN if one is not finite (a NaN would
 * not compare). In locals, not in the caller's array: a running maximum
 * kept in memory waits on a store and a load at every entry, which took
 * more time than the reduction it scales. The maximum is exact in any
 * order, so the loop may run in vector lanes. */
static double max_abs(int len, const double *x) {
  /* four independent maxima m0..m3, not one chain; z: 0 while every entry
   * is finite, else NaN. Plain scalars: GCC keeps a small array of them in
   * memory. */
  double m0 = 0, m1 = 0, m2 = 0, m3 = 0, z0 = 0, z1 = 0, z2 = 0, z3 = 0;
  int i = 0;
  for (; i + 4 <= len; i += 4) {
    double t0 = fabs(x[i]), t1 = fabs(x[i + 1]), t2 = fabs(x[i + 2]), t3 = fabs(x[i + 3]);
    m0 = t0 > m0 ? t0 : m0, m1 = t1 > m1 ? t1 : m1, m2 = t2 > m2 ? t2 : m2, m3 = t3 > m3 ? t3 : m3;
    z0 += x[i] * 0, z1 += x[i + 1] * 0, z2 += x[i + 2] * 0, z3 += x[i + 3] * 0;
  }
  for (; i < len; i++) {
    double t = fabs(x[i]);
    m0 = t > m0 ? t : m0, z0 += x[i] * 0;
  }
  double top = fmax(fmax(m0, m1), fmax(m2, m3));
  return z0 + z1 + z2 + z3 == 0 ? top : NAN;
}

/* The lower triangles of the live lanes' a[l], times r[l], into the packed
 * A; +0 in the other lanes (a lane without a matrix, or a zero or NaN
 * one). A whole vector at a time: each lane's product, then a mask that
 * clears the lanes that are not live (reading a[0] there, so no pointer
 * is needed). */
static void pack4(int n, double *const a[], const int live[LANES], const double r[LANES], v4d *A) {
  const double *src[LANES];
  v4l keep;
  v4d R;
  for (int l = 0; l < LANES; l++) src[l] = live[l] ? a[l] : a[0], keep[l] = live[l] ? -1 : 0, R[l] = r[l];
  for (int i = 0; i < n; i++) {
    v4d *row = packed_row(A, i);
    for (int j = 0; j <= i; j++) {
      int k = i * n + j;
      v4d x = {src[0][k], src[1][k], src[2][k], src[3][k]};
      row[j] = (v4d)((v4l)(x * R) & keep);
    }
  }
}

void dtm_eig_sym_max_tridiag_packed(int n, dtm_v4d *A, const double s[4], int count, double *lambda) {
  double d[LANES][DTM_K_DOF], e[LANES][DTM_K_DOF], top[LANES];
  int live[LANES];
  for (int l = 0; l < LANES; l++) live[l] = l < count && s[l] > 0;
  reduce4(n, A, e);
  for (int l = 0; l < LANES; l++) {
    if (n >= 2) e[l][n - 2] = packed_row(A, n - 1)[n - 2][l];
    for (int i = 0; i < n; i++) d[l][i] = packed_row(A, i)[i][l];
  }
  tri_max_fast4(n, d, e, live, top);
  for (int l = 0; l < count; l++) lambda[l] = live[l] ? s[l] * top[l] : s[l];
}

void dtm_eig_sym_max_tridiag_lanes(int n, double *const a[], int count, double *lambda) {
  v4d A[DTM_K_DOF * (DTM_K_DOF + 1) / 2];
  double s[LANES], r[LANES];
  int live[LANES];
  if (count <= 0) return;
  for (int l = 0; l < LANES; l++) {
    s[l] = l < count ? max_abs(n * n, a[l]) : 0;
    live[l] = l < count && s[l] > 0; /* else the answer is s: 0 or NaN */
    r[l] = live[l] ? 1 / s[l] : 0;   /* a lane without a matrix holds zeros: no reflection touches it */
  }
  pack4(n, a, live, r, A);
  dtm_eig_sym_max_tridiag_packed(n, A, s, count, lambda);
}
