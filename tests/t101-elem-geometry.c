/* Element catalogue, measures, lumped weights and elastic moduli of the
 * kernels (include/dtmap/kernel.h), against values worked out by hand.
 * Tolerances: 1e-14 relative for closed forms evaluated in double precision
 * (a few roundings of O(1) numbers); quadrature results are exact for these
 * affine elements, so they get the same tolerance. */
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

/* Unit-ish reference shapes in Gmsh node order. */
static const double line2[] = {0, 0, 0, 2, 0, 0};
static const double tri3[] = {0, 0, 0, 3, 0, 0, 0, 4, 0}; /* right, legs 3, 4 */
static const double quad4[] = {0, 0, 0, 2, 0, 0, 2, 3, 0, 0, 3, 0};
static const double tet4[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
static const double hex8[] = {0, 0, 0, 2, 0, 0, 2, 3, 0, 0, 3, 0, 0, 0, 4, 2, 0, 4, 2, 3, 4, 0, 3, 4};
static const double prism6[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 2, 1, 0, 2, 0, 1, 2};
static const double pyr5[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, 0, 0, 1};

static void test_info(void **state) {
  (void)state;
  static const struct {
    int type, dim, nn, simplex;
    const char *name;
  } t[] = {{DTM_LINE2, 1, 2, 1, "line2"}, {DTM_TRI3, 2, 3, 1, "tri3"}, {DTM_QUAD4, 2, 4, 0, "quad4"},
           {DTM_TET4, 3, 4, 1, "tet4"},   {DTM_HEX8, 3, 8, 0, "hex8"}, {DTM_PRISM6, 3, 6, 0, "prism6"},
           {DTM_PYR5, 3, 5, 0, "pyr5"}};
  for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
    int dim = -1, nn = -1;
    assert_int_equal(dtm_elem_info(t[i].type, &dim, &nn), DTM_OK);
    assert_int_equal(dim, t[i].dim);
    assert_int_equal(nn, t[i].nn);
    assert_int_equal(dtm_elem_is_simplex(t[i].type), t[i].simplex);
    assert_string_equal(dtm_elem_name(t[i].type), t[i].name);
  }
}

static void test_unsupported(void **state) {
  (void)state;
  int dim, nn;
  dtm_error_clear();
  assert_int_equal(dtm_elem_info(29, &dim, &nn), DTM_ERR_INPUT); /* tet20 (third order) */
  assert_non_null(strstr(dtm_error_message(), "type 29"));
  assert_non_null(strstr(dtm_error_message(), "second-order"));
  assert_string_equal(dtm_elem_name(29), "unknown");
  assert_int_equal(dtm_elem_is_simplex(29), 0);
  assert_true(isnan(dtm_elem_measure(29, tet4)));
  dtm_error_clear();
}

static void test_measure(void **state) {
  (void)state;
  near(dtm_elem_measure(DTM_LINE2, line2), 2, 1e-14, "line length");
  near(dtm_elem_measure(DTM_TRI3, tri3), 6, 1e-14, "triangle area 3*4/2");
  near(dtm_elem_measure(DTM_QUAD4, quad4), 6, 1e-14, "rectangle area");
  near(dtm_elem_measure(DTM_TET4, tet4), 1.0 / 6, 1e-14, "corner tet volume");
  near(dtm_elem_measure(DTM_HEX8, hex8), 24, 1e-14, "box volume");
  near(dtm_elem_measure(DTM_PRISM6, prism6), 1, 1e-14, "prism volume 1/2*2");
  near(dtm_elem_measure(DTM_PYR5, pyr5), 4.0 / 3, 1e-14, "pyramid base*h/3");
  /* An inverted tet (nodes 1 and 2 swapped) has negative measure. */
  double inv[12];
  memcpy(inv, tet4, sizeof inv);
  inv[3] = 0, inv[4] = 1, inv[6] = 1, inv[7] = 0;
  near(dtm_elem_measure(DTM_TET4, inv), -1.0 / 6, 1e-14, "inverted tet");
}

