/* Selective mass scaling against closed forms (src/spectral/sms.c,
 * sms_global.c, include/dtmap/sms.h).
 * One tet4 and one hex8 (steel, distorted): with beta = (T / dt_e)^2 - 1
 * for T = 3 dt_e, the top eigenvalue of the pencil (K, M_s) is that of
 * (K, M) divided by 1 + beta (SMS: the non-rigid modes are M-orthogonal to
 * the translations, which M_add annihilates), so the element's step grows
 * by exactly sqrt(1 + beta) = 3. Reference: dense K from the operator's
 * product, M_s from dtm_sms_assemble, the pencil reduced by a dense
 * Cholesky factor and its top by dtm_eig_sym_max (cyclic Jacobi): 1e-12
 * relative allows the rounding of these few dozen unknowns. The same
 * element's lambda from the kernel (dtm_kernel_elastic_lambda, which the
 * analysis's element step is) agrees with the dense (K, M) to 1e-10
 * (the kernel's own solver's tolerance). Rigid translations: M_add times a
 * unit translation along each axis is zero to 1e-13 of M_add's largest
 * entry times the unknowns; the translational mass (by the product) is
 * rho V exactly (1e-13). The matrix-free product agrees with the
 * assembled one (1e-13); PCG meets its tolerance.
 * A jittered 3 x 3 x 3 Kuhn tet grid with one corner node pulled in (a
 * thin element, steps spread 10x), target 2x and 5x its smallest step:
 * dtm_sms_lambda_max's proven bound holds the dense pencil's lambda_max
 * (1e-12 for rounding) and lies within 2 tol of it, and the probable
 * bound (certificate refused) holds it as well. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/operator.h"
#include "fixtures.h"
#include "dtmap/sms.h"

#define N 3
#define RHO 7850.0
#define TOL 1e-6

typedef struct {
  dtm_mesh m;
  dtm_block b;
  double *xyz;
  size_t *conn, *tags;
  int *mat;
} mesh_t;

static dtm_operator *make(const dtm_mesh *m) {
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO};
  dtm_operator *op = NULL;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 210e9, 0.3, RHO, &c.mod), 0);
  dtm_error_clear();
  if (dtm_operator_create(m, DTM_OP_ELASTIC, &c, NULL, NULL, 1, &op)) fail_msg("create: %s", dtm_error_message());
  return op;
}

static double *dense_csr(const dtm_csr *m) {
  double *a = calloc(m->n * m->n, sizeof *a);
  assert_non_null(a);
  for (size_t i = 0; i < m->n; i++)
    for (size_t p = m->rowptr[i]; p < m->rowptr[i + 1]; p++) a[i * m->n + m->col[p]] = m->val[p];
  return a;
}

/* The top eigenvalue of (K, M) for dense symmetric K, M (M positive
 * definite): M = L L^T, C = L^-1 K L^-T. */
static double pencil_top(size_t n, const double *k, const double *mm) {
  double *l = calloc(n * n, sizeof *l), *c = malloc(n * n * sizeof *c);
  assert_non_null(l), assert_non_null(c);
  for (size_t j = 0; j < n; j++)
    for (size_t i = j; i < n; i++) {
      double s = mm[i * n + j];
      for (size_t p = 0; p < j; p++) s -= l[i * n + p] * l[j * n + p];
      if (i == j) {
        assert_true(s > 0);
        l[j * n + j] = sqrt(s);
      } else
        l[i * n + j] = s / l[j * n + j];
    }
  memcpy(c, k, n * n * sizeof *c); /* columns: X = L^-1 K, then C = X L^-T = (L^-1 X^T)^T */
  for (int pass = 0; pass < 2; pass++) {
    for (size_t col = 0; col < n; col++)
      for (size_t i = 0; i < n; i++) {
        double s = c[col * n + i];
        for (size_t p = 0; p < i; p++) s -= l[i * n + p] * c[col * n + p];
        c[col * n + i] = s / l[i * n + i];
      }
    for (size_t i = 0; i < n; i++) /* transpose */
      for (size_t j = i + 1; j < n; j++) {
        double t = c[i * n + j];
        c[i * n + j] = c[j * n + i], c[j * n + i] = t;
      }
  }
  double top = dtm_eig_sym_max((int)n, c);
  free(l), free(c);
  return top;
}

