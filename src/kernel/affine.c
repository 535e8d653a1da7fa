/* The element matrices of straight-sided second-order simplices (tri6,
 * tet10) from reference tensors, without quadrature per element. When
 * every mid-edge node is at the middle of its edge, the isoparametric map
 * is the affine map of the corners: J is constant, g_a = J^-T dN_a, and
 * with the full rule's points and weights (w_k, xi_k) the stiffness the
 * generic path sums point by point is a contraction of one reference
 * tensor per type,
 *   R_ab[p][q] = sum_k w_k dN_a/dxi_p(xi_k) dN_b/dxi_q(xi_k),
 *   A_ab = J^-T R_ab J^-1,  integral g_ai g_bj = det J A_ab[i][j],
 * so K_(ai)(bj) = det J (lam A_ij + mu A_ji + mu delta_ij tr A) and the
 * Laplacian K_ab = det J tr A_ab. The HRZ masses are fixed fractions of
 * the measure: m_a = det J (sum_k w_k) f_a with f_a = D_a / sum_b D_b,
 * D_a = sum_k w_k N_a(xi_k)^2 (tri6: 3/57 and 16/57; tet10: 1/36 and
 * 4/27). The tensors are built once per type from the rule's table
 * (dtm_ref_rule_table), so they are the generic path's own sums; the
 * per-element work drops from nq points x (nn d)^2 / 2 products to
 * nn^2 / 2 small 3x3 contractions (tet10: 14 x 465 to 55 x 54).
 *
 * The shortcut applies only where it gives the generic path's numbers to
 * 1e-12 relative (tests/t521 compares them on random shapes): every
 * mid-edge node within AFFINE_TOL of its edge's length from the middle
 * (rounding of Gmsh's midpoints is ~1e-16 of the coordinates), and det J
 * clear of the validity threshold of map.c (32 eps times the Hadamard
 * bound) by a factor 1000, so that no element the generic path would
 * refuse passes here. Anything else returns 0 and the caller takes the
 * generic path. */
#if defined(__GNUC__) && !defined(__clang__)
/* Let GCC vectorise the loops with a varying trip count (axpy updates of
 * the element matrices): -O2's very-cheap cost model leaves them scalar.
 * Lanes are independent, so every sum is rounded as before. */
#pragma GCC optimize("vect-cost-model=dynamic")
#endif
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdlib.h>

#include "kernel-impl.h"
#include "assemble-impl.h"

#define AFFINE_TOL 1e-14 /* relative mid-node offset below which the map is taken as affine */
#define MAXN 10          /* nodes of the largest type served (tet10) */

typedef struct {
  double R[MAXN][MAXN][3][3]; /* reference tensor R_ab[p][q] */
  double f[MAXN];             /* HRZ mass fractions */
  double wsum;                /* sum of the rule's weights: the reference measure */
} affine_ref;

static const affine_ref *refs[2]; /* tri6, tet10 */
static pthread_mutex_t building = PTHREAD_MUTEX_INITIALIZER;

static affine_ref *build(int type, int nn) {
  const dtm_ref_table *t = dtm_ref_rule_table(type, 0);
  affine_ref *r = t ? calloc(1, sizeof *r) : NULL;
  double D[MAXN] = {0}, sum = 0;
  if (!r) return NULL;
  for (int k = 0; k < t->q.n; k++) {
    double w = t->q.w[k];
    r->wsum += w;
    for (int a = 0; a < nn; a++) {
      D[a] += w * t->N[k][a] * t->N[k][a];
      for (int b = 0; b < nn; b++)
        for (int p = 0; p < 3; p++)
          for (int q = 0; q < 3; q++) r->R[a][b][p][q] += w * t->dN[k][a][p] * t->dN[k][b][q];
    }
  }
  for (int a = 0; a < nn; a++) sum += D[a];
  for (int a = 0; a < nn; a++) r->f[a] = D[a] / sum;
  return r;
}

static const affine_ref *reference(int type, int nn) {
  int i = type == DTM_TET10;
  const affine_ref *r = __atomic_load_n(&refs[i], __ATOMIC_ACQUIRE);
  if (r) return r;
  pthread_mutex_lock(&building);
  r = refs[i];
  if (!r) r = build(type, nn), __atomic_store_n(&refs[i], r, __ATOMIC_RELEASE);
  pthread_mutex_unlock(&building);
  return r;
}

