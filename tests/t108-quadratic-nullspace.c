/* Null spaces of the assembled second-order element matrices (generic
 * path, src/kernel/assemble.c) and the eigenvalue solver of that path
 * (src/kernel/tridiag.c):
 *   - elastic stiffness of every 3D type, tet10 and hex20 first: the six
 *     rigid modes (three translations, three rotations omega x x) are in
 *     its null space; of every 2D type (plane strain): the three rigid
 *     modes; the element is sheared, off the origin and, for tet10 and
 *     hex20, also curved;
 *   - scalar Laplacian of every type: the constant field;
 *   - symmetry of both matrices;
 *   - dtm_eig_sym_max_tridiag against the Jacobi solver dtm_eig_sym_max
 *     and against matrices of known spectrum, n from 1 to 81.
 * Tolerances: |K r| <= 1e-10 |K| |r| (Frobenius and Euclidean norms) for
 * the null spaces, the bar set for this work (the residuals measured are
 * about 1e-16: rounding of the quadrature sums); exact symmetry
 * for the second-order assembly (it mirrors one triangle); 1e-13 of the
 * matrix norm for the eigenvalues (both solvers are backward stable to a
 * small multiple of n eps |A|, n <= 81). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "assemble-impl.h"
#include "kernel-impl.h"

static const int types[] = {DTM_TET10,   DTM_HEX20, DTM_TRI6,  DTM_QUAD9,   DTM_HEX27,
                            DTM_PRISM18, DTM_PYR14, DTM_QUAD8, DTM_PRISM15, DTM_PYR13};
#define NTYPES (sizeof types / sizeof types[0])

static int nodes_of(int type) {
  int nn = 0;
  dtm_elem_info(type, NULL, &nn);
  return nn;
}

/* A sheared element off the origin; curved (two mid-edge nodes moved off
 * their edges) when curve is set. */
static void element(int type, int curve, double *x) {
  static const double A[3][3] = {{1.3, 0.4, -0.2}, {0.1, 0.9, 0.3}, {0.2, -0.1, 1.1}};
  static const double b[3] = {0.7, -1.2, 2.5};
  int d, nc;
  dtm_elem_info(type, &d, NULL);
  dtm_elem_info(dtm_elem_parent(type), NULL, &nc);
  for (int a = 0; a < nodes_of(type); a++) {
    double p[3];
    dtm_ref_node_uvw(type, a, p);
    for (int i = 0; i < 3; i++) {
      x[3 * a + i] = b[i];
      for (int j = 0; j < d; j++) x[3 * a + i] += (d == 3 || i < 2 ? A[i][j] : 0) * p[j];
    }
  }
  if (curve) { /* nodes nc and nc + 1 are mid-edge nodes in every type */
    x[3 * nc + 1] += 0.06, x[3 * nc + 2] -= 0.04;
    x[3 * (nc + 1)] -= 0.05;
  }
}

static double norm(int n, const double *v) {
  double s = 0;
  for (int i = 0; i < n; i++) s += v[i] * v[i];
  return sqrt(s);
}

/* |K r| / (|K| |r|) for the n x n matrix K. */
static double residual(int n, const double *K, const double *r) {
  double Kr[DTM_K_DOF];
  for (int i = 0; i < n; i++) {
    Kr[i] = 0;
    for (int j = 0; j < n; j++) Kr[i] += K[i * n + j] * r[j];
  }
  return norm(n, Kr) / (norm(n * n, K) * norm(n, r));
}