static double *diag_of(const dtm_operator *op) {
  size_t n = dtm_operator_ndof(op);
  double *d = calloc(n * n, sizeof *d);
  assert_non_null(d);
  for (size_t i = 0; i < n; i++) d[i * n + i] = dtm_operator_mass(op)[i];
  return d;
}

static void one_element(int type, int nn, const double *x, double volume) {
  size_t conn[8], tag = 1;
  int mat = 0;
  double xyz[24];
  for (int a = 0; a < nn; a++) conn[a] = (size_t)a;
  memcpy(xyz, x, 3 * (size_t)nn * sizeof *xyz);
  dtm_block b = {.type = type, .dim = 3, .nn = nn, .n = 1, .tags = &tag, .conn = conn, .mat = &mat};
  dtm_mesh m = {.dim = 3, .nnodes = (size_t)nn, .xyz = xyz, .nblocks = 1, .blocks = &b};
  dtm_operator *op = make(&m);
  size_t n = dtm_operator_ndof(op);
  double *k = tu_operator_dense(op, 0), *md = diag_of(op), lam0 = pencil_top(n, k, md), lam_kernel;
  dtm_elastic_moduli mod;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 210e9, 0.3, RHO, &mod), 0);
  assert_int_equal(dtm_kernel_elastic_lambda(type, &mod, x, &lam_kernel), 0);
  assert_true(fabs(lam_kernel / lam0 - 1) < 1e-10);
  double dt = 2 / sqrt(lam0), beta;
  dtm_sms_beta(1, &dt, 3 * dt, &beta);
  assert_true(fabs(beta - 8) < 1e-12);
  dtm_sms *s = NULL;
  assert_int_equal(dtm_sms_create(op, &m, NULL, &beta, &s), 0);
  dtm_csr ms = {0}, add = {0};
  assert_int_equal(dtm_sms_assemble(s, 0, &ms), 0);
  assert_int_equal(dtm_sms_assemble(s, 1, &add), 0);
  double *msd = dense_csr(&ms), lams = pencil_top(n, k, msd);
  double grow = sqrt(lam0 / lams);
  print_message("%s: step x %.15f (sqrt(1 + beta) = 3)\n", dtm_elem_name(type), grow);
  assert_true(fabs(grow / 3 - 1) < 1e-12);
  double scaled_step;
  dtm_sms_element_steps(1, &dt, &beta, &scaled_step);
  assert_true(fabs(scaled_step / (2 / sqrt(lams)) - 1) < 1e-12);
  /* rigid translations in M_add's null space; the translational mass kept */
  double big = 0, *t = malloc(n * sizeof *t), *y = malloc(n * sizeof *y), *y2 = malloc(n * sizeof *y2);
  for (size_t p = 0; p < add.rowptr[n]; p++) big = fmax(big, fabs(add.val[p]));
  for (int c = 0; c < 3; c++) {
    for (size_t i = 0; i < n; i++) t[i] = i % 3 == (size_t)c;
    dtm_csr_apply(&add, t, y);
    for (size_t i = 0; i < n; i++) assert_true(fabs(y[i]) <= 1e-13 * big * (double)n);
  }
  dtm_sms_stats st;
  dtm_sms_stats_get(s, &st);
  assert_int_equal(st.scaled, 1);
  assert_true(fabs(st.translational / (RHO * volume) - 1) < 1e-13);
  assert_true(fabs(st.translational_m / (RHO * volume) - 1) < 1e-13);
  assert_true(fabs(st.trace_mass[0] / (RHO * volume) - 1) < 1e-13);
  assert_true(st.trace_add[0] > 0 && st.trace_add[0] < 8 * RHO * volume);
  /* the matrix-free product against the assembled one; PCG */
  for (size_t i = 0; i < n; i++) t[i] = sin(1.0 + (double)i);
  dtm_sms_apply(s, t, y);
  dtm_csr_apply(&ms, t, y2);
  for (size_t i = 0; i < n; i++) assert_true(fabs(y[i] - y2[i]) <= 1e-13 * fabs(big) * 9 * (double)n);
  int it = 0;
  assert_int_equal(dtm_sms_solve(&ms, y, 1e-12, 1000, y2, &it), 0);
  assert_true(it >= 1 && it <= 1000);
  for (size_t i = 0; i < n; i++) assert_true(fabs(y2[i] - t[i]) < 1e-9);
  free(t), free(y), free(y2), free(k), free(md), free(msd);
  dtm_csr_free(&ms), dtm_csr_free(&add);
  dtm_sms_destroy(&s);
  dtm_operator_destroy(&op);
}

