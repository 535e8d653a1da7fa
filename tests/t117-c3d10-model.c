/* The "calculix" discrete model of tet10 (src/kernel/curved.c, lump.c,
 * quadrature.c): CalculiX's C3D10 integration and lumping.
 *   - the 4-point rule integrates every monomial of degree <= 2 on the unit
 *     tetrahedron exactly (i! j! k! / (i + j + k + 3)!) and misses u^3 (so
 *     the check can fail), with positive weights;
 *   - on a straight-sided tet10 the lumped weights are CalculiX's closed
 *     form: corners alp / (4 (1 + alp)), mid-edge nodes 1 / (6 (1 + alp)),
 *     alp = 0.1203 (HRZ gives 1/36 and 4/27: the test tells them apart);
 *   - on a curved tet10 the masses sum to the 4-point measure and the
 *     corners carry alp / (1 + alp) of it;
 *   - the element eigenvalue of the unit right tet10, straight and with one
 *     mid-edge node moved, matches tests/reference/c3d10_element.py (its
 *     own shape functions, numpy);
 *   - other 3D types are integrated as under "converged" (bit for bit), and the
 *     model's name is "calculix".
 * Tolerances: 1e-15 absolute on monomial integrals (4 terms of O(0.1));
 * 1e-14 relative on weights and sums (a few roundings); 1e-12 relative on
 * the eigenvalues (two eigen-solvers, a 30 x 30 matrix). */
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

#define ALP 0.1203

static double fact(int n) { return n <= 1 ? 1 : n * fact(n - 1); }

static double rule_integral(const dtm_qrule *q, int i, int j, int k) {
  double s = 0;
  for (int a = 0; a < q->n; a++) s += q->w[a] * pow(q->p[a][0], i) * pow(q->p[a][1], j) * pow(q->p[a][2], k);
  return s;
}

static void test_rule(void **state) {
  (void)state;
  dtm_qrule q;
  assert_int_equal(dtm_ref_rule_level(DTM_TET10, DTM_K_RULE_C3D10, &q), DTM_K_RULE_C3D10);
  assert_int_equal(q.n, 4);
  for (int a = 0; a < 4; a++) assert_true(q.w[a] > 0);
  for (int i = 0; i <= 2; i++)
    for (int j = 0; i + j <= 2; j++)
      for (int k = 0; i + j + k <= 2; k++) {
        double ex = fact(i) * fact(j) * fact(k) / fact(i + j + k + 3), s = rule_integral(&q, i, j, k);
        if (!(fabs(s - ex) <= 1e-15)) fail_msg("u^%d v^%d w^%d: %.17g, exact %.17g", i, j, k, s, ex);
      }
  assert_true(fabs(rule_integral(&q, 3, 0, 0) - 1.0 / 120) > 1e-4); /* degree 3 is not exact */
}

/* The unit right tet10 (Gmsh node order), mid-edge node 4 moved by bend. */
static void unit_tet10(double bend, double *x) {
  static const double c[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  static const int e[6][2] = {{0, 1}, {1, 2}, {2, 0}, {3, 0}, {3, 2}, {3, 1}};
  memcpy(x, c, sizeof c);
  for (int k = 0; k < 6; k++)
    for (int i = 0; i < 3; i++) x[3 * (4 + k) + i] = 0.5 * (c[e[k][0]][i] + c[e[k][1]][i]);
  x[12] += 0.05 * bend, x[13] -= 0.08 * bend, x[14] += 0.03 * bend;
}

static void test_straight_weights(void **state) {
  (void)state;
  double x[30], w[10];
  unit_tet10(0, x);
  double vol = dtm_elem_lumped_model(DTM_TET10, x, DTM_INTEGRATION_CALCULIX, w);
  assert_true(fabs(vol - 1.0 / 6) <= 1e-15);
  for (int a = 0; a < 10; a++) {
    double ex = a < 4 ? ALP / (4 * (1 + ALP)) : 1 / (6 * (1 + ALP));
    if (!(fabs(w[a] - ex) <= 1e-14 * ex)) fail_msg("node %d: %.17g, CalculiX %.17g", a, w[a], ex);
  }
  dtm_elem_lumped_model(DTM_TET10, x, DTM_INTEGRATION_CONVERGED, w); /* HRZ, for contrast */
  assert_true(fabs(w[0] - 1.0 / 36) <= 1e-14 && fabs(w[4] - 4.0 / 27) <= 1e-14);
}

static void test_curved_sums(void **state) {
  (void)state;
  double x[30], w[10], se = 0, sm = 0;
  unit_tet10(1, x);
  double vol = dtm_elem_lumped_model(DTM_TET10, x, DTM_INTEGRATION_CALCULIX, w);
  assert_true(fabs(vol - 0.175) <= 1e-14); /* 4-point measure, tests/reference/c3d10_element.py */
  for (int a = 0; a < 10; a++) *(a < 4 ? &se : &sm) += w[a];
  assert_true(fabs(se + sm - 1) <= 1e-14);
  assert_true(fabs(se - ALP / (1 + ALP)) <= 1e-14);
  assert_true(fabs(w[4] - 0.1516033828807192) <= 1e-13 && fabs(w[5] - 0.14593596669826256) <= 1e-13);
}

static double lambda(int type, const double *x, int model) {
  dtm_elastic_moduli m;
  double l = NAN;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, 70e9, 0.3, 2700, &m), DTM_OK);
  m.integration = model;
  if (dtm_kernel_elastic_lambda(type, &m, x, &l)) fail_msg("%s", dtm_error_message());
  return l;
}

static void test_eigenvalues(void **state) {
  (void)state;
  static const double ref[2] = {3676014446.9400091, 3680235584.4416122}; /* c3d10_element.py */
  for (int b = 0; b < 2; b++) {
    double x[30];
    unit_tet10(b, x);
    double l = lambda(DTM_TET10, x, DTM_INTEGRATION_CALCULIX), lc = lambda(DTM_TET10, x, DTM_INTEGRATION_CONVERGED);
    print_message("bend %d: calculix %.17g, converged %.17g (%.3f %%)\n", b, l, lc, 100 * (l / lc - 1));
    if (!(fabs(l - ref[b]) <= 1e-12 * ref[b])) fail_msg("bend %d: %.17g, reference %.17g", b, l, ref[b]);
    assert_true(fabs(l - lc) > 1e-4 * lc); /* the two models differ */
  }
}

static void test_other_types(void **state) {
  (void)state;
  static const int types[] = {DTM_TET4, DTM_PRISM18, DTM_HEX27};
  for (size_t t = 0; t < 3; t++) {
    double x[3 * DTM_MAX_NODES];
    assert_int_equal(dtm_elem_regular(types[t], 1.0, x), DTM_OK);
    assert_true(lambda(types[t], x, DTM_INTEGRATION_CALCULIX) == lambda(types[t], x, DTM_INTEGRATION_CONVERGED));
  }
  assert_string_equal(dtm_integration_name(DTM_INTEGRATION_CALCULIX), "calculix");
  assert_string_equal(dtm_integration_name(7), "unknown");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rule),        cmocka_unit_test(test_straight_weights), cmocka_unit_test(test_curved_sums),
      cmocka_unit_test(test_eigenvalues), cmocka_unit_test(test_other_types),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
