/* Elastic element bound lambda_max(Me^-1 Ke) (dtm_kernel_elastic_lambda)
 * against hand-derived closed forms, the simplex closed form against the
 * generic assembled-Ke + Jacobi path, invariances, the small eigen solvers
 * and the error paths.
 *
 * Hand values (row-sum lumped mass, see src/kernel/elastic_simplex.c):
 *   regular tet, edge a:  S = (2/a^2) I, lambda = 4/rho (2mu + 3lam) 2/a^2.
 *   equilateral triangle: S = (2/a^2) I, lambda = 3/rho (2mu + 2lam) 2/a^2.
 *   bar of length L:      lambda = 4E/(rho L^2), dt = 2/sqrt(lambda) = L/c.
 *   square quad4, side h (plane strain or stress): by the D4 symmetry of
 *     the square, the eigenvectors of Ke are the uniform dilatation
 *     (2(lam+mu)), the two pure shears (2mu each), the hourglass pair
 *     ((lam+3mu)/3) and three rigid modes (0); their sum matches
 *     tr Ke = (8/3)(lam + 3mu). Lumped mass rho h^2/4, so
 *     lambda = 8 (lam + mu)/(rho h^2) for lam >= 0.
 *   cube hex8, side h: Ke maps linear fields u = H x to nodal forces
 *     (h/2) sigma(H) x, so the dilatation has (3lam + 2mu) h/2 and the five
 *     deviatoric modes mu h; the bilinear and trilinear modes give
 *     (2/3) mu h, mu h/6 (x2), (lam+3mu) h/6 (x6), (lam+4mu) h/18 (x3);
 *     with six rigid modes the sum is (8/3)(lam + 4mu) h = tr Ke. Lumped
 *     mass rho h^3/8: lambda = 4 (3lam + 2mu)/(rho h^2) for lam >= 0
 *     (nu = 0: 4E/(rho h^2), dt = h/c).
 *   right prism (unit right triangle x height H) and the Gmsh reference
 *     pyramid: no short hand form; the values below come from exact
 *     rational integration (sympy, with the shape functions written out
 *     independently of dtmap, the pyramid's rational basis integrated in
 *     collapsed coordinates) and a 40-digit symmetric eigensolver.
 * Tolerances: 1e-13 relative where both sides are closed forms or exact
 * quadrature plus Jacobi (a handful of roundings on O(1) numbers, Jacobi
 * converged to eps^2 in the off-diagonal); 1e-12 for closed form vs
 * Jacobi on elongated shapes, whose metric S is formed with cancellation
 * growing with the aspect ratio (1e-3 here); 1e-10 for scaling by 1e-6
 * as the brief asks. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "kernel-impl.h"

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

static dtm_elastic_moduli moduli(dtm_formulation f, double E, double nu, double rho) {
  dtm_elastic_moduli m;
  assert_int_equal(dtm_elastic_moduli_init(f, E, nu, rho, &m), DTM_OK);
  return m;
}

static double lambda_of(int type, const dtm_elastic_moduli *m, const double *x) {
  double l = NAN;
  dtm_error_clear();
  int r = dtm_kernel_elastic_lambda(type, m, x, &l);
  if (r) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static double generic_of(int type, const dtm_elastic_moduli *m, const double *x) {
  double l = NAN;
  dtm_error_clear();
  assert_int_equal(dtm_elastic_lambda_generic(type, m, x, &l), DTM_OK);
  return l;
}

static void regular_tet(double a, double *x) {
  const double r[12] = {0, 0, 0, 1, 0, 0, 0.5, sqrt(3) / 2, 0, 0.5, sqrt(3) / 6, sqrt(2.0 / 3)};
  for (int i = 0; i < 12; i++) x[i] = a * r[i];
}

static void test_regular_tet(void **state) {
  (void)state;
  double x[12], a = 0.37;
  regular_tet(a, x);
  const double nus[] = {0, 0.25, 0.3, 0.45, 0.4999};
  for (size_t i = 0; i < sizeof nus / sizeof nus[0]; i++) {
    dtm_elastic_moduli m = moduli(DTM_FORM_3D, 60e9, nus[i], 2700);
    double want = 4 / m.rho * (2 * m.mu + 3 * m.lam) * 2 / (a * a);
    near(lambda_of(DTM_TET4, &m, x), want, 1e-13, "regular tet closed form");
    near(generic_of(DTM_TET4, &m, x), want, 1e-13, "regular tet generic");
  }
}

static void test_triangles(void **state) {
  (void)state;
  double a = 2.5, x[9] = {0, 0, 0, a, 0, 0, a / 2, a * sqrt(3) / 2, 0};
  for (int f = DTM_FORM_PLANE_STRAIN; f <= DTM_FORM_PLANE_STRESS; f++) {
    dtm_elastic_moduli m = moduli(f, 1e9, 0.3, 1000);
    double want = 3 / m.rho * (2 * m.mu + 2 * m.lam) * 2 / (a * a);
    near(lambda_of(DTM_TRI3, &m, x), want, 1e-13, "equilateral triangle");
    near(generic_of(DTM_TRI3, &m, x), want, 1e-13, "equilateral generic");
  }
  /* Right triangle, legs 3 and 4: S = [[2/9, 1/12], [1/12, 2/16]]. */
  double r[9] = {0, 0, 0, 3, 0, 0, 0, 4, 0};
  dtm_elastic_moduli m = moduli(DTM_FORM_PLANE_STRAIN, 1e9, 0.3, 1000);
  double sa = 2.0 / 9, sc = 2.0 / 16, sb = 1.0 / 12;
  double s1 = (sa + sc) / 2 + sqrt((sa - sc) * (sa - sc) / 4 + sb * sb);
  double s2 = sa + sc - s1, M = 2 * m.mu + m.lam;
  double top = M * (s1 + s2) / 2 + sqrt(M * M * (s1 - s2) * (s1 - s2) / 4 + m.lam * m.lam * s1 * s2);
  near(lambda_of(DTM_TRI3, &m, r), 3 / m.rho * top, 1e-13, "right triangle");
  near(generic_of(DTM_TRI3, &m, r), 3 / m.rho * top, 1e-13, "right tri generic");
}

