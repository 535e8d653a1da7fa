/* The isoparametric map from the reference element to the element in its
 * own frame: Jacobian, its determinant, physical gradients of the shape
 * functions, and the validity check that rejects degenerate or inverted
 * elements. A Jacobian is taken as valid when det J > 32 eps times its
 * Hadamard bound (the product of its column lengths): below that the sign
 * of the determinant is not trustworthy in double precision, so the element
 * is flat to rounding. Slivers of any realistic flatness pass. The check
 * that refuses an element covers its quadrature points only: an element
 * whose Jacobian is positive there has well-defined element matrices even
 * when it is negative at a corner (dtm_kernel_shape, shape.c, classifies
 * those). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "kernel-impl.h"

/* J[i][j] = d x_i / d xi_j, i, j < d. The 3D case unrolled (the hot one:
 * every point of every solid), summed in the same order. */
static void jacobian(int d, int nn, const double (*xl)[3], const double (*dN)[3], double J[3][3]) {
  if (d == 3) {
    double s[3][3] = {{0}};
    for (int a = 0; a < nn; a++)
#pragma GCC unroll 3
      for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) s[i][j] += xl[a][i] * dN[a][j];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) J[i][j] = s[i][j];
    return;
  }
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) {
      J[i][j] = 0;
      for (int a = 0; a < nn; a++) J[i][j] += xl[a][i] * dN[a][j];
    }
}

/* g[a][i] = sum_j K[j][i] dN[a][j] (K = J^-1), 0 for i >= d; 3D unrolled,
 * summed in the same order. */
static void gradients(int d, int nn, const double (*K)[3], const double (*dN)[3], double (*g)[3]) {
  if (d == 3) {
    for (int a = 0; a < nn; a++)
#pragma GCC unroll 3
      for (int i = 0; i < 3; i++) g[a][i] = 0 + K[0][i] * dN[a][0] + K[1][i] * dN[a][1] + K[2][i] * dN[a][2];
    return;
  }
  for (int a = 0; a < nn; a++)
    for (int i = 0; i < 3; i++) {
      g[a][i] = 0;
      for (int j = 0; j < d && i < d; j++) g[a][i] += K[j][i] * dN[a][j];
    }
}

double dtm_map_eval_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double wq, double (*g)[3],
                       double *dv) {
  double J[3][3], K[3][3];
  jacobian(d, nn, xl, dN, J);
  double dj = dtm_mat_det(d, (const double(*)[3])J);
  dtm_mat_inverse(d, (const double(*)[3])J, dj, K);
  gradients(d, nn, (const double(*)[3])K, dN, g);
  *dv = dj * wq;
  return dj;
}

double dtm_map_dv_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double wq, double *dv) {
  double J[3][3];
  jacobian(d, nn, xl, dN, J);
  double dj = dtm_mat_det(d, (const double(*)[3])J);
  *dv = dj * wq;
  return dj;
}

double dtm_map_eval(int type, int d, int nn, const double (*xl)[3], const double p[3], double wq, double *N,
                    double (*g)[3], double *dv) {
  double dN[DTM_K_NODES][3];
  dtm_ref_eval(type, p, N, dN);
  return dtm_map_eval_dn(d, nn, xl, (const double(*)[3])dN, wq, g, dv);
}

double dtm_map_det_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double *hadamard) {
  double J[3][3];
  jacobian(d, nn, xl, dN, J);
  *hadamard = dtm_mat_hadamard(d, (const double(*)[3])J);
  return dtm_mat_det(d, (const double(*)[3])J);
}

double dtm_map_det(int type, int d, int nn, const double (*xl)[3], const double p[3], double *hadamard) {
  double N[DTM_K_NODES], dN[DTM_K_NODES][3];
  dtm_ref_eval(type, p, N, dN);
  return dtm_map_det_dn(d, nn, xl, (const double(*)[3])dN, hadamard);
}

