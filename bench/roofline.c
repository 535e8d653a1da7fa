/* Benchmark (not a test): the roofline of the element kernels (issue 46),
 * one thread. For each kernel: the floating-point operations one element
 * costs, counted from the algorithm (below), the measured time per element
 * (the best of REPS passes over a few thousand random elements), and the
 * GFlop/s that makes, against the core's peak measured in the same run by
 * a plain dense kernel compiled with the same flags: C += A B on 30 x 30
 * matrices, 2 * 30^3 flops a product, its inner loop over contiguous
 * columns (the reach of this build's vector instructions), and the same
 * loop compiled for AVX (the instructions the lanes use where the
 * processor has them). Times are the thread's CPU time
 * (CLOCK_THREAD_CPUTIME_ID): on a shared machine the time given to other
 * processes is not counted (their use of the caches is).
 *
 * Kernels: tet4 (closed form, elastic_simplex.c), tet10 straight (reference
 * tensors, affine.c) and curved (its kept level's rule, assemble.c), hex8
 * (2 x 2 x 2 Gauss, assemble.c), each through dtm_kernel_elastic_lambda_at
 * (the path before the lanes) and, where the lanes take the type, through
 * dtm_kernel_elastic_lambda_lanes four at a time; the 30 x 30 eigenvalue
 * problem alone (dtm_eig_sym_max_tridiag, and four at a time); the tri3
 * and quad4 shells' scaled bound (dtm_kernel_shell_bounds with the scale:
 * frame, membrane, bending and shear stiffness, the certificate's
 * factorisations).
 *
 * Flop counts (an addition, multiplication, division or square root is one
 * flop; comparisons and copies are none), from the code:
 *  - the eigenvalue problem of n unknowns (generic.c, tridiag.c): the mass
 *    scaling 2 n^2 + 2 n, the scaling by the largest entry n^2, one
 *    Householder reflection of a trailing block of size m 4 m^2 + 10 m + 9
 *    (A v from the lower triangle 2 m (m - 1), the rank-2 update
 *    2 m (m + 1), the rest linear), m = n - 1 .. 2, the Gershgorin bounds
 *    5 n, and LAGUERRE steps of 17 n + 10 (an assumption: from the
 *    Gershgorin bound the iteration converges cubically in 3 to 5);
 *  - tet10 straight (affine.c): the affine check 6 x 25, the Jacobian, its
 *    determinant, Hadamard bound and inverse 79, per node pair (55) the two
 *    3 x 3 products 108, the trace 2 and the block 33, the masses 32;
 *  - a rule point of tet10 (assemble.c, map.c): the Jacobian 180, its
 *    checks and inverse 70, the gradients 180, the Gram update
 *    30 + 2 x 465, the masses 31; then the stiffness from the Gram tensor
 *    1,890 and the HRZ scaling 40; a level-n rule has n^3 points;
 *  - a rule point of hex8: the map 359, the stiffness update 64 x 72, the
 *    masses 16;
 *  - tet4 (simplex.c, elastic_simplex.c): the metric 115, the invariants
 *    and 3 Halley steps 125, the rest 10;
 *  - shells (shell.c), approximately: assembly as add_btdb's products at
 *    each point (tri3: membrane and bending once, shear at 3 points; quad4:
 *    2 x 2 points and shear at the centre) and the frame, then the
 *    certificate: the Cholesky factorisations (n^3 / 3 + n^2 / 2) of the
 *    translational (nn) and rotational (2 nn) blocks and the Schur
 *    complement between them, the membrane eigenvalue (tri3 closed form,
 *    quad4 8 x 8).
 *
 * Every kernel runs one pass over its elements in turn, for a number of
 * rounds, and keeps its best pass: on a loaded machine the best of many
 * short interleaved passes is the nearest to the unloaded speed, and every
 * kernel sees the same load. The lanes' rows are left out when the
 * library has no lanes (a build from before them, bench/roofline.py's
 * "before"). Prints the peak, then one line per kernel:
 *   ROW|kernel|path|flops per element|ns per element|GFlop/s
 *
 * Usage: bench_roofline [elements per kernel (default 400)] [rounds (15)] */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("vect-cost-model=dynamic") /* as the kernels' files */
#endif
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "dtmap/kernel.h"
#include "../src/kernel/assemble-impl.h"
#include "../src/kernel/kernel-impl.h"
#include "../src/kernel/structural.h"
#include "fixtures.h"

#define LAGUERRE 4
#define PN 30

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