static double dist(const double *a, const double *b) {
  double s = 0;
  for (int i = 0; i < 3; i++) s += (a[i] - b[i]) * (a[i] - b[i]);
  return sqrt(s);
}

/* 1 when every mid-edge node is within AFFINE_TOL of its edge's middle. */
static int affine(int type, int nn, const double (*xl)[3]) {
  const dtm_topology *t = dtm_elem_topology(type);
  int nc = nn - t->nedge;
  for (int k = 0; k < t->nedge; k++) {
    const double *p = xl[t->edge[k][0]], *q = xl[t->edge[k][1]];
    double mid[3] = {0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
    if (!(dist(xl[nc + k], mid) <= AFFINE_TOL * dist(p, q))) return 0;
  }
  return 1;
}

int dtm_affine_frame(int type, int d, int nn, const double (*xl)[3], double *dj, double Ji[3][3]) {
  if ((type != DTM_TET10 && type != DTM_TRI6) || !affine(type, nn, xl) || !reference(type, nn)) return 0;
  double J[3][3] = {{0}};
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) J[i][j] = xl[j + 1][i] - xl[0][i]; /* corner j + 1 at xi_j = 1 */
  *dj = dtm_mat_det(d, (const double(*)[3])J);
  if (!(*dj > 1000 * 32 * DBL_EPSILON * dtm_mat_hadamard(d, (const double(*)[3])J)) || !isfinite(*dj)) return 0;
  dtm_mat_inverse(d, (const double(*)[3])J, *dj, Ji);
  return 1;
}

int dtm_affine_matrices(int type, int d, int nn, const double (*xl)[3], const dtm_elastic_moduli *m, double *K,
                        double *mass) {
  double dj, Ji[3][3];
  if (!dtm_affine_frame(type, d, nn, xl, &dj, Ji)) return 0;
  const affine_ref *r = reference(type, nn);
  int n = m ? nn * d : nn;
  double lam = m ? dj * (d == 1 ? m->modulus : m->lam) : 0, mu = m ? dj * (d == 1 ? 0 : m->mu) : 0;
  for (int a = 0; a < nn; a++) {
    mass[a] = dj * r->wsum * r->f[a];
    for (int b = a; b < nn; b++) {
      double T[3][3] = {{0}}, A[3][3] = {{0}}; /* T = R_ab J^-1, A = J^-T T */
      for (int p = 0; p < d; p++)
        for (int q = 0; q < d; q++)
          for (int j = 0; j < d; j++) T[p][j] += r->R[a][b][p][q] * Ji[q][j];
      for (int i = 0; i < d; i++)
        for (int p = 0; p < d; p++)
          for (int j = 0; j < d; j++) A[i][j] += Ji[p][i] * T[p][j];
      double tr = A[0][0] + A[1][1] + A[2][2];
      if (!m) {
        K[a * n + b] = K[b * n + a] = dj * tr;
        continue;
      }
      for (int i = 0; i < d; i++)
        for (int j = 0; j < d; j++) {
          double v = lam * A[i][j] + mu * A[j][i] + (i == j ? mu * tr : 0);
          K[(a * d + i) * n + b * d + j] = K[(b * d + j) * n + a * d + i] = v;
        }
    }
  }
  return 1;
}

/* ---- tet10 elastic matrices four at a time ----
 * dtm_affine_matrices' elastic tet10 branch on the lanes of a vector of four
 * doubles: lane l holds element l's J^-1 and moduli, and every operation is
 * the scalar one lane by lane in the same order (the same bits). */
typedef dtm_v4d v4d;
typedef long long v4l __attribute__((vector_size(32)));

/* Block (a, b) of the four lanes: A = J^-T R_ab J^-1 (T = R_ab J^-1 first)
 * and its trace, in dtm_affine_matrices' order. */
static inline __attribute__((always_inline)) void block4(const affine_ref *r, int a, int b, const v4d (*Ji)[3],
                                                         v4d A[3][3], v4d *tr) {
  const v4d zero = {0, 0, 0, 0};
  v4d T[3][3];
  for (int p = 0; p < 3; p++)
    for (int j = 0; j < 3; j++) T[p][j] = A[p][j] = zero;
  for (int p = 0; p < 3; p++)
    for (int q = 0; q < 3; q++)
      for (int j = 0; j < 3; j++) T[p][j] += r->R[a][b][p][q] * Ji[q][j];
  for (int i = 0; i < 3; i++)
    for (int p = 0; p < 3; p++)
      for (int j = 0; j < 3; j++) A[i][j] += Ji[p][i] * T[p][j];
  *tr = A[0][0] + A[1][1] + A[2][2];
}

