/* Validity of curved tri6 and tet10 between their sampling points
 * (src/kernel/bezier.c, shape.c):
 *   - a hand-made tri6 and tet10 whose det J is positive at every node and
 *     at every point of the full rule (checked here) but negative inside
 *     (found by a search on a fine lattice; their minima, -0.026 and -0.045,
 *     were computed independently in numpy) are classified
 *     DTM_SHAPE_INSIDE with a negative scaled Jacobian;
 *   - straight-sided elements are proved valid with ratio 1 (det J is
 *     constant: every Bernstein coefficient equals it);
 *   - on mildly curved elements the bound holds: every value of det J on a
 *     lattice of points lies within [low, top] of the Bernstein
 *     coefficients, and the reported ratio is below the lattice's
 *     min / max;
 *   - other types are not handled (-2).
 * Tolerances: 1e-12 on ratios of O(1) values made of a few dozen
 * roundings; the lattice checks are inequalities with 1e-12 slack. */
#include <float.h>
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

/* Node sets (Gmsh order) of the reference triangle and tetrahedron with
 * two mid-edge nodes moved. */
static const double tri_bad[6 * 3] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.26, -0.284, 0, 0.5, 0.5, 0, 0.258, 0.356, 0};
static const double tet_bad[10 * 3] = {0,   0,   0, 1, 0,    0,    0, 1, 0,   0, 0,   1,   0.27, 0.13, 0.17,
                                       0.5, 0.5, 0, 0, 0.28, -0.1, 0, 0, 0.5, 0, 0.5, 0.5, 0.5,  0,    0.5};

/* Smallest det J over the nodes and the full rule's points. */
static double min_sampled(int type, const double *x) {
  int d, nn;
  double had, mn = INFINITY, p[3];
  dtm_qrule q;
  dtm_elem_info(type, &d, &nn);
  dtm_ref_rule(type, &q);
  for (int k = 0; k < q.n; k++) mn = fmin(mn, dtm_map_det(type, d, nn, (const double(*)[3])x, q.p[k], &had));
  for (int a = 0; a < nn; a++) {
    dtm_ref_node(type, a, p);
    mn = fmin(mn, dtm_map_det(type, d, nn, (const double(*)[3])x, p, &had));
  }
  return mn;
}

static void test_inverted_inside(void **state) {
  (void)state;
  const int types[2] = {DTM_TRI6, DTM_TET10};
  const double *xs[2] = {tri_bad, tet_bad};
  for (int t = 0; t < 2; t++) {
    dtm_shape s;
    assert_true(min_sampled(types[t], xs[t]) > 1e-3);
    assert_int_equal(dtm_kernel_shape(types[t], xs[t], &s), DTM_OK);
    if (s.status != DTM_SHAPE_INSIDE) fail_msg("%s: status %d", dtm_elem_name(types[t]), s.status);
    assert_true(s.min_jacobian < 0);
    assert_int_equal(s.node, -1);
    assert_non_null(strstr(dtm_shape_describe(s.status), "Bezier"));
  }
}

/* The reference element of type (d = 2 or 3), mid-edge nodes moved by
 * bend along a fixed pattern. */
static void curved(int type, double bend, double *x) {
  int nn, d;
  dtm_elem_info(type, &d, &nn);
  const double(*r)[3] = dtm_ref_nodes(type);
  for (int a = 0; a < nn; a++)
    for (int i = 0; i < 3; i++) x[3 * a + i] = r[a][i] + (a > d && i < d ? bend * sin(1.9 * a + 1.1 * i) : 0);
}

static void test_bounds_hold(void **state) {
  (void)state;
  const int types[2] = {DTM_TRI6, DTM_TET10};
  for (int t = 0; t < 2; t++)
    for (int k = 0; k <= 3; k++) {
      int d, nn;
      double x[30], ratio, had, lo = INFINITY, hi = -INFINITY, bend = 0.03 * k;
      dtm_elem_info(types[t], &d, &nn);
      curved(types[t], bend, x);
      assert_int_equal(dtm_elem_jacobian_bound(types[t], d, nn, (const double(*)[3])x, &ratio, NULL), 1);
      if (k == 0) assert_true(fabs(ratio - 1) <= 1e-12);
      const int n = 20;
      for (int i = 0; i <= n; i++)
        for (int j = 0; i + j <= n; j++)
          for (int l = 0; i + j + l <= (d == 3 ? n : i + j); l++) {
            double p[3] = {(double)i / n, (double)j / n, d == 3 ? (double)l / n : 0};
            double v = dtm_map_det(types[t], d, nn, (const double(*)[3])x, p, &had);
            lo = fmin(lo, v), hi = fmax(hi, v);
          }
      if (!(ratio <= lo / hi + 1e-12))
        fail_msg("%s bend %g: ratio %.17g above the lattice's %.17g", dtm_elem_name(types[t]), bend, ratio, lo / hi);
      if (k > 0) assert_true(ratio < 1 - 1e-3);
      dtm_shape s;
      assert_int_equal(dtm_kernel_shape(types[t], x, &s), DTM_OK);
      assert_int_equal(s.status, DTM_SHAPE_VALID);
    }
  double x[30], ratio;
  curved(DTM_TET10, 0, x);
  assert_int_equal(dtm_elem_jacobian_bound(DTM_HEX27, 3, 27, (const double(*)[3])x, &ratio, NULL), -2);
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_inverted_inside),
      cmocka_unit_test(test_bounds_hold),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