/* 0 when det J with reference gradients dN is safely positive. */
static int valid_dn(int d, int nn, const double (*xl)[3], const double (*dN)[3], double *dj) {
  double had;
  *dj = dtm_map_det_dn(d, nn, xl, dN, &had);
  return *dj > 32 * DBL_EPSILON * had && isfinite(*dj) ? 0 : -1;
}

int dtm_map_first_bad(int type, int d, int nn, const double (*xl)[3], const dtm_qrule *q, double *dj) {
  double N[DTM_K_NODES], dN[DTM_K_NODES][3];
  for (int k = 0; k < q->n; k++) {
    dtm_ref_eval(type, q->p[k], N, dN);
    if (valid_dn(d, nn, xl, (const double(*)[3])dN, dj)) return k;
  }
  return -1;
}

int dtm_map_first_bad_table(int d, int nn, const double (*xl)[3], const dtm_ref_table *t, double *dj) {
  for (int k = 0; k < t->q.n; k++)
    if (valid_dn(d, nn, xl, (const double(*)[3])t->dN[k], dj)) return k;
  return -1;
}

int dtm_map_eval_valid(int d, int nn, const double (*xl)[3], const double (*dN)[3], double wq, double (*g)[3],
                       double *dv, double *dj) {
  double J[3][3], K[3][3];
  jacobian(d, nn, xl, dN, J);
  double had = dtm_mat_hadamard(d, (const double(*)[3])J);
  *dj = dtm_mat_det(d, (const double(*)[3])J);
  dtm_mat_inverse(d, (const double(*)[3])J, *dj, K);
  gradients(d, nn, (const double(*)[3])K, dN, g);
  *dv = *dj * wq;
  return *dj > 32 * DBL_EPSILON * had && isfinite(*dj) ? 0 : -1;
}

/* ---- four rule points at once (3D) ----
 * dtm_map_eval_dn at points k..k+3 of a table, lane l of each vector the
 * point k + l: every operation is the scalar path's (jacobian, dtm_mat_det,
 * dtm_mat_inverse, gradients for d = 3) on that lane, in the same order,
 * so g and dv are bitwise those four calls give. The Jacobian, its inverse
 * and the gradients are a few hundred flops of scalar code per point,
 * about a third of a curved element's level search: in lanes, a quarter of
 * the instructions. */
typedef dtm_v4d v4d;
/* The same vector at any double's address: a row of g need not be 32-byte
 * aligned. (memcpy of one was expanded as two 16-byte moves through the
 * stack.) */
typedef double v4du __attribute__((vector_size(32), aligned(8), may_alias));

/* The Jacobians J of the four points whose reference gradients are D
 * (lane by lane: a table's dN4) and det J (dtm_mat_det's expression) into
 * *dj. */
static inline __attribute__((always_inline)) void jacobian4(int nn, const double (*xl)[3], const v4d (*D)[3],
                                                            v4d J[3][3], v4d *dj) {
  v4d s[3][3]; /* in registers: constant indices once the loops are unrolled */
#pragma GCC unroll 3
  for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
    for (int j = 0; j < 3; j++) s[i][j] = (v4d){0, 0, 0, 0};
#pragma GCC unroll 10
  for (int a = 0; a < nn; a++)
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
      for (int j = 0; j < 3; j++) s[i][j] += xl[a][i] * D[a][j];
#pragma GCC unroll 3
  for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
    for (int j = 0; j < 3; j++) J[i][j] = s[i][j];
  *dj = J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) - J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
        J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

/* Entries e .. e + 3 of the four points' rows g[l] from four vectors x
 * (x[c] lane l: point l's entry e + c): a 4 x 4 transpose in registers and
 * four stores, instead of sixteen single stores through the stack. */
