/* Geometric characteristic lengths (dtm_kernel_length), each definition on
 * shapes where it can be worked out by hand, plus the property that makes
 * DTM_LEN_SAFE worth its name: L_safe / C_D never exceeds the element's own
 * step 2/sqrt(lambda_e) for nu >= 0 (src/kernel/length.c proves it).
 *   regular tet, edge a: altitude h = a sqrt(2/3); sum_a h_a^-2 = 6/a^2, so
 *     L_safe = 2/sqrt(4 * 6/a^2) = a/sqrt(6); inradius a/(2 sqrt 6), so
 *     2r = a/sqrt(6) too; V/A_max = h/3.
 *   right triangle, legs a = 3, b = 4, c = 5: altitudes a, b, ab/c; sum
 *     h^-2 = 2(a^2+b^2)/(a b)^2, L_safe = 2ab/(c sqrt 6); 2r = 2ab/(a+b+c)
 *     = 2; A/c = 6/5.
 *   box a x b x c (hex8): min width = a; 2r := 2 * 3V/(total area) =
 *     3abc/(ab+bc+ca); V/A_max = a; L_safe: integral|grad N|^2 = V/9 sum
 *     1/a_i^2 and integral N = V/8 per node, so L_safe = (3/4)/sqrt(sum
 *     1/a_i^2).
 *   bar of length L: every length is L.
 * Tolerance 1e-14 relative: closed forms and exact quadrature on O(1)
 * numbers. */
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

static double len(int type, dtm_length_kind k, const double *x) { return dtm_kernel_length(type, k, x); }

static void test_regular_tet(void **state) {
  (void)state;
  double a = 0.7, x[12] = {0, 0, 0, a, 0, 0, a / 2, a * sqrt(3) / 2, 0, a / 2, a * sqrt(3) / 6, a * sqrt(2.0 / 3)};
  double h = a * sqrt(2.0 / 3);
  near(len(DTM_TET4, DTM_LEN_SAFE, x), a / sqrt(6), 1e-14, "tet safe");
  near(len(DTM_TET4, DTM_LEN_MIN_EDGE, x), a, 1e-14, "tet min edge");
  near(len(DTM_TET4, DTM_LEN_MIN_ALTITUDE, x), h, 1e-14, "tet altitude");
  near(len(DTM_TET4, DTM_LEN_INRADIUS, x), a / sqrt(6), 1e-14, "tet 2r");
  near(len(DTM_TET4, DTM_LEN_VOLUME_AREA, x), h / 3, 1e-14, "tet V/A");
  assert_true(isnan(len(DTM_TET4, DTM_LEN_EIGEN, x)));
}

static void test_right_triangle(void **state) {
  (void)state;
  double x[9] = {0, 0, 0, 3, 0, 0, 0, 4, 0};
  near(len(DTM_TRI3, DTM_LEN_SAFE, x), 24 / (5 * sqrt(6)), 1e-14, "tri safe");
  near(len(DTM_TRI3, DTM_LEN_MIN_EDGE, x), 3, 1e-14, "tri min edge");
  near(len(DTM_TRI3, DTM_LEN_MIN_ALTITUDE, x), 12.0 / 5, 1e-14, "tri altitude");
  near(len(DTM_TRI3, DTM_LEN_INRADIUS, x), 2, 1e-14, "tri 2r");
  near(len(DTM_TRI3, DTM_LEN_VOLUME_AREA, x), 6.0 / 5, 1e-14, "tri A/c");
  assert_true(isnan(len(DTM_TRI3, DTM_LEN_EIGEN, x)));
}