static void test_bar(void **state) {
  (void)state;
  dtm_elastic_moduli m = moduli(DTM_FORM_BAR, 210e9, 0.3, 7850);
  double L = 0.125, x[6] = {1, 2, 3, 1 + L * 0.6, 2 + L * 0.8, 3};
  double l = lambda_of(DTM_LINE2, &m, x);
  near(l, 4 * 210e9 / (7850 * L * L), 1e-14, "bar lambda");
  near(2 / sqrt(l), L / m.cd, 1e-14, "bar dt = L/c");
  near(generic_of(DTM_LINE2, &m, x), l, 1e-13, "bar generic");
}

static void test_square_quad(void **state) {
  (void)state;
  double h = 0.01, x[12] = {0, 0, 0, h, 0, 0, h, h, 0, 0, h, 0};
  for (int f = DTM_FORM_PLANE_STRAIN; f <= DTM_FORM_PLANE_STRESS; f++) {
    dtm_elastic_moduli m = moduli(f, 70e9, 0.33, 2700);
    near(lambda_of(DTM_QUAD4, &m, x), 8 * (m.lam + m.mu) / (m.rho * h * h), 1e-13, "square quad4");
  }
}

static void test_cube_hex(void **state) {
  (void)state;
  double h = 2e-3, x[24];
  const int c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int a = 0; a < 8; a++)
    for (int i = 0; i < 3; i++) x[3 * a + i] = h * c[a][i];
  dtm_elastic_moduli m = moduli(DTM_FORM_3D, 60e9, 0.25, 2700);
  near(lambda_of(DTM_HEX8, &m, x), 4 * (3 * m.lam + 2 * m.mu) / (m.rho * h * h), 1e-13, "cube hex8");
  dtm_elastic_moduli m0 = moduli(DTM_FORM_3D, 60e9, 0, 2700);
  double l0 = lambda_of(DTM_HEX8, &m0, x);
  near(l0, 4 * 60e9 / (2700 * h * h), 1e-13, "cube hex8, nu = 0");
  near(2 / sqrt(l0), h / m0.cd, 1e-13, "cube hex8, nu = 0: dt = h/c");
}