static void test_tet4(void **state) {
  (void)state;
  const double x[12] = {0, 0, 0, 0.012, 0.001, 0, 0.002, 0.009, 0.001, 0.003, 0.002, 0.007};
  double e[3][3];
  for (int a = 0; a < 3; a++)
    for (int i = 0; i < 3; i++) e[a][i] = x[3 * (a + 1) + i] - x[i];
  double vol = (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0])) /
               6;
  one_element(DTM_TET4, 4, x, vol);
}

static void test_hex8(void **state) {
  (void)state;
  /* a brick 0.02 x 0.01 x 0.005 sheared in x by z (volume unchanged) */
  double x[24];
  static const int corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int a = 0; a < 8; a++) {
    x[3 * a] = 0.02 * corner[a][0] + 0.004 * corner[a][2];
    x[3 * a + 1] = 0.01 * corner[a][1];
    x[3 * a + 2] = 0.005 * corner[a][2];
  }
  one_element(DTM_HEX8, 8, x, 0.02 * 0.01 * 0.005);
}

/* ---- a small grid ------------------------------------------------------ */

static size_t nid(int i, int j, int k) { return (size_t)i + (N + 1) * ((size_t)j + (N + 1) * (size_t)k); }

static double det4(const double *x, const size_t *c) {
  double e[3][3];
  for (int a = 0; a < 3; a++)
    for (int i = 0; i < 3; i++) e[a][i] = x[3 * c[a + 1] + i] - x[3 * c[0] + i];
  return e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
         e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
}

static void grid_init(mesh_t *g) {
  static const int perm[6][2] = {{0, 1}, {0, 2}, {1, 0}, {1, 2}, {2, 0}, {2, 1}};
  size_t nn = nid(0, 0, N + 1), ne = 6 * N * N * N, e = 0;
  memset(g, 0, sizeof *g);
  g->xyz = malloc(nn * 3 * sizeof *g->xyz), g->conn = malloc(ne * 4 * sizeof *g->conn);
  g->tags = malloc(ne * sizeof *g->tags), g->mat = calloc(ne, sizeof *g->mat);
  uint64_t s = 7;
  for (int k = 0; k <= N; k++)
    for (int j = 0; j <= N; j++)
      for (int i = 0; i <= N; i++) {
        double *x = g->xyz + 3 * nid(i, j, k), d[3];
        for (int c = 0; c < 3; c++)
          s = s * 6364136223846793005u + 1442695040888963407u, d[c] = (double)(s >> 11) * 0x1.0p-52 - 1;
        x[0] = 0.01 * (i + 0.1 * d[0]), x[1] = 0.01 * (j + 0.1 * d[1]), x[2] = 0.01 * (k + 0.1 * d[2]);
      }
  double *c0 = g->xyz + 3 * nid(N, N, N); /* a corner pulled in: thin elements there */
  c0[0] -= 0.008, c0[1] -= 0.008, c0[2] -= 0.008;
  for (int k = 0; k < N; k++)
    for (int j = 0; j < N; j++)
      for (int i = 0; i < N; i++)
        for (int q = 0; q < 6; q++, e++) {
          int b1 = 1 << perm[q][0], b2 = b1 | 1 << perm[q][1];
          size_t *c = g->conn + 4 * e;
          c[0] = nid(i, j, k), c[1] = nid(i + (b1 & 1), j + (b1 >> 1 & 1), k + (b1 >> 2));
          c[2] = nid(i + (b2 & 1), j + (b2 >> 1 & 1), k + (b2 >> 2)), c[3] = nid(i + 1, j + 1, k + 1);
          if (det4(g->xyz, c) < 0) {
            size_t t = c[1];
            c[1] = c[2], c[2] = t;
          }
          g->tags[e] = e + 1;
        }
  g->b = (dtm_block){.type = DTM_TET4, .dim = 3, .nn = 4, .n = ne, .tags = g->tags, .conn = g->conn, .mat = g->mat};
  g->m = (dtm_mesh){.dim = 3, .nnodes = nn, .xyz = g->xyz, .nblocks = 1, .blocks = &g->b};
}