static void test_box_and_bar(void **state) {
  (void)state;
  const double a = 1, b = 2, c = 3;
  const double x[24] = {0, 0, 0, a, 0, 0, a, b, 0, 0, b, 0, 0, 0, c, a, 0, c, a, b, c, 0, b, c};
  double inv2 = 1 / (a * a) + 1 / (b * b) + 1 / (c * c);
  near(len(DTM_HEX8, DTM_LEN_SAFE, x), 0.75 / sqrt(inv2), 1e-14, "box safe");
  near(len(DTM_HEX8, DTM_LEN_MIN_EDGE, x), a, 1e-14, "box min edge");
  near(len(DTM_HEX8, DTM_LEN_MIN_ALTITUDE, x), a, 1e-14, "box width");
  near(len(DTM_HEX8, DTM_LEN_INRADIUS, x), 3 * a * b * c / (a * b + b * c + c * a), 1e-14, "box 2r");
  near(len(DTM_HEX8, DTM_LEN_VOLUME_AREA, x), a, 1e-14, "box V/A");
  const double bar[6] = {1, 1, 1, 1.3, 1.4, 1};
  for (int k = DTM_LEN_SAFE; k <= DTM_LEN_VOLUME_AREA; k++) near(len(DTM_LINE2, k, bar), 0.5, 1e-14, "bar length");
  assert_true(isnan(len(29, DTM_LEN_MIN_EDGE, bar)));
  const double inv[12] = {0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1};
  assert_true(isnan(len(DTM_TET4, DTM_LEN_SAFE, inv)));
  assert_int_equal(dtm_error_code(), DTM_OK); /* lengths raise nothing */
}

/* L_safe / C_D <= 2 / sqrt(lambda_e) for every type, several shapes and
 * nu in [0, 0.5); equality holds for the bar, hence the 1e-13 slack. */
static void test_safe_is_safe(void **state) {
  (void)state;
  static const struct {
    int type, nn;
    double x[24];
  } el[] = {{DTM_LINE2, 2, {0, 0, 0, 1, 1, 0}},
            {DTM_TRI3, 3, {0, 0, 0, 1, 0, 0, 0.5, 0.05, 0}},
            {DTM_QUAD4, 4, {0, 0, 0, 2, 0, 0, 2.2, 1, 0, 0, 0.8, 0}},
            {DTM_TET4, 4, {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.02}},
            {DTM_TET4, 4, {0, 0, 0, 1, 0, 0, 0.5, 0.866, 0, 0.5, 0.29, 0.8}},
            {DTM_HEX8, 8, {0, 0, 0, 1.1, 0, 0.1, 1, 1, 0, 0, 0.9, 0, 0, 0.1, 0.3, 1, 0, 0.4, 1, 1, 0.3, 0.1, 1, 0.35}},
            {DTM_PRISM6, 6, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 3, 1, 0, 3, 0, 1, 3}},
            {DTM_PYR5, 5, {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0.2, 0.1, 0.4}}};
  const double nus[] = {0, 0.25, 0.45, 0.4999};
  for (size_t e = 0; e < sizeof el / sizeof el[0]; e++)
    for (size_t i = 0; i < sizeof nus / sizeof nus[0]; i++) {
      int dim;
      dtm_elem_info(el[e].type, &dim, NULL);
      dtm_formulation f = dim == 3   ? DTM_FORM_3D
                          : dim == 2 ? (i % 2 ? DTM_FORM_PLANE_STRESS : DTM_FORM_PLANE_STRAIN)
                                     : DTM_FORM_BAR;
      dtm_elastic_moduli m;
      double lambda;
      assert_int_equal(dtm_elastic_moduli_init(f, 5e10, nus[i], 2500, &m), 0);
      assert_int_equal(dtm_kernel_elastic_lambda(el[e].type, &m, el[e].x, &lambda), 0);
      double dt_safe = len(el[e].type, DTM_LEN_SAFE, el[e].x) / m.cd;
      if (!(dt_safe <= 2 / sqrt(lambda) * (1 + 1e-13)))
        fail_msg("%s, nu %g: L_safe/C_D = %g > element step %g", dtm_elem_name(el[e].type), nus[i], dt_safe,
                 2 / sqrt(lambda));
    }
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_regular_tet),
      cmocka_unit_test(test_right_triangle),
      cmocka_unit_test(test_box_and_bar),
      cmocka_unit_test(test_safe_is_safe),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