static void test_prism_pyramid(void **state) {
  (void)state;
  dtm_elastic_moduli m = moduli(DTM_FORM_3D, 1, 0.25, 1);
  double pr[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1};
  near(lambda_of(DTM_PRISM6, &m, pr), 12.317224290413576607, 1e-13, "prism H=1");
  for (int a = 3; a < 6; a++) pr[3 * a + 2] = 0.5;
  near(lambda_of(DTM_PRISM6, &m, pr), 22.001260036849207390, 1e-13, "prism H=1/2");
  double py[15] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 1};
  near(lambda_of(DTM_PYR5, &m, py), 6.8794557256353899714, 1e-13, "pyramid");
}

/* Tets where closed form and Jacobi must agree: well shaped, a corner tet,
 * needles (one with an exactly symmetric cross-section: S has a double top
 * eigenvalue), a sliver and a cap, for several Poisson ratios including
 * nu < 0.045 (trigonometric path) and nu < 0 (auxetic: shear term). */
static void test_closed_vs_generic(void **state) {
  (void)state;
  const double shapes[][12] = {
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
      {0.1, 0.2, 0, 1.3, 0.1, 0.2, 0.4, 1.1, -0.1, 0.5, 0.3, 0.9},
      {0, 0, 0, 1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1},
      {-5e-4, -2.886751345948129e-4, 0, 5e-4, -2.886751345948129e-4, 0, 0, 5.773502691896258e-4, 0, 0, 0, 1},
      {0, 0, 0, 1, 0, 0, 0.5, 0.9, 0, 0.5, 0.3, 1e-3},
      {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1e-3},
      {0, 0, 0, 1, 0, 0, 0.5, 0.8, 0, 0.5, 0.27, 0.05}};
  const double nus[] = {0.3, 0.49, 0.1, 0.02, 0, -0.3, -0.9};
  for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++)
    for (size_t i = 0; i < sizeof nus / sizeof nus[0]; i++) {
      dtm_elastic_moduli m = moduli(DTM_FORM_3D, 1e10, nus[i], 2000);
      double a = lambda_of(DTM_TET4, &m, shapes[s]);
      double b = generic_of(DTM_TET4, &m, shapes[s]);
      near(a, b, 1e-12, "tet closed form vs Jacobi");
    }
  double tri[9] = {0, 0, 0, 1, 0, 0, 0.5, 1e-3, 0};
  for (size_t i = 0; i < sizeof nus / sizeof nus[0]; i++) {
    dtm_elastic_moduli m = moduli(DTM_FORM_PLANE_STRESS, 1e10, nus[i], 2000);
    near(lambda_of(DTM_TRI3, &m, tri), generic_of(DTM_TRI3, &m, tri), 1e-12, "flat triangle closed form vs Jacobi");
  }
}

/* Random well-shaped tets (regular, jittered by up to 40% of the edge):
 * closed form vs Jacobi. A fixed xorshift keeps the test reproducible. */
static void test_random_tets(void **state) {
  (void)state;
  uint64_t st = 88172645463325252ull;
  double reg[12], x[12];
  regular_tet(1, reg);
  dtm_elastic_moduli m = moduli(DTM_FORM_3D, 3e10, 0.2, 2500);
  for (int k = 0; k < 2000; k++) {
    for (int i = 0; i < 12; i++) {
      st ^= st << 13, st ^= st >> 7, st ^= st << 17;
      x[i] = reg[i] + 0.4 * ((double)(st >> 11) * 0x1.0p-53 - 0.5);
    }
    if (dtm_elem_measure(DTM_TET4, x) <= 0) continue;
    near(lambda_of(DTM_TET4, &m, x), generic_of(DTM_TET4, &m, x), 1e-13, "random tet closed form vs Jacobi");
  }
}

