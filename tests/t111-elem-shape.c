/* The shape classification behind dtmap's invalid-element policy
 * (dtm_kernel_shape): the scaled Jacobian det J / (product of the column
 * lengths of J) at the integration points and nodes, against closed forms.
 *  - Right-corner tet: J = I, scaled Jacobian 1. Regular tet: three unit
 *    edges at 60 degrees, det = sqrt(1 - 3c^2 + 2c^3) at c = 1/2, so 1/sqrt(2).
 *  - Unit cube with node 0 moved to (a, a, a): x = X + d N0(X), d = (a,a,a),
 *    N0 = (1-X)(1-Y)(1-Z), so J = I + d grad(N0)^T and (rank-one update)
 *    det J = 1 - a [(1-Y)(1-Z) + (1-X)(1-Z) + (1-X)(1-Y)]. At node 0 it is
 *    1 - 3a, the columns there are e_i - d, each of length
 *    sqrt((1-a)^2 + 2a^2): scaled (1 - 3a)/((1-a)^2 + 2a^2)^(3/2), negative
 *    for a > 1/3. The smallest value at the 2x2x2 Gauss points is at the
 *    point nearest node 0, X = Y = Z = g = (1 - 1/sqrt(3))/2:
 *    1 - 3a(1-g)^2, which vanishes at a* = 1/(3 (1-g)^2) = 0.5359: below
 *    a* the element is inverted at a corner only (analysed, flagged), above
 *    it at a Gauss point (refused). Its volume is 1 - 3a/4 and the row sum
 *    of node 0 is 1/8 - a/6 (integrals of products of (1-X)^k).
 *  - Dart quadrangle (0,0) (2,0) (2,2) (1.1,0.9): det J is linear in (u, v)
 *    with corner values 0.45, 1, 0.45, -0.1 (cross products of half edges),
 *    positive at the Gauss points (0.45 - 0.55/sqrt(3) = 0.1325 at the
 *    worst); at node 3 the half edges are (0.45, 0.55) and (0.55, 0.45):
 *    scaled -0.1/0.505.
 * Tolerances: 1e-13 relative, a few roundings of O(1) numbers through the
 * shape-function gradients (1e-14 where the arithmetic is exact). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want))) fail_msg("%s: got %.17g, want %.17g (rel tol %g)", what, got, want, rel);
}

static dtm_shape shape(int type, const double *x) {
  dtm_shape s;
  assert_int_equal(dtm_kernel_shape(type, x, &s), DTM_OK);
  return s;
}

static void test_simplices(void **state) {
  (void)state;
  const double right[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  dtm_shape s = shape(DTM_TET4, right);
  assert_int_equal(s.status, DTM_SHAPE_VALID);
  near(s.min_jacobian, 1, 1e-14, "right-corner tet");
  const double h = sqrt(3) / 2, z = sqrt(2.0 / 3);
  const double regular[] = {0, 0, 0, 1, 0, 0, 0.5, h, 0, 0.5, h / 3, z};
  near(shape(DTM_TET4, regular).min_jacobian, 1 / sqrt(2), 1e-14, "regular tet");
  const double inverted[] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
  s = shape(DTM_TET4, inverted);
  assert_int_equal(s.status, DTM_SHAPE_FOLDED);
  near(s.min_jacobian, -1, 1e-14, "inverted tet");
  assert_int_equal(s.point, 0);
  const double flat[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.3, 0.3, 0};
  s = shape(DTM_TET4, flat);
  assert_int_equal(s.status, DTM_SHAPE_FLAT);
  assert_true(fabs(s.min_jacobian) <= 32 * 2.2e-16);
  const double tri[] = {1, 1, 1, 1, 3, 1, 1, 1, 4}; /* right triangle in the plane x = 1 */
  near(shape(DTM_TRI3, tri).min_jacobian, 1, 1e-14, "right triangle");
  const double line[] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  assert_int_equal(shape(DTM_TRI3, line).status, DTM_SHAPE_FLAT);
  const double bar[] = {1, 2, 3, 1, 2, 3};
  assert_int_equal(shape(DTM_LINE2, bar).status, DTM_SHAPE_FLAT);
}