static inline __attribute__((always_inline)) void elastic4(const affine_ref *r, const v4d (*Ji)[3], const v4d *lm,
                                                           int count, double *const *K) {
  enum { NN = 10, D = 3, N = 30 };
  const v4d zero = {0, 0, 0, 0}, lam = lm[0], mu = lm[1];
  for (int a = 0; a < NN; a++)
    for (int b = a; b < NN; b++) {
      v4d A[3][3], tr;
      block4(r, a, b, Ji, A, &tr);
      for (int i = 0; i < D; i++)
        for (int j = 0; j < D; j++) {
          v4d v = lam * A[i][j] + mu * A[j][i] + (i == j ? mu * tr : zero);
          for (int l = 0; l < count; l++) K[l][(a * D + i) * N + b * D + j] = K[l][(b * D + j) * N + a * D + i] = v[l];
        }
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx"))) static void elastic4_avx(const affine_ref *r, const v4d (*Ji)[3], const v4d *lm,
                                                        int count, double *const *K) {
  elastic4(r, Ji, lm, count, K);
}
#endif

void dtm_affine_elastic_lanes(int count, const double *dj, const double (*Ji)[3][3], const dtm_elastic_moduli *const *m,
                              double *const *K, double *const *mass) {
  const affine_ref *r = reference(DTM_TET10, 10); /* built: dtm_affine_frame said so */
  v4d J4[3][3], lm[2];
  for (int l = 0; l < 4; l++) {
    int k = l < count ? l : 0; /* a short group repeats element 0 in the idle lanes */
    lm[0][l] = dj[k] * m[k]->lam, lm[1][l] = dj[k] * m[k]->mu;
    for (int q = 0; q < 3; q++)
      for (int j = 0; j < 3; j++) J4[q][j][l] = Ji[k][q][j];
  }
  for (int l = 0; l < count; l++)
    for (int a = 0; a < 10; a++) mass[l][a] = dj[l] * r->wsum * r->f[a];
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx")) {
    elastic4_avx(r, (const v4d(*)[3])J4, lm, count, K);
    return;
  }
#endif
  elastic4(r, (const v4d(*)[3])J4, lm, count, K);
}

/* ---- the same, straight into the eigenvalue solver's packed lanes ----
 * dtm_affine_elastic_lanes, then the mass scaling of generic.c
 * (K_ij r_i r_j with r = (rho m)^-1/2), then the largest |entry| and the
 * division by it (dtm_packed_divide) that dtm_eig_sym_max_tridiag_lanes
 * does, without the
 * 30 x 30 matrices between them: each block's lower triangle is scaled
 * as it is formed and stored in the packed rows. The values are those
 * the matrices held (their lower triangle: block (a, a) holds v_ij, i >=
 * j, the iteration that wrote it last in elastic4), so the bits are the
 * same. */
static inline __attribute__((always_inline)) void packed4(const affine_ref *r, const v4d (*Ji)[3], const v4d *lm,
                                                          const v4d *R, v4d *A, v4d *top, v4d *bad) {
  enum { NN = 10, D = 3 };
  const v4d zero = {0, 0, 0, 0}, lam = lm[0], mu = lm[1];
  v4d mx = zero, z = zero;
  for (int a = 0; a < NN; a++)
    for (int b = a; b < NN; b++) {
      v4d Am[3][3], tr;
      block4(r, a, b, Ji, Am, &tr);
      for (int i = 0; i < D; i++)
        for (int j = 0; j < D; j++) {
          if (a == b && i < j) continue; /* block (a, a): its lower triangle */
          int row = b * D + j, col = a * D + i;
          if (a == b) row = a * D + i, col = a * D + j;
          v4d v = lam * Am[i][j] + mu * Am[j][i] + (i == j ? mu * tr : zero);
          v *= R[row] * R[col];
          A[row * (row + 1) / 2 + col] = v;
          v4d av = (v4d)((v4l)v & ~(v4l)(v4d){-0.0, -0.0, -0.0, -0.0});
          v4l gt = av > mx;
          mx = (v4d)((gt & (v4l)av) | (~gt & (v4l)mx)), z += v * 0;
        }
    }
  *top = mx, *bad = z;
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx"))) static void packed4_avx(const affine_ref *r, const v4d (*Ji)[3], const v4d *lm,
                                                       const v4d *R, v4d *A, v4d *top, v4d *bad) {
  packed4(r, Ji, lm, R, A, top, bad);
}
#endif