static uint64_t seed = 0x9e3779b97f4a7c15u;
static double urand(void) { /* [-1, 1) */
  seed = seed * 6364136223846793005u + 1442695040888963407u;
  return (double)(seed >> 11) / 4503599627370496.0 - 1;
}

static volatile double sink;

/* ---- the dense reference ---- */
static void matmul(const double *restrict A, const double *restrict B, double *restrict C) {
  for (int i = 0; i < PN; i++)
    for (int k = 0; k < PN; k++) {
      double a = A[i * PN + k];
      for (int j = 0; j < PN; j++) C[i * PN + j] += a * B[k * PN + j];
    }
}

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
/* The same product compiled for AVX (the lanes' instructions), when the
 * processor has it: the roof of the lanes. */
__attribute__((target("avx"))) static void matmul_avx(const double *restrict A, const double *restrict B,
                                                      double *restrict C) {
  for (int i = 0; i < PN; i++)
    for (int k = 0; k < PN; k++) {
      double a = A[i * PN + k];
      for (int j = 0; j < PN; j++) C[i * PN + j] += a * B[k * PN + j];
    }
}
#define HAVE_AVX_PEAK 1
#endif

static double peak_of(void (*mm)(const double *restrict, const double *restrict, double *restrict)) {
  static double A[PN * PN], B[PN * PN], C[PN * PN];
  for (int i = 0; i < PN * PN; i++) A[i] = urand(), B[i] = urand() * 1e-3, C[i] = 0;
  int nprod = 400;
  double t0 = now();
  for (int p = 0; p < nprod; p++) mm(A, B, C);
  sink = C[7];
  return 2.0 * PN * PN * PN * nprod / (now() - t0) * 1e-9;
}

/* ---- flop counts ---- */
static double eig_flops(int n) {
  double f = 2.0 * n * n + 2 * n + 1.0 * n * n + 5 * n + LAGUERRE * (17.0 * n + 10);
  for (int m = 2; m <= n - 1; m++) f += 4.0 * m * m + 10 * m + 9;
  return f;
}
static double tet10_straight_flops(void) { return 150 + 79 + 55 * (108 + 2 + 33) + 32 + eig_flops(30); }
static double tet10_point_flops(void) { return 180 + 70 + 180 + 30 + 2 * 465 + 31; }
static double tet10_curved_flops(int points) { return points * tet10_point_flops() + 1890 + 40 + eig_flops(30); }
static double hex8_flops(void) { return 8 * (359 + 64 * 72 + 16) + eig_flops(24); }
static double chol(int n) { return n * n * n / 3.0 + n * n / 2.0; }
static double btdb(int nr, int nc) { return 2.0 * nr * nc * nr + nc * nr * (1 + 2.0 * nc); }
/* the certificate: A = T m - K and its factor (nt), the Schur complement
 * (nr columns, each two triangular solves, then nr^2 sums of nt products),
 * its factor (nr) */
static double certificate(int nt, int nr) {
  return nt * nt + chol(nt) + nr * 2.0 * nt * nt + nr * nr * (5.0 * nt + 1) + nr * nr + chol(nr);
}
static double tri3_shell_flops(void) { return 60 + 2 * btdb(3, 6) + 3 * btdb(2, 9) + certificate(3, 6) + 250; }
static double quad4_shell_flops(void) {
  return 60 + 4 * 2 * btdb(3, 8) + btdb(2, 12) + certificate(4, 8) + 8 * 8 * 2 + eig_flops(8);
}

/* ---- elements ---- */
/* A tet10 at scale h: tests/common's random element (the corners of the
 * unit tetrahedron moved by up to 15 %, the mid-edge nodes where the
 * corners' map puts them, moved by up to curve h, as tests/t521), moved
 * to positive coordinates and scaled. */
static void tet10(double h, double curve, double *x) {
  if (tu_random_element(DTM_TET10, curve, urand, x)) abort();
  for (int i = 0; i < 30; i++) x[i] = h * (x[i] + 2);
}

static void hex8(double h, double *x) {
  static const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                 {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int a = 0; a < 8; a++)
    for (int i = 0; i < 3; i++) x[3 * a + i] = h * (c[a][i] + 0.15 * urand() + 2);
}

