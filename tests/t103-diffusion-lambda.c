/* Diffusion element bound lambda_max(Ce^-1 Ke) (dtm_kernel_diffusion_lambda)
 * against hand-derived values. Forward Euler is stable for dt <= 2/lambda.
 *   bar, length h:    Ke = alpha/h [[1,-1],[-1,1]], Ce = h/2 I, lambda =
 *                     4 alpha/h^2: dt = h^2/(2 alpha) exactly.
 *   square quad4 and cube hex8, side h: Ke = sum over directions of 1D
 *     stiffness (x) 1D consistent masses; on the vectors (1,1) and (1,-1)
 *     per direction the 1D stiffness is 0 and 2/h, the mass h/2 and h/6,
 *     so the largest eigenvalue of Ke is that of one "(1,-1)" direction:
 *     (2/h)(h/2)^(d-1). With Ce = h^d/2^d I, lambda = 4 alpha/h^2 for both:
 *     a single element already gives DESIGN.md's h^2/(2 alpha), not the
 *     finite-difference h^2/(2 d alpha).
 *   simplices: lambda = (d+1) alpha s_max (S = sum g_a g_a^T); regular tet
 *     of edge a: s = 2/a^2; right isosceles triangle of legs 1: S =
 *     [[2,1],[1,2]], s_max = 3.
 *   right prism (unit right triangle x height H): Ke and Ce are tensor
 *     products of the triangle's and the line's, and the triangle's lumped
 *     and consistent masses commute with its stiffness (the consistent mass
 *     is (A/12)(I + 11^T)), so the eigenvalues are 4/H^2 (constant over the
 *     triangle), 3 s_i and s_i + 1/H^2 (s = 3, 1): lambda = max(4/H^2, 9).
 *   Gmsh reference pyramid: 16/3, from exact rational integration (sympy,
 *     rational basis in collapsed coordinates) and a 40-digit eigensolver.
 * Tolerance 1e-13 relative: closed forms or exact quadrature followed by a
 * converged Jacobi, a few roundings of O(1) numbers. */
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

static double lambda_of(int type, double alpha, const double *x) {
  double l = NAN;
  dtm_error_clear();
  if (dtm_kernel_diffusion_lambda(type, alpha, x, &l)) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static void test_bar(void **state) {
  (void)state;
  double h = 0.3, alpha = 1.2e-6, x[6] = {0, 0, 0, 0, h, 0};
  near(2 / lambda_of(DTM_LINE2, alpha, x), h * h / (2 * alpha), 1e-14, "bar dt = h^2/(2 alpha)");
}

static void test_quad_hex(void **state) {
  (void)state;
  double h = 0.02, alpha = 3e-5;
  double q[12] = {0, 0, 0, h, 0, 0, h, h, 0, 0, h, 0}, x[24];
  near(2 / lambda_of(DTM_QUAD4, alpha, q), h * h / (2 * alpha), 1e-13, "square quad4 dt");
  const int c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (int a = 0; a < 8; a++)
    for (int i = 0; i < 3; i++) x[3 * a + i] = h * c[a][i];
  near(2 / lambda_of(DTM_HEX8, alpha, x), h * h / (2 * alpha), 1e-13, "cube hex8 dt");
}

static void test_simplices(void **state) {
  (void)state;
  double a = 0.5, alpha = 2;
  double tet[12] = {0, 0, 0, a, 0, 0, a / 2, a * sqrt(3) / 2, 0, a / 2, a * sqrt(3) / 6, a * sqrt(2.0 / 3)};
  near(lambda_of(DTM_TET4, alpha, tet), 4 * alpha * 2 / (a * a), 1e-13, "regular tet");
  double tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  near(lambda_of(DTM_TRI3, alpha, tri), 3 * alpha * 3, 1e-13, "right triangle");
  /* Closed form vs the generic path on assorted shapes. */
  const double shapes[][12] = {{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1},
                               {0.1, 0.2, 0, 1.3, 0.1, 0.2, 0.4, 1.1, -0.1, 0.5, 0.3, 0.9},
                               {0, 0, 0, 1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1},
                               {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 1e-3}};
  for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
    double g;
    assert_int_equal(dtm_diffusion_lambda_generic(DTM_TET4, alpha, shapes[s], &g), 0);
    /* 1e-12: the needle and the sliver form S with cancellation ~ aspect */
    near(lambda_of(DTM_TET4, alpha, shapes[s]), g, 1e-12, "tet closed vs Jacobi");
  }
}

static void test_prism_pyramid(void **state) {
  (void)state;
  double pr[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 0, 1, 1};
  near(lambda_of(DTM_PRISM6, 1, pr), 9, 1e-13, "prism H = 1");
  for (int a = 3; a < 6; a++) pr[3 * a + 2] = 0.5;
  near(lambda_of(DTM_PRISM6, 1, pr), 16, 1e-13, "prism H = 1/2");
  double py[15] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 1};
  near(lambda_of(DTM_PYR5, 1, py), 16.0 / 3, 1e-13, "reference pyramid");
}

static void test_scaling(void **state) {
  (void)state;
  const double hex[24] = {0, 0, 0, 1.1, 0, 0.1, 1, 1, 0, 0, 0.9, 0, 0, 0.1, 1, 1, 0, 1.2, 1, 1, 1, 0.1, 1, 1};
  double small[24];
  for (int i = 0; i < 24; i++) small[i] = 1e-3 * hex[i];
  double l = lambda_of(DTM_HEX8, 1e-6, hex);
  /* dt ~ L^2 / alpha: 1e-3 smaller element, 1e-6 smaller step */
  near(lambda_of(DTM_HEX8, 1e-6, small), 1e6 * l, 1e-12, "dt scales as L^2");
  near(lambda_of(DTM_HEX8, 3e-6, hex), 3 * l, 1e-14, "dt scales as 1/alpha");
}

static void test_errors(void **state) {
  (void)state;
  const double tet[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double inv[12] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
  double l;
  const double bad_alpha[] = {0, -1, NAN, INFINITY};
  for (size_t i = 0; i < sizeof bad_alpha / sizeof bad_alpha[0]; i++) {
    dtm_error_clear();
    assert_int_equal(dtm_kernel_diffusion_lambda(DTM_TET4, bad_alpha[i], tet, &l), DTM_ERR_INPUT);
    assert_non_null(strstr(dtm_error_message(), "diffusivity"));
  }
  dtm_error_clear();
  assert_int_equal(dtm_kernel_diffusion_lambda(DTM_TET4, 1, inv, &l), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "degenerate or inverted"));
  dtm_error_clear();
  assert_int_equal(dtm_kernel_diffusion_lambda(29, 1, tet, &l), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "second-order"));
  dtm_error_clear();
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bar),           cmocka_unit_test(test_quad_hex), cmocka_unit_test(test_simplices),
      cmocka_unit_test(test_prism_pyramid), cmocka_unit_test(test_scaling),  cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