/* Every packed entry times keep (1 / s of its lane), +0 where the lane is
 * not live (as dtm_eig_sym_max_tridiag_lanes packs such a lane). */
static inline __attribute__((always_inline)) void divide4(v4d *A, const v4d *keep, const v4l *live) {
  v4d k4 = *keep;
  v4l l4 = *live;
  for (int k = 0; k < 30 * 31 / 2; k++) A[k] = (v4d)((v4l)(A[k] * k4) & l4);
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx"))) static void divide4_avx(v4d *A, const v4d *keep, const v4l *live) {
  divide4(A, keep, live);
}
#endif

int dtm_affine_elastic_pack(const int *use, const double *dj, const double (*Ji)[3][3],
                            const dtm_elastic_moduli *const *m, dtm_v4d *A, double *top) {
  const affine_ref *r = reference(DTM_TET10, 10);
  v4d J4[3][3], lm[2], R[30], mx, bad;
  int first = 0;
  while (first < 4 && !use[first]) first++;
  if (first == 4) return 1;
  for (int l = 0; l < 4; l++) {
    int k = use[l] ? l : first; /* a lane not used repeats the first one used */
    lm[0][l] = dj[k] * m[k]->lam, lm[1][l] = dj[k] * m[k]->mu;
    for (int q = 0; q < 3; q++)
      for (int j = 0; j < 3; j++) J4[q][j][l] = Ji[k][q][j];
    for (int a = 0; a < 10; a++) {
      double mass = dj[k] * r->wsum * r->f[a]; /* as dtm_affine_elastic_lanes, then rho */
      mass *= m[k]->rho;
      if (!(mass > 0)) return 0; /* generic.c's path names the element */
      for (int i = 0; i < 3; i++) R[a * 3 + i][l] = 1 / sqrt(mass);
    }
  }
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx"))
    packed4_avx(r, (const v4d(*)[3])J4, lm, R, A, &mx, &bad);
  else
#endif
    packed4(r, (const v4d(*)[3])J4, lm, R, A, &mx, &bad);
  for (int l = 0; l < 4; l++)
    if (use[l]) top[l] = bad[l] == 0 ? mx[l] : NAN; /* dtm_eig_sym_max_tridiag_lanes' max_abs */
  return 1;
}

void dtm_packed_divide(int count, dtm_v4d *A, double *s) {
  v4d keep;
  v4l live;
  for (int l = 0; l < 4; l++) {
    if (l >= count) s[l] = 0;
    live[l] = l < count && s[l] > 0 ? -1 : 0;
    keep[l] = live[l] ? 1 / s[l] : 0;
  }
#if defined(__x86_64__) && defined(__GNUC__)
  if (__builtin_cpu_supports("avx"))
    divide4_avx(A, &keep, &live);
  else
#endif
    divide4(A, &keep, &live);
}

int dtm_affine_lumped(int type, int d, int nn, const double (*xl)[3], double *m, double *vol) {
  double dj, Ji[3][3];
  if (!dtm_affine_frame(type, d, nn, xl, &dj, Ji)) return 0;
  const affine_ref *r = reference(type, nn);
  for (int a = 0; a < nn; a++) m[a] = dj * r->wsum * r->f[a];
  *vol = dj * r->wsum;
  return 1;
}

int dtm_affine_scaled(int type, int d, int nn, const double (*xl)[3], double *scaled) {
  if ((type != DTM_TET10 && type != DTM_TRI6) || !affine(type, nn, xl)) return 0;
  double J[3][3] = {{0}};
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) J[i][j] = xl[j + 1][i] - xl[0][i];
  double had = dtm_mat_hadamard(d, (const double(*)[3])J), dj = dtm_mat_det(d, (const double(*)[3])J);
  *scaled = had > 0 ? dj / had : 0.0;
  return 1;
}

int dtm_elem_affine(int type, const double *x) {
  double xl[DTM_K_NODES][3], dj, Ji[3][3];
  int d = 0, nn = 0;
  if (type != DTM_TET10 || dtm_elem_info(type, &d, &nn) || dtm_elem_local(type, x, xl)) return 0;
  return dtm_affine_frame(type, d, nn, (const double(*)[3])xl, &dj, Ji);
}