static void flat(int nn, double h, double *x) { /* a shell element on a tilted plane */
  static const double c[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  static const double t[3][2] = {{0, 0}, {1, 0}, {0.4, 0.9}};
  for (int a = 0; a < nn; a++) {
    double u = h * ((nn == 4 ? c[a][0] : t[a][0]) + 0.15 * urand()),
           v = h * ((nn == 4 ? c[a][1] : t[a][1]) + 0.15 * urand());
    x[3 * a] = u + 1, x[3 * a + 1] = v + 2, x[3 * a + 2] = 0.3 * u + 0.2 * v + 3;
  }
}

/* ---- the kernels, each over the n elements of x (stride sx) ---- */
typedef struct {
  int type, n, sx, lanes;
  const double *x;
  const int *level;
  const dtm_elastic_moduli *m;
} job;

static void run_scalar(const job *j) {
  double l = 0, s = 0;
  for (int e = 0; e < j->n; e++) {
    if (dtm_kernel_elastic_lambda_at(j->type, j->m, j->x + (size_t)e * j->sx, j->level ? j->level[e] : 0, &l)) abort();
    s += l;
  }
  sink = s;
}

#ifdef DTM_KERNEL_LANES /* the lanes (issue 46); absent from a build before them */
static void run_lanes(const job *j) {
  double l[DTM_KERNEL_LANES], s = 0;
  const dtm_elastic_moduli *m[DTM_KERNEL_LANES] = {j->m, j->m, j->m, j->m};
  for (int e = 0; e + DTM_KERNEL_LANES <= j->n; e += DTM_KERNEL_LANES) {
    const double *x[DTM_KERNEL_LANES];
    int failed, lv[DTM_KERNEL_LANES];
    for (int k = 0; k < DTM_KERNEL_LANES; k++)
      x[k] = j->x + (size_t)(e + k) * j->sx, lv[k] = j->level ? j->level[e + k] : 0;
    if (dtm_kernel_elastic_lambda_lanes(j->type, DTM_KERNEL_LANES, m, x, lv, l, &failed)) abort();
    s += l[0] + l[3];
  }
  sink = s;
}

#endif

static void run_shell(const job *j) {
  dtm_shell_section sec = {210e9, 0.3, 7850, 0.005, 0};
  double out[3], m[DTM_STRUCT_DOF], s = 0;
  int nn;
  for (int e = 0; e < j->n; e++) {
    if (dtm_kernel_shell_bounds(j->type, &sec, j->x + (size_t)e * j->sx, DTM_STRUCT_NEED_SCALE, 0, out, m, &nn))
      abort();
    s += out[0];
  }
  sink = s;
}

/* The 30 x 30 eigenvalue problems of the n tet10 in x: the scaled
 * matrices built once (outside the timing), copied and solved. */
static double *eig_matrices(const job *j) {
  double *K = malloc(sizeof(double) * 900 * (size_t)j->n), mass[DTM_K_NODES], xl[DTM_K_NODES][3];
  for (int e = 0; e < j->n; e++) {
    double *k = K + 900 * (size_t)e;
    dtm_elem_local(DTM_TET10, j->x + (size_t)e * j->sx, xl);
    if (!dtm_affine_matrices(DTM_TET10, 3, 10, (const double(*)[3])xl, j->m, k, mass)) abort();
    for (int r = 0; r < 30; r++)
      for (int c = 0; c < 30; c++) k[r * 30 + c] /= sqrt(mass[r / 3] * mass[c / 3]);
  }
  return K;
}

static const double *eig_source;
static void run_eig(const job *j) {
  double a[900], s = 0;
  for (int e = 0; e < j->n; e++) {
    memcpy(a, eig_source + 900 * (size_t)e, sizeof a);
    s += dtm_eig_sym_max_tridiag(30, a);
  }
  sink = s;
}

#ifdef DTM_KERNEL_LANES
static void run_eig_lanes(const job *j) {
  double l[4], s = 0, a[4][900];
  for (int e = 0; e + 4 <= j->n; e += 4) {
    double *p[4] = {a[0], a[1], a[2], a[3]};
    memcpy(a, eig_source + 900 * (size_t)e, sizeof a); /* the same copies as run_eig: they read */
    dtm_eig_sym_max_tridiag_lanes(30, p, 4, l);
    s += l[0] + l[3];
  }
  sink = s;
}
#endif

/* One timed pass of f over j's elements: ns per element. */
static double pass_ns(void (*f)(const job *), const job *j) {
  double t0 = now();
  f(j);
  return 1e9 * (now() - t0) / j->n;
}

typedef struct {
  const char *name, *path;
  double flops;
  void (*f)(const job *);
  const job *j;
  double best; /* ns per element, the best pass */
} kernel;

int main(int argc, char **argv) {
  int n = argc > 1 ? atoi(argv[1]) : 400, rounds = argc > 2 ? atoi(argv[2]) : 15;
  n -= n % 4;
  double *x10 = malloc(sizeof(double) * 30 * n), *xc = malloc(sizeof(double) * 30 * n);
  double *x8 = malloc(sizeof(double) * 24 * n), *x4 = malloc(sizeof(double) * 12 * n);
  double *xt = malloc(sizeof(double) * 9 * n), *xq = malloc(sizeof(double) * 12 * n);
  int *lv = malloc(sizeof(int) * n), points = 0;
  for (int e = 0; e < n; e++) {
    double h = pow(10, urand());
    tet10(h, 0, x10 + 30 * e);
    tet10(h, 0.06, xc + 30 * e);
    memcpy(x4 + 12 * e, x10 + 30 * e, 12 * sizeof(double));
    hex8(h, x8 + 24 * e);
    flat(3, h, xt + 9 * e);
    flat(4, h, xq + 12 * e);
    double rem;
    lv[e] = dtm_ref_level_elem(DTM_TET10, xc + 30 * e, &rem);
    const dtm_ref_table *t = dtm_ref_rule_table(DTM_TET10, lv[e]);
    points += t ? t->q.n : 0;
  }
  dtm_memo_clear(); /* the kernel integrates the kept level: what a run's memo spares is not this table's */
  dtm_elastic_moduli m;
  if (dtm_elastic_moduli_init(DTM_FORM_3D, 210e9, 0.3, 7850, &m)) return 1;
  double mean_points = (double)points / n, eig = eig_flops(30) - 2.0 * 900 - 60, pk = 0, pk_avx = 0;
  job j4 = {DTM_TET4, n, 12, 0, x4, NULL, &m}, j10 = {DTM_TET10, n, 30, 0, x10, NULL, &m};
  job jc = {DTM_TET10, n, 30, 0, xc, lv, &m}, j8 = {DTM_HEX8, n, 24, 0, x8, NULL, &m};
  job jt = {DTM_TRI3, n, 9, 0, xt, NULL, &m}, jq = {DTM_QUAD4, n, 12, 0, xq, NULL, &m};
  eig_source = eig_matrices(&j10);
  kernel ks[] = {
      {"tet4", "closed form", 250, run_scalar, &j4, INFINITY},
      {"tet10 straight", "one by one", tet10_straight_flops(), run_scalar, &j10, INFINITY},
      {"tet10 30 x 30 eigenvalue alone", "one by one", eig, run_eig, &j10, INFINITY},
      {"tet10 curved (level kept)", "one by one", tet10_curved_flops((int)(mean_points + 0.5)), run_scalar, &jc,
       INFINITY},
      {"hex8", "one by one", hex8_flops(), run_scalar, &j8, INFINITY},
      {"tri3 shell (scaled bound)", "one by one", tri3_shell_flops(), run_shell, &jt, INFINITY},
      {"quad4 shell (scaled bound)", "one by one", quad4_shell_flops(), run_shell, &jq, INFINITY},
#ifdef DTM_KERNEL_LANES
      {"tet10 straight", "lanes", tet10_straight_flops(), run_lanes, &j10, INFINITY},
      {"tet10 30 x 30 eigenvalue alone", "lanes", eig, run_eig_lanes, &j10, INFINITY},
      {"tet10 curved (level kept)", "lanes", tet10_curved_flops((int)(mean_points + 0.5)), run_lanes, &jc, INFINITY},
      {"hex8", "lanes", hex8_flops(), run_lanes, &j8, INFINITY},
#endif
  };
  int nk = (int)(sizeof ks / sizeof ks[0]);
  for (int r = 0; r < rounds; r++) { /* interleaved: every kernel sees the same load */
    pk = fmax(pk, peak_of(matmul));
#ifdef HAVE_AVX_PEAK
    if (__builtin_cpu_supports("avx")) pk_avx = fmax(pk_avx, peak_of(matmul_avx));
#endif
    for (int k = 0; k < nk; k++) ks[k].best = fmin(ks[k].best, pass_ns(ks[k].f, ks[k].j));
  }
  printf("peak %.3f GFlop/s (30 x 30 matrix product, same flags, one thread)\n", pk);
  printf("peak_avx %.3f GFlop/s (the same compiled for AVX; 0: no AVX)\n", pk_avx);
  printf("elements %d per kernel, %d interleaved rounds; curved tet10: %.1f rule points on average\n", n, rounds,
         mean_points);
  for (int k = 0; k < nk; k++)
    printf("ROW|%s|%s|%.0f|%.1f|%.3f\n", ks[k].name, ks[k].path, ks[k].flops, ks[k].best, ks[k].flops / ks[k].best);
  return 0;
}