static void grid_free(mesh_t *g) { free(g->xyz), free(g->conn), free(g->tags), free(g->mat); }

/* Element steps by the kernel, as the analysis has them. */
static double element_steps(const mesh_t *g, double *dt) {
  dtm_elastic_moduli mod;
  double lo = INFINITY, hi = 0;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 210e9, 0.3, RHO, &mod), 0);
  for (size_t e = 0; e < g->b.n; e++) {
    double x[12], lam;
    for (int a = 0; a < 4; a++) memcpy(x + 3 * a, g->xyz + 3 * g->conn[4 * e + (size_t)a], 3 * sizeof *x);
    assert_int_equal(dtm_kernel_elastic_lambda(DTM_TET4, &mod, x, &lam), 0);
    dt[e] = 2 / sqrt(lam), lo = fmin(lo, dt[e]), hi = fmax(hi, dt[e]);
  }
  print_message("grid: element steps %.4g .. %.4g s\n", lo, hi);
  return lo;
}

static void check_grid(const mesh_t *g, dtm_operator *op, const double *k, const double *dt, double target) {
  size_t n = dtm_operator_ndof(op), ne = g->b.n;
  double *beta = malloc(ne * sizeof *beta);
  dtm_sms_beta(ne, dt, target, beta);
  dtm_sms *s = NULL;
  dtm_csr ms = {0};
  assert_int_equal(dtm_sms_create(op, &g->m, NULL, beta, &s), 0);
  assert_int_equal(dtm_sms_assemble(s, 0, &ms), 0);
  double *msd = dense_csr(&ms), exact = pencil_top(n, k, msd);
  dtm_sms_global gp, gq;
  assert_int_equal(dtm_sms_lambda_max(op, s, TOL, 400, 1, 1e9, -1, &gp), 0);
  assert_int_equal(dtm_sms_lambda_max(op, s, TOL, 400, 1, 0, 0.05, &gq), 0);
  print_message("target %.4g s: exact step %.6g s, proven %.6g s (%d steps, %.1f CG iterations per solve), "
                "probable %.6g s (%d steps, eps %.3g)\n",
                target, 2 / sqrt(exact), gp.dt, gp.iterations, gp.cg_mean, gq.dt, gq.iterations, gq.eps);
  assert_int_equal(gp.certified, DTM_CERT_PROVEN);
  assert_true(gp.converged);
  assert_true(gp.bound >= exact * (1 - 1e-12));
  assert_true(gp.bound <= exact * (1 + 2 * TOL));
  assert_true(gp.theta <= exact * (1 + 1e-12));
  assert_int_equal(gq.certified, DTM_CERT_PROBABLE);
  assert_true(gq.bound >= exact * (1 - 1e-12));
  free(msd), free(beta);
  dtm_csr_free(&ms);
  dtm_sms_destroy(&s);
}

static void test_grid(void **state) {
  (void)state;
  mesh_t g;
  grid_init(&g);
  dtm_operator *op = make(&g.m);
  double *dt = malloc(g.b.n * sizeof *dt), lo = element_steps(&g, dt), *k = tu_operator_dense(op, 0);
  check_grid(&g, op, k, dt, 2 * lo);
  check_grid(&g, op, k, dt, 5 * lo);
  free(dt), free(k);
  dtm_operator_destroy(&op);
  grid_free(&g);
}

static void test_beta(void **state) {
  (void)state;
  double dt[4] = {1, 2, INFINITY, 0}, beta[4];
  dtm_sms_beta(4, dt, 1.5, beta);
  assert_true(fabs(beta[0] - 1.25) < 1e-15);
  assert_true(beta[1] == 0 && beta[2] == 0 && beta[3] == 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_beta), cmocka_unit_test(test_tet4),
                                     cmocka_unit_test(test_hex8), cmocka_unit_test(test_grid)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