static void test_invariance(void **state) {
  (void)state;
  double x[12], y[12];
  const double t[12] = {0.1, 0.2, 0, 1.3, 0.1, 0.2, 0.4, 1.1, -0.1, 0.5, 0.3, 0.9};
  dtm_elastic_moduli m = moduli(DTM_FORM_3D, 1e10, 0.3, 2000);
  dtm_elastic_moduli m4 = moduli(DTM_FORM_3D, 4e10, 0.3, 2000);
  const int types[] = {DTM_TET4, DTM_HEX8};
  const double hex[24] = {0, 0, 0, 1.1, 0, 0.1, 1, 1, 0, 0, 0.9, 0, 0, 0.1, 1, 1, 0, 1.2, 1, 1, 1, 0.1, 1, 1};
  for (int k = 0; k < 2; k++) {
    int nn = types[k] == DTM_TET4 ? 4 : 8;
    const double *x0 = types[k] == DTM_TET4 ? t : hex;
    double big[24], small[24];
    for (int i = 0; i < 3 * nn; i++) big[i] = x0[i], small[i] = 1e-6 * x0[i];
    double dt = 2 / sqrt(lambda_of(types[k], &m, big));
    near(2 / sqrt(lambda_of(types[k], &m, small)), 1e-6 * dt, 1e-10, "dt scales with the element");
    near(2 / sqrt(lambda_of(types[k], &m4, big)), dt / 2, 1e-13, "4 E halves dt");
  }
  (void)x, (void)y;
}

/* Rotate by the rotation with axis (1, 2, 3) and angle 0.7, then shift. */
static void tilt(int nn, const double *x, double *y) {
  double k[3] = {1, 2, 3}, n = sqrt(14.0), c = cos(0.7), s = sin(0.7);
  for (int i = 0; i < 3; i++) k[i] /= n;
  for (int a = 0; a < nn; a++) {
    const double *p = x + 3 * a;
    double kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
    double kxp[3] = {k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]};
    for (int i = 0; i < 3; i++) y[3 * a + i] = p[i] * c + kxp[i] * s + k[i] * kp * (1 - c) + 10 * (i + 1);
  }
}

static void test_tilted_plane(void **state) {
  (void)state;
  const double tri[9] = {0, 0, 0, 1, 0.2, 0, 0.3, 0.8, 0};
  const double quad[12] = {0, 0, 0, 1, 0.1, 0, 1.2, 0.9, 0, -0.1, 1, 0};
  double y[12];
  dtm_elastic_moduli m = moduli(DTM_FORM_PLANE_STRAIN, 1e10, 0.3, 2000);
  tilt(3, tri, y);
  near(lambda_of(DTM_TRI3, &m, y), lambda_of(DTM_TRI3, &m, tri), 1e-13, "tilted triangle");
  tilt(4, quad, y);
  near(lambda_of(DTM_QUAD4, &m, y), lambda_of(DTM_QUAD4, &m, quad), 1e-13, "tilted quadrangle");
}

static void expect_error(int type, const dtm_elastic_moduli *m, const double *x, const char *word) {
  double l;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_elastic_lambda(type, m, x, &l), DTM_ERR_INPUT);
  if (!strstr(dtm_error_message(), word)) fail_msg("message \"%s\" lacks \"%s\"", dtm_error_message(), word);
  dtm_error_clear();
}