static void test_rigid_modes(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t];
    for (int curve = 0; curve < 2; curve++) {
      double x[3 * DTM_MAX_NODES], K[DTM_K_DOF * DTM_K_DOF], r[DTM_K_DOF];
      dtm_elem_geom eg;
      dtm_elastic_moduli m;
      element(type, curve, x);
      assert_int_equal(dtm_elem_setup(type, x, DTM_INTEGRATION_CONVERGED, &eg), 0);
      int d = eg.d, n = eg.nn * d;
      assert_int_equal(dtm_elastic_moduli_init(d == 3 ? DTM_FORM_3D : DTM_FORM_PLANE_STRAIN, 60e9, 0.3, 2700, &m),
                       DTM_OK);
      dtm_elem_stiffness(&eg, &m, K);
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
          if (K[i * n + j] != K[j * n + i]) fail_msg("%s: K not symmetric at %d %d", dtm_elem_name(type), i, j);
      /* translations, then rotations about axis k: u = e_k x x */
      int nmodes = d == 3 ? 6 : 3;
      for (int k = 0; k < nmodes; k++) {
        for (int a = 0; a < eg.nn; a++) {
          const double *y = eg.xl[a];
          double *u = r + a * d;
          for (int i = 0; i < d; i++) u[i] = k < d ? (i == k) : 0;
          if (k < d) continue;
          int axis = d == 3 ? k - 3 : 2; /* 2D: the one in-plane rotation */
          double e[3] = {0, 0, 0}, w[3];
          e[axis] = 1;
          w[0] = e[1] * y[2] - e[2] * y[1];
          w[1] = e[2] * y[0] - e[0] * y[2];
          w[2] = e[0] * y[1] - e[1] * y[0];
          for (int i = 0; i < d; i++) u[i] = w[i];
        }
        double res = residual(n, K, r);
        if (!(res <= 1e-10))
          fail_msg("%s%s: rigid mode %d, |Kr|/(|K||r|) = %g", dtm_elem_name(type), curve ? " (curved)" : "", k, res);
      }
    }
  }
}

static void test_constant_field(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t];
    for (int curve = 0; curve < 2; curve++) {
      double x[3 * DTM_MAX_NODES], K[DTM_K_NODES * DTM_K_NODES], one[DTM_K_NODES];
      dtm_elem_geom eg;
      element(type, curve, x);
      assert_int_equal(dtm_elem_setup(type, x, DTM_INTEGRATION_CONVERGED, &eg), 0);
      dtm_elem_laplace(&eg, K);
      for (int a = 0; a < eg.nn; a++) one[a] = 1;
      double res = residual(eg.nn, K, one);
      if (!(res <= 1e-10)) fail_msg("%s: |K 1|/(|K||1|) = %g", dtm_elem_name(type), res);
      for (int a = 0; a < eg.nn; a++)
        for (int b = 0; b < eg.nn; b++)
          if (fabs(K[a * eg.nn + b] - K[b * eg.nn + a]) > 1e-15 * norm(eg.nn * eg.nn, K))
            fail_msg("%s: Laplacian not symmetric", dtm_elem_name(type));
    }
  }
}

/* Deterministic pseudo-random numbers in [-1, 1). */
static double rnd(uint64_t *s) {
  *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
  return (double)(*s >> 11) * 0x1.0p-52 - 1;
}

/* a = Q diag(e) Q^T with Q = I - 2 v v^T / v.v (a Householder reflector). */
static void known_spectrum(int n, const double *e, uint64_t *s, double *a) {
  double v[DTM_K_DOF], vv = 0;
  for (int i = 0; i < n; i++) v[i] = rnd(s), vv += v[i] * v[i];
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) {
      a[i * n + j] = 0;
      for (int k = 0; k < n; k++) {
        double qik = (i == k) - 2 * v[i] * v[k] / vv, qjk = (j == k) - 2 * v[j] * v[k] / vv;
        a[i * n + j] += qik * e[k] * qjk;
      }
    }
}