/* Unit cube [0,1]^3 in Gmsh's hex8 order with node 0 at (a, a, a). */
static void corner_hex(double a, double x[24]) {
  static const double cube[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
  memcpy(x, cube, sizeof cube);
  x[0] = x[1] = x[2] = a;
}

static void test_hex_corner(void **state) {
  (void)state;
  double x[24];
  corner_hex(0, x);
  dtm_shape s = shape(DTM_HEX8, x);
  assert_int_equal(s.status, DTM_SHAPE_VALID);
  near(s.min_jacobian, 1, 1e-14, "unit cube");
  const double a = 0.4;
  corner_hex(a, x);
  s = shape(DTM_HEX8, x);
  assert_int_equal(s.status, DTM_SHAPE_CORNER);
  assert_int_equal(s.node, 0);
  assert_int_equal(s.point, -1);
  near(s.min_jacobian, (1 - 3 * a) / pow((1 - a) * (1 - a) + 2 * a * a, 1.5), 1e-13, "corner scaled Jacobian");
  /* analysed: the element matrices are those of a valid map */
  near(dtm_elem_measure(DTM_HEX8, x), 1 - 3 * a / 4, 1e-13, "corner hex volume");
  double w[8];
  dtm_elem_lumped_weights(DTM_HEX8, x, w);
  near(w[0], (1.0 / 8 - a / 6) / (1 - 3 * a / 4), 1e-13, "row sum of the inverted corner");
  dtm_elastic_moduli m;
  double lambda = NAN, diff = NAN;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 1e9, 0.3, 1000, &m), DTM_OK);
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_HEX8, &m, x, &lambda), DTM_OK);
  assert_true(isfinite(lambda) && lambda > 0);
  assert_int_equal(dtm_kernel_diffusion_lambda(DTM_HEX8, 1e-6, x, &diff), DTM_OK);
  assert_true(isfinite(diff) && diff > 0);
  assert_true(dtm_kernel_length(DTM_HEX8, DTM_LEN_SAFE, x) > 0);
}

/* The threshold between an inverted corner and an inverted Gauss point. */
static void test_hex_threshold(void **state) {
  (void)state;
  const double g = (1 - 1 / sqrt(3)) / 2, star = 1 / (3 * (1 - g) * (1 - g));
  double x[24], lambda;
  dtm_elastic_moduli m;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 1e9, 0.3, 1000, &m), DTM_OK);
  corner_hex(star - 1e-3, x);
  assert_int_equal(shape(DTM_HEX8, x).status, DTM_SHAPE_CORNER);
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_HEX8, &m, x, &lambda), DTM_OK);
  corner_hex(star + 1e-3, x);
  dtm_shape s = shape(DTM_HEX8, x);
  assert_int_equal(s.status, DTM_SHAPE_FOLDED);
  assert_int_equal(s.point, 0); /* Gauss point 0 is the one nearest node 0 */
  dtm_error_clear();
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_HEX8, &m, x, &lambda), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "integration point 0"));
  dtm_error_clear();
  double flat[24];
  corner_hex(0, flat);
  for (int k = 0; k < 8; k++) flat[3 * k + 2] = 0; /* top face on the bottom one */
  assert_int_equal(shape(DTM_HEX8, flat).status, DTM_SHAPE_FLAT);
}

static void test_dart_quad(void **state) {
  (void)state;
  const double q[] = {0, 0, 0, 2, 0, 0, 2, 2, 0, 1.1, 0.9, 0};
  dtm_shape s = shape(DTM_QUAD4, q);
  assert_int_equal(s.status, DTM_SHAPE_CORNER);
  assert_int_equal(s.node, 3);
  near(s.min_jacobian, -0.1 / 0.505, 1e-13, "dart corner");
  /* an arrow: corner values 0.1, 1, 0.1, -0.8, so 0.1 - 0.9/sqrt(3) < 0 at a
   * Gauss point */
  const double arrow[] = {0, 0, 0, 2, 0, 0, 2, 2, 0, 1.8, 0.2, 0};
  assert_int_equal(shape(DTM_QUAD4, arrow).status, DTM_SHAPE_FOLDED);
  /* a symmetric bow-tie: its two lobes cancel, zero area */
  const double bowtie[] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 2, 2, 0};
  assert_int_equal(shape(DTM_QUAD4, bowtie).status, DTM_SHAPE_FLAT);
}

static void test_unsupported(void **state) {
  (void)state;
  double x[60] = {0};
  dtm_shape s;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_shape(29, x, &s), DTM_ERR_INPUT);
  dtm_error_clear();
  assert_string_equal(dtm_shape_describe(DTM_SHAPE_FLAT), "flat (zero measure)");
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_simplices), cmocka_unit_test(test_hex_corner),  cmocka_unit_test(test_hex_threshold),
      cmocka_unit_test(test_dart_quad), cmocka_unit_test(test_unsupported),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