/* A general (non-parallelogram) quadrangle: area by the shoelace formula. */
static void test_measure_trapezoid(void **state) {
  (void)state;
  const double q[] = {0, 0, 0, 4, 0, 0, 3, 2, 0, 1, 2, 0};
  near(dtm_elem_measure(DTM_QUAD4, q), 6, 1e-14, "trapezoid (4+2)/2*2");
}

static void weights(int type, const double *x, int nn, const double *want) {
  double w[8];
  dtm_elem_lumped_weights(type, x, w);
  for (int a = 0; a < nn; a++) near(w[a], want[a], 1e-14, dtm_elem_name(type));
}

static void test_lumped_weights(void **state) {
  (void)state;
  const double half[] = {0.5, 0.5}, third[] = {1. / 3, 1. / 3, 1. / 3};
  const double quarter[] = {.25, .25, .25, .25};
  const double eighth[] = {.125, .125, .125, .125, .125, .125, .125, .125};
  const double sixth[] = {1. / 6, 1. / 6, 1. / 6, 1. / 6, 1. / 6, 1. / 6};
  /* Pyramid: integral of N_base = 1/4, of N_apex = 1/3 over V = 4/3. */
  const double pyr[] = {3. / 16, 3. / 16, 3. / 16, 3. / 16, 1. / 4};
  weights(DTM_LINE2, line2, 2, half);
  weights(DTM_TRI3, tri3, 3, third);
  weights(DTM_QUAD4, quad4, 4, quarter);
  weights(DTM_TET4, tet4, 4, quarter);
  weights(DTM_HEX8, hex8, 8, eighth);
  weights(DTM_PRISM6, prism6, 6, sixth);
  weights(DTM_PYR5, pyr5, 5, pyr);
}

static void test_moduli(void **state) {
  (void)state;
  dtm_elastic_moduli m;
  double E = 60e9, nu = 0.25, rho = 2700;
  double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, E, nu, rho, &m), DTM_OK);
  near(m.lam, lam, 1e-14, "lam");
  near(m.mu, mu, 1e-14, "mu");
  near(m.cd, sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu) * rho)), 1e-14, "C_D 3D from DESIGN.md");
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRAIN, E, nu, rho, &m), 0);
  near(m.modulus, lam + 2 * mu, 1e-14, "plane strain modulus");
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E, nu, rho, &m), 0);
  near(m.modulus, E / (1 - nu * nu), 1e-14, "plane stress modulus");
  near(m.cd, sqrt(E / (rho * (1 - nu * nu))), 1e-14, "plane stress C_D");
  near(m.lam, E * nu / (1 - nu * nu), 1e-14, "plane stress lam*");
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_BAR, E, nu, rho, &m), 0);
  near(m.modulus, E, 1e-14, "bar modulus");
  assert_true(m.lam == 0 && m.mu == 0);
  near(m.cd, sqrt(E / rho), 1e-14, "bar C_D");
}

static void test_moduli_errors(void **state) {
  (void)state;
  dtm_elastic_moduli m;
  const struct {
    double E, nu, rho;
    const char *word;
  } bad[] = {{0, 0.3, 1000, "E must"},    {-1, 0.3, 1000, "E must"},  {NAN, 0.3, 1000, "E must"},
             {1e9, 0.5, 1000, "nu must"}, {1e9, -1, 1000, "nu must"}, {1e9, INFINITY, 1000, "nu must"},
             {1e9, 0.3, 0, "rho must"},   {1e9, 0.3, -5, "rho must"}};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    dtm_error_clear();
    assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, bad[i].E, bad[i].nu, bad[i].rho, &m), DTM_ERR_INPUT);
    assert_non_null(strstr(dtm_error_message(), bad[i].word));
  }
  dtm_error_clear();
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_info),           cmocka_unit_test(test_unsupported),
      cmocka_unit_test(test_measure),        cmocka_unit_test(test_measure_trapezoid),
      cmocka_unit_test(test_lumped_weights), cmocka_unit_test(test_moduli),
      cmocka_unit_test(test_moduli_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