static void test_tridiag_solver(void **state) {
  (void)state;
  const int sizes[] = {1, 2, 3, 6, 12, 30, 45, 60, 81};
  uint64_t s = 12345;
  double a[DTM_K_DOF * DTM_K_DOF], b[DTM_K_DOF * DTM_K_DOF], e[DTM_K_DOF];
  for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
    int n = sizes[k];
    /* random symmetric, indefinite */
    for (int i = 0; i < n; i++)
      for (int j = 0; j <= i; j++) a[i * n + j] = a[j * n + i] = rnd(&s) * 1e9;
    memcpy(b, a, sizeof(double) * (size_t)(n * n));
    double fro = norm(n * n, a);
    double t = dtm_eig_sym_max_tridiag(n, a), j = dtm_eig_sym_max(n, b);
    if (!(fabs(t - j) <= 1e-13 * fro)) fail_msg("n %d: tridiagonal %.17g, Jacobi %.17g", n, t, j);
    /* known spectrum with a cluster at the top and a null space, like an
     * element matrix (rigid modes) */
    for (int i = 0; i < n; i++) e[i] = i < n / 4 ? 0 : 1 + 1e-3 * rnd(&s);
    e[n - 1] = 1 + 2e-3;
    known_spectrum(n, e, &s, a);
    t = dtm_eig_sym_max_tridiag(n, a);
    if (!(fabs(t - e[n - 1]) <= 1e-13 * norm(n, e))) fail_msg("n %d: known top %.17g, got %.17g", n, e[n - 1], t);
  }
  /* diagonal, tiny and huge scales, and the zero matrix */
  for (int i = 0; i < 30; i++)
    for (int j = 0; j < 30; j++) a[i * 30 + j] = i == j ? 1e-300 * (i + 1) : 0;
  assert_true(fabs(dtm_eig_sym_max_tridiag(30, a) - 30e-300) <= 1e-13 * 30e-300);
  for (int i = 0; i < 30 * 30; i++) a[i] = 0;
  for (int i = 0; i < 30; i++) a[i * 30 + i] = -1e300 * (i + 1);
  assert_true(fabs(dtm_eig_sym_max_tridiag(30, a) + 1e300) <= 1e-13 * 1e300);
  for (int i = 0; i < 30 * 30; i++) a[i] = 0;
  assert_true(dtm_eig_sym_max_tridiag(30, a) == 0);
  /* a non-finite entry gives NaN, never a finite (unsafe) bound */
  a[5 * 30 + 7] = a[7 * 30 + 5] = NAN;
  assert_true(isnan(dtm_eig_sym_max_tridiag(30, a)));
  for (int i = 0; i < 30 * 30; i++) a[i] = i % 31 ? 0 : 1;
  a[0] = INFINITY;
  assert_true(isnan(dtm_eig_sym_max_tridiag(30, a)));
}

/* The bound of the generic path is the top eigenvalue of the lumped
 * problem whichever solver runs: re-solve the same matrix with Jacobi. */
static void test_kernel_vs_jacobi(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t];
    double x[3 * DTM_MAX_NODES], K[DTM_K_DOF * DTM_K_DOF], m[DTM_K_NODES], l = NAN;
    dtm_elem_geom eg;
    dtm_elastic_moduli mod;
    element(type, 1, x);
    assert_int_equal(dtm_elem_setup(type, x, DTM_INTEGRATION_CONVERGED, &eg), 0);
    int d = eg.d, n = eg.nn * d;
    assert_int_equal(dtm_elastic_moduli_init(d == 3 ? DTM_FORM_3D : DTM_FORM_PLANE_STRAIN, 60e9, 0.3, 2700, &mod),
                     DTM_OK);
    dtm_elem_stiffness(&eg, &mod, K);
    dtm_elem_mass(&eg, m);
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) K[i * n + j] /= mod.rho * sqrt(m[i / d] * m[j / d]);
    double fro = norm(n * n, K);
    double jac = dtm_eig_sym_max(n, K);
    dtm_error_clear();
    assert_int_equal(dtm_kernel_elastic_lambda(type, &mod, x, &l), DTM_OK);
    if (!(fabs(l - jac) <= 1e-13 * fro)) fail_msg("%s: kernel %.17g, Jacobi %.17g", dtm_elem_name(type), l, jac);
  }
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rigid_modes),
      cmocka_unit_test(test_constant_field),
      cmocka_unit_test(test_tridiag_solver),
      cmocka_unit_test(test_kernel_vs_jacobi),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