typedef long long v4l __attribute__((vector_size(32)));
#if defined(__clang__)
#define SHUFFLE(a, b, i, j, k, l) __builtin_shufflevector(a, b, i, j, k, l)
#else
#define SHUFFLE(a, b, i, j, k, l) __builtin_shuffle(a, b, (v4l){i, j, k, l})
#endif
static inline __attribute__((always_inline)) void store4(const v4d *x, double *const g[4], int e) {
  v4d t0 = SHUFFLE(x[0], x[1], 0, 4, 2, 6), t1 = SHUFFLE(x[0], x[1], 1, 5, 3, 7);
  v4d t2 = SHUFFLE(x[2], x[3], 0, 4, 2, 6), t3 = SHUFFLE(x[2], x[3], 1, 5, 3, 7);
  v4d r[4] = {SHUFFLE(t0, t2, 0, 1, 4, 5), SHUFFLE(t1, t3, 0, 1, 4, 5), SHUFFLE(t0, t2, 2, 3, 6, 7),
              SHUFFLE(t1, t3, 2, 3, 6, 7)};
#pragma GCC unroll 4
  for (int l = 0; l < 4; l++) *(v4du *)(g[l] + e) = r[l]; /* one unaligned vector store each */
}
#undef SHUFFLE

/* dtm_mat_hadamard lane by lane: the product of the column lengths. */
static inline __attribute__((always_inline)) void hadamard4(const v4d J[3][3], double *had) {
  v4d c[3];
#pragma GCC unroll 3
  for (int j = 0; j < 3; j++) c[j] = (v4d){0, 0, 0, 0};
#pragma GCC unroll 3
  for (int j = 0; j < 3; j++)
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) c[j] += J[i][j] * J[i][j];
  v4d h = {1, 1, 1, 1}; /* the scalar path's 1 * sqrt(c0) * sqrt(c1) * sqrt(c2), lane by lane */
#pragma GCC unroll 3
  for (int j = 0; j < 3; j++) {
    v4d r;
    for (int l = 0; l < 4; l++) r[l] = sqrt(c[j][l]); /* one vector square root (-fno-math-errno: CMakeLists.txt) */
    h *= r;
  }
  for (int l = 0; l < 4; l++) had[l] = h[l];
}

/* Whether each lane's det J passes dtm_map_eval_valid's test, dj > 32 eps
 * times the Hadamard bound had = sqrt(c0) sqrt(c1) sqrt(c2) (c_j the
 * squared column lengths of J, as hadamard4 sums them) and finite; the
 * first lane that does not, or -1. A lane with dj > 0, each c_j in
 * [2^-300, 2^300] (so that no product below under- or overflows) and
 * dj^2 > 4 (32 eps)^2 c0 c1 c2, dj^2 finite, passes that test too: the
 * factor 4 covers every rounding of both sides (at most 8 ulps). The
 * square roots are taken only when a lane does not clear it so: then the
 * test is dtm_map_eval_valid's, lane by lane, in the points' order. */
static inline __attribute__((always_inline)) int first_bad4(const v4d J[3][3], v4d dj) {
  const double k4 = 4 * (32 * DBL_EPSILON) * (32 * DBL_EPSILON), lo = 0x1p-300, hi = 0x1p300;
  v4d c[3];
#pragma GCC unroll 3
  for (int j = 0; j < 3; j++) c[j] = J[0][j] * J[0][j] + J[1][j] * J[1][j] + J[2][j] * J[2][j];
  v4d p = c[0] * c[1] * c[2], q = dj * dj;
  v4l clear = (dj > 0) & (q < INFINITY) & (q > k4 * p); /* lanes -1 where true */
#pragma GCC unroll 3
  for (int j = 0; j < 3; j++) clear &= (c[j] >= lo) & (c[j] <= hi);
  if ((clear[0] & clear[1] & clear[2] & clear[3]) == -1) return -1;
  double had[4], det[4];
  hadamard4(J, had);
  for (int l = 0; l < 4; l++) det[l] = dj[l];
  for (int l = 0; l < 4; l++)
    if (!(det[l] > 32 * DBL_EPSILON * had[l] && isfinite(det[l]))) return l;
  return -1;
}