static void test_errors(void **state) {
  (void)state;
  dtm_elastic_moduli m3 = moduli(DTM_FORM_3D, 1e10, 0.3, 2000);
  dtm_elastic_moduli m2 = moduli(DTM_FORM_PLANE_STRAIN, 1e10, 0.3, 2000);
  const double tet[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double inv[12] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
  const double flat[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const double tri[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  const double bowtie[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  const double hexinv[24] = {0, 0, 0, 0, 1, 0, 1, 1, 0, 1, 0, 0, 0, 0, 1, 0, 1, 1, 1, 1, 1, 1, 0, 1};
  expect_error(DTM_TET4, &m3, inv, "degenerate or inverted");
  expect_error(DTM_TET4, &m3, flat, "degenerate or inverted");
  expect_error(DTM_TET4, &m2, tet, "plane-strain");
  expect_error(DTM_TRI3, &m3, tri, "3d");
  expect_error(DTM_TRI3, &m2, tri, "degenerate or inverted");
  expect_error(DTM_QUAD4, &m2, bowtie, "degenerate or inverted");
  expect_error(DTM_HEX8, &m3, hexinv, "degenerate or inverted");
  expect_error(29, &m3, tet, "second-order"); /* tet20: third order */
}

/* dtm_eig_sym_max and the closed-form 3x3 solver on matrices with known
 * spectra: S = Q diag(e) Q^T / 9 with Q = [[1,2,2],[2,1,-2],[2,-2,1]]
 * (orthogonal rows of length 3); only the final /9 rounds, so the stored
 * matrix has the spectrum e to ~eps |S|. Close pairs at the top and at the
 * bottom are the cases the deflation exists for. */
static void test_eigen(void **state) {
  (void)state;
  const double Q[3][3] = {{1, 2, 2}, {2, 1, -2}, {2, -2, 1}};
  const double spectra[][3] = {{3, 2, 1}, {1, 1, 0.3}, {1, 1 - 1e-9, 0.3}, {1, 1e-9, 0}, {5, 0.2, 0.2 + 1e-10},
                               {2, 2, 2}, {1e8, 3, 1}};
  for (size_t k = 0; k < sizeof spectra / sizeof spectra[0]; k++) {
    double A[3][3], s[6], e[3], a[9];
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        A[i][j] = 0;
        for (int l = 0; l < 3; l++) A[i][j] += Q[i][l] * spectra[k][l] * Q[j][l];
        A[i][j] /= 9;
        a[3 * i + j] = A[i][j];
      }
    s[0] = A[0][0], s[1] = A[1][1], s[2] = A[2][2];
    s[3] = A[0][1], s[4] = A[0][2], s[5] = A[1][2];
    dtm_eig3_sym(s, e);
    double sorted[3] = {spectra[k][0], spectra[k][1], spectra[k][2]};
    for (int i = 0; i < 2; i++)
      for (int j = 0; j < 2 - i; j++)
        if (sorted[j] < sorted[j + 1]) {
          double t = sorted[j];
          sorted[j] = sorted[j + 1], sorted[j + 1] = t;
        }
    for (int i = 0; i < 3; i++)
      if (fabs(e[i] - sorted[i]) > 1e-14 * sorted[0])
        fail_msg("spectrum %zu: eigenvalue %d = %.17g, want %.17g", k, i, e[i], sorted[i]);
    dtm_top3 t;
    dtm_eig3_top(s, &t);
    near(t.s1, sorted[0], 1e-14, "top eigenvalue");
    if (fabs(t.tau - (2 * sorted[0] - sorted[1] - sorted[2])) > 1e-14 * sorted[0] ||
        fabs(t.rho - (sorted[0] - sorted[1]) * (sorted[0] - sorted[2])) > 1e-14 * sorted[0] * sorted[0])
      fail_msg("spectrum %zu: gap sum/product %g %g", k, t.tau, t.rho);
    near(dtm_eig_sym_max(3, a), sorted[0], 1e-14, "Jacobi top eigenvalue");
  }
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_regular_tet),
      cmocka_unit_test(test_triangles),
      cmocka_unit_test(test_bar),
      cmocka_unit_test(test_square_quad),
      cmocka_unit_test(test_cube_hex),
      cmocka_unit_test(test_prism_pyramid),
      cmocka_unit_test(test_closed_vs_generic),
      cmocka_unit_test(test_random_tets),
      cmocka_unit_test(test_invariance),
      cmocka_unit_test(test_tilted_plane),
      cmocka_unit_test(test_errors),
      cmocka_unit_test(test_eigen),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