/* The map at four points (see above) for elements of nn nodes. */
static inline __attribute__((always_inline)) int eval4_nodes(int nn, const double (*xl)[3], const v4d (*D)[3],
                                                             const double *wq, double *const g[4], double *dv,
                                                             double *det) {
  v4d J[3][3], K[3][3];
  v4d dj;
  jacobian4(nn, xl, D, J, &dj);
  int bad = first_bad4(J, dj);
  for (int l = 0; l < 4; l++) det[l] = dj[l];
#pragma GCC unroll 3
  for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
    for (int j = 0; j < 3; j++) {
      int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      K[i][j] = (J[i1][j1] * J[i2][j2] - J[i1][j2] * J[i2][j1]) / dj;
    }
  double *const rows[4] = {g[0], g[1], g[2], g[3]}; /* in registers: the stores below cannot change them */
  int e = 0;
#pragma GCC unroll 8
  for (; e + 4 <= 3 * nn; e += 4) { /* entries e .. e + 3, the gradients g_ai at 3 a + i, stored as they are formed */
    v4d x[4];
#pragma GCC unroll 4
    for (int c = 0; c < 4; c++) {
      int a = (e + c) / 3, i = (e + c) % 3;
      x[c] = 0 + K[0][i] * D[a][0] + K[1][i] * D[a][1] + K[2][i] * D[a][2];
    }
    store4(x, rows, e);
  }
  for (; e < 3 * nn; e++) {
    int a = e / 3, i = e % 3;
    v4d x = 0 + K[0][i] * D[a][0] + K[1][i] * D[a][1] + K[2][i] * D[a][2];
    for (int l = 0; l < 4; l++) rows[l][e] = x[l];
  }
  v4d w = {wq[0], wq[1], wq[2], wq[3]}, v = dj * w;
  for (int l = 0; l < 4; l++) dv[l] = v[l];
  return bad;
}

/* tet10 (the curved elements' search) with its node count a constant, so
 * that every loop unrolls. */
static DTM_KERNEL_AVX int eval4(int nn, const double (*xl)[3], const v4d (*D)[3], const double *wq, double *const g[4],
                                double *dv, double *det) {
  if (nn == 10) return eval4_nodes(10, xl, D, wq, g, dv, det);
  return eval4_nodes(nn, xl, D, wq, g, dv, det);
}

static DTM_KERNEL_AVX void dv4(int nn, const double (*xl)[3], const v4d (*D)[3], const double *wq, double *dv) {
  v4d J[3][3];
  v4d w = {wq[0], wq[1], wq[2], wq[3]}, dj;
  jacobian4(nn, xl, D, J, &dj);
  v4d v = dj * w;
  for (int l = 0; l < 4; l++) dv[l] = v[l];
}

void dtm_map_dv_dn4(int nn, const double (*xl)[3], const dtm_v4d (*D)[3], const double *wq, double *dv) {
  dv4(nn, xl, D, wq, dv);
}

static DTM_KERNEL_AVX void det4(int nn, const double (*xl)[3], const v4d (*D)[3], double *det, double *had) {
  v4d J[3][3], dj;
  jacobian4(nn, xl, D, J, &dj);
  hadamard4(J, had);
  for (int l = 0; l < 4; l++) det[l] = dj[l];
}

void dtm_map_det_dn4(int nn, const double (*xl)[3], const dtm_v4d (*D)[3], double *det, double *hadamard) {
  det4(nn, xl, D, det, hadamard);
}

int dtm_map_eval_valid4(int nn, const double (*xl)[3], const dtm_v4d (*D)[3], const double *wq, double *const g[4],
                        double *dv, double *dj) {
  return eval4(nn, xl, D, wq, g, dv, dj);
}
