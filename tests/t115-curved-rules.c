/* Curved second-order elements in the kernel (src/kernel/quadrature_level.c,
 * curved.c):
 *   - the levelled rules integrate every monomial of the degree they claim
 *     exactly (triangle 2n - 2, tetrahedron 2n - 3, 2n - 1 per variable on
 *     quadrangles and hexahedra, prisms both), n = 1 .. DTM_K_LEVEL_MAX,
 *     and their weights are positive;
 *   - straight-sided tri6 and tet10 (and quad9, hex27, prism18) give
 *     exactly (bit for bit) the numbers of the full rules: the element
 *     bound, the lumped weights and the measure;
 *   - on curved tri6 and tet10 the HRZ masses are exact: the same at the
 *     first level and at the last one (degree 6 and 7 integrands: both
 *     rules integrate them exactly), while the full rules miss them;
 *   - the element bound of the converged model agrees with the one
 *     integrated at the highest level to 1e-6 (the criterion) for
 *     several Poisson ratios, and differs from the full rules' one by more
 *     than that on these elements (so the check can fail);
 *   - the node offset is the mid-node's distance from the edge's middle
 *     over the edge length;
 *   - the memo of the level search (memo.c) answers the element map and
 *     the measure of an element searched just before, with the very bits
 *     of integrating it again (compared with the memo emptied), and holds
 *     every element of a chunk of 512 searched after 1,000 others.
 * Tolerances: 1e-14 of the reference measure (up to 8) on monomial
 * integrals (Gauss points and weights to a few ulps, at most 512 terms); 1e-13 relative on
 * exact masses (two exact rules, rounding of sums of <= 512 terms); 1e-6
 * relative for the converged bound (the criterion; curved.c proves
 * < 8e-7); 1e-15 on the offset (a few roundings of O(1) numbers). */
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

static double fact(int n) { return n <= 1 ? 1 : n * fact(n - 1); }

/* Exact integral of u^i v^j w^k over the reference element of type. */
static double exact(int type, int i, int j, int k) {
  double line_i = i % 2 ? 0 : 2.0 / (i + 1), line_j = j % 2 ? 0 : 2.0 / (j + 1), line_k = k % 2 ? 0 : 2.0 / (k + 1);
  switch (type) {
  case DTM_TRI6: return k ? 0 : fact(i) * fact(j) / fact(i + j + 2);
  case DTM_TET10: return fact(i) * fact(j) * fact(k) / fact(i + j + k + 3);
  case DTM_QUAD9: return k ? 0 : line_i * line_j;
  case DTM_HEX27: return line_i * line_j * line_k;
  default: return fact(i) * fact(j) / fact(i + j + 2) * line_k; /* prism */
  }
}

/* Whether the rule of level n claims u^i v^j w^k. */
static int claimed(int type, int n, int i, int j, int k) {
  switch (type) {
  case DTM_TRI6: return k == 0 && i + j <= 2 * n - 2;
  case DTM_TET10: return i + j + k <= 2 * n - 3;
  case DTM_QUAD9: return k == 0 && i <= 2 * n - 1 && j <= 2 * n - 1;
  case DTM_HEX27: return i <= 2 * n - 1 && j <= 2 * n - 1 && k <= 2 * n - 1;
  default: return i + j <= 2 * n - 2 && k <= 2 * n - 1;
  }
}

static void test_monomials(void **state) {
  (void)state;
  static const int types[] = {DTM_TRI6, DTM_TET10, DTM_QUAD9, DTM_HEX27, DTM_PRISM18};
  for (size_t t = 0; t < sizeof types / sizeof types[0]; t++)
    for (int n = 1; n <= DTM_K_LEVEL_MAX; n++) {
      dtm_qrule q;
      assert_int_equal(dtm_ref_rule_level(types[t], n, &q), n);
      for (int a = 0; a < q.n; a++) assert_true(q.w[a] > 0);
      for (int i = 0; i <= 15; i++)
        for (int j = 0; j <= 15; j++)
          for (int k = 0; k <= 15; k++) {
            if (!claimed(types[t], n, i, j, k)) continue;
            double s = 0;
            for (int a = 0; a < q.n; a++) s += q.w[a] * pow(q.p[a][0], i) * pow(q.p[a][1], j) * pow(q.p[a][2], k);
            if (!(fabs(s - exact(types[t], i, j, k)) <= 1e-14 * fmax(1, exact(types[t], 0, 0, 0))))
              fail_msg("%s level %d: u^%d v^%d w^%d gives %.17g, exact %.17g", dtm_elem_name(types[t]), n, i, j, k, s,
                       exact(types[t], i, j, k));
          }
    }
  dtm_qrule q;
  assert_int_equal(dtm_ref_rule_level(DTM_PYR14, 4, &q), 0); /* no levelled pyramid rule */
  assert_int_equal(q.n, 0);
}

/* An element of type: the regular one of edge 1, moved and sheared, with
 * its second-order nodes pushed off their straight place by bend (0:
 * straight) along a fixed pattern. */
static void element(int type, double bend, double *x) {
  int nn, nc;
  assert_int_equal(dtm_elem_regular(type, 1.0, x), DTM_OK);
  dtm_elem_info(type, NULL, &nn);
  dtm_elem_info(dtm_elem_parent(type), NULL, &nc);
  for (int a = 0; a < nn; a++) {
    double *p = x + 3 * a, y = p[1], z = p[2];
    p[0] += 0.3 * y + 0.1 * z + 1.5, p[1] += 0.2 * z - 0.7, p[2] += 2.0;
    if (a >= nc && dtm_elem_is_simplex(dtm_elem_parent(type)) && type != DTM_TRI6) {
      p[0] += bend * sin(1.3 * a), p[1] += bend * cos(0.7 * a), p[2] += bend * sin(2.1 * a + 0.4);
    } else if (a >= nc) {
      p[0] += bend * sin(1.3 * a), p[1] += bend * cos(0.7 * a);
    }
  }
}

static dtm_elastic_moduli moduli(int type, double nu, int model) {
  int d;
  dtm_elastic_moduli m;
  dtm_elem_info(type, &d, NULL);
  assert_int_equal(dtm_elastic_moduli_init(d == 3 ? DTM_FORM_3D : DTM_FORM_PLANE_STRAIN, 70e9, nu, 2700, &m), DTM_OK);
  m.integration = model;
  return m;
}

static double lambda(int type, const double *x, double nu, int model) {
  dtm_elastic_moduli m = moduli(type, nu, model);
  double l = NAN;
  dtm_error_clear();
  if (dtm_kernel_elastic_lambda(type, &m, x, &l)) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static void test_straight_unchanged(void **state) {
  (void)state;
  static const int types[] = {DTM_TRI6, DTM_TET10, DTM_QUAD9, DTM_HEX27, DTM_PRISM18};
  for (size_t t = 0; t < sizeof types / sizeof types[0]; t++) {
    double x[3 * DTM_MAX_NODES];
    element(types[t], 0, x);
    assert_true(dtm_elem_node_offset(types[t], (const double(*)[3])x) < 1e-12);
    for (double nu = 0; nu < 0.5; nu += 0.245)
      assert_true(lambda(types[t], x, nu, DTM_INTEGRATION_CONVERGED) == lambda(types[t], x, nu, DTM_INTEGRATION_FULL));
    dtm_elem_geom eg;
    double m[DTM_K_NODES], w[DTM_K_NODES];
    assert_int_equal(dtm_elem_setup(types[t], x, DTM_INTEGRATION_FULL, &eg), 0);
    double vol = dtm_lumped_mass(eg.type, eg.d, eg.nn, (const double(*)[3])eg.xl, &eg.q, m);
    /* tri6 and tet10 take the measure and the masses from det J and the
     * reference fractions (affine.c) instead of the rule's sum: equal to
     * rounding (1e-13 relative: sums of at most 14 rounded products); the
     * other types sum the same rule, bit for bit */
    int affine = types[t] == DTM_TRI6 || types[t] == DTM_TET10;
    double tol = affine ? 1e-13 : 0;
    assert_true(fabs(dtm_elem_measure(types[t], x) - vol) <= tol * fabs(vol));
    dtm_elem_lumped_weights(types[t], x, w);
    for (int a = 0; a < eg.nn; a++) assert_true(fabs(w[a] - m[a] / vol) <= tol * (m[a] / vol));
  }
}

/* Masses at the element's own rule and at level lv. */
static void masses(int type, const double *x, int model, int lv, double *m) {
  dtm_elem_geom eg;
  assert_int_equal(dtm_elem_setup(type, x, model, &eg), 0);
  if (lv) dtm_ref_rule_level(type, lv, &eg.q);
  dtm_elem_mass(&eg, m);
}

static void test_exact_masses(void **state) {
  (void)state;
  static const int types[] = {DTM_TRI6, DTM_TET10};
  for (size_t t = 0; t < 2; t++) {
    double x[3 * DTM_MAX_NODES], m[DTM_K_NODES], top[DTM_K_NODES], full[DTM_K_NODES], miss = 0;
    int nn;
    dtm_elem_info(types[t], NULL, &nn);
    element(types[t], 0.08, x);
    masses(types[t], x, DTM_INTEGRATION_CONVERGED, types[t] == DTM_TRI6 ? 4 : 5, m);
    masses(types[t], x, DTM_INTEGRATION_CONVERGED, DTM_K_LEVEL_MAX, top);
    masses(types[t], x, DTM_INTEGRATION_FULL, 0, full);
    for (int a = 0; a < nn; a++) {
      if (!(fabs(m[a] - top[a]) <= 1e-13 * top[a]))
        fail_msg("%s node %d: %.17g vs %.17g", dtm_elem_name(types[t]), a, m[a], top[a]);
      miss = fmax(miss, fabs(full[a] - top[a]) / top[a]);
    }
    print_message("%s: the full rule's HRZ masses are off by up to %.2e\n", dtm_elem_name(types[t]), miss);
    assert_true(miss > 1e-6); /* the element is curved enough to tell */
  }
}

/* The bound integrated at the highest level. */
static double lambda_top(int type, const double *x, double nu) {
  dtm_elem_geom eg;
  dtm_elastic_moduli m = moduli(type, nu, DTM_INTEGRATION_CONVERGED);
  double K[DTM_K_DOF * DTM_K_DOF], mass[DTM_K_NODES], l;
  assert_int_equal(dtm_elem_setup(type, x, DTM_INTEGRATION_CONVERGED, &eg), 0);
  dtm_ref_rule_level(type, DTM_K_LEVEL_MAX, &eg.q);
  dtm_elem_stiffness(&eg, &m, K);
  dtm_elem_mass(&eg, mass);
  for (int a = 0; a < eg.nn; a++) mass[a] *= m.rho;
  assert_int_equal(dtm_lumped_eig_max(type, eg.nn * eg.d, eg.d, K, mass, &l), DTM_OK);
  return l;
}

static void test_converged_bound(void **state) {
  (void)state;
  static const int types[] = {DTM_TRI6, DTM_TET10};
  static const double nus[] = {-0.5, 0, 0.3, 0.49};
  for (size_t t = 0; t < 2; t++)
    for (size_t i = 0; i < 4; i++) {
      double x[3 * DTM_MAX_NODES];
      element(types[t], 0.08, x);
      double lc = lambda(types[t], x, nus[i], DTM_INTEGRATION_CONVERGED), lt = lambda_top(types[t], x, nus[i]);
      double lf = lambda(types[t], x, nus[i], DTM_INTEGRATION_FULL);
      if (!(fabs(lc - lt) <= 1e-6 * lt))
        fail_msg("%s nu %g: converged %.17g, top level %.17g", dtm_elem_name(types[t]), nus[i], lc, lt);
      if (!(fabs(lf - lt) > 1e-6 * lt))
        fail_msg("%s nu %g: the full rule is already converged", dtm_elem_name(types[t]), nus[i]);
    }
}

static void test_offset(void **state) {
  (void)state;
  double x[3 * DTM_MAX_NODES];
  element(DTM_TRI6, 0, x);
  /* node 3 is the middle of edge 0-1: move it by 0.1 across the edge */
  double e[3] = {x[3] - x[0], x[4] - x[1], 0}, len = hypot(e[0], e[1]);
  x[9] += -0.1 * e[1] / len, x[10] += 0.1 * e[0] / len;
  double off = dtm_elem_node_offset(DTM_TRI6, (const double(*)[3])x);
  assert_true(fabs(off - 0.1 / len) <= 1e-15);
  assert_true(dtm_elem_node_offset(DTM_TET4, (const double(*)[3])x) == 0);
}

/* A tet10 whose edge 0-1 folds back at node 0 (its middle node at 0.22
 * of the edge: dx/dt = -0.12 there) is inverted at that node but positive
 * at the 14 points of the full rule (dtmap analyses and flags it); the
 * levelled rules reach the inverted region, so the converged model keeps
 * the full rule for it: the same bound, and not settled. */
static void test_corner_keeps_full(void **state) {
  (void)state;
  double x[30];
  const double(*r)[3] = dtm_ref_nodes(DTM_TET10);
  memcpy(x, r, sizeof x);
  x[3 * 4] = 0.22;
  dtm_shape s;
  assert_int_equal(dtm_kernel_shape(DTM_TET10, x, &s), DTM_OK);
  if (s.status != DTM_SHAPE_CORNER) fail_msg("status %d", s.status);
  assert_true(lambda(DTM_TET10, x, 0.3, DTM_INTEGRATION_CONVERGED) == lambda(DTM_TET10, x, 0.3, DTM_INTEGRATION_FULL));
  dtm_curvature c;
  assert_int_equal(dtm_kernel_curvature(DTM_TET10, x, &c), DTM_OK);
  assert_int_equal(c.level, 0);
  assert_int_equal(c.settled, 0);
}

/* The element bound at the kept level lv, the lumped weights and the
 * measure, into out[0], out[1 ..] and out[nn + 1]. */
static void kept_numbers(int type, const double *x, int lv, double *out) {
  dtm_elastic_moduli m = moduli(type, 0.3, DTM_INTEGRATION_CONVERGED);
  int nn;
  dtm_elem_info(type, NULL, &nn);
  assert_int_equal(dtm_kernel_elastic_lambda_at(type, &m, x, lv, &out[0]), DTM_OK);
  out[nn + 1] = dtm_elem_lumped_at(type, x, DTM_INTEGRATION_CONVERGED, lv, out + 1);
}

static void test_memo(void **state) {
  (void)state;
  static const int types[] = {DTM_TRI6, DTM_TET10};
  for (size_t t = 0; t < 2; t++) {
    double x[3 * DTM_MAX_NODES], rem, hit[DTM_K_NODES + 2], again[DTM_K_NODES + 2];
    int nn;
    dtm_elem_info(types[t], NULL, &nn);
    element(types[t], 0.08, x);
    dtm_memo_clear();
    int lv = dtm_ref_level_elem(types[t], x, &rem);
    assert_true(lv > 0);
    long h0 = dtm_memo_hits();
    kept_numbers(types[t], x, lv, hit);
    assert_int_equal(dtm_memo_hits() - h0, 2); /* the bound and the weights came from the memo */
    dtm_memo_clear();
    kept_numbers(types[t], x, lv, again);
    assert_int_equal(dtm_memo_hits() - h0, 2); /* integrated */
    assert_memory_equal(hit, again, (size_t)(nn + 2) * sizeof *hit);
  }
  /* a chunk of 512 curved tet10 searched after 1,000 others: each is
   * still there when the element map asks for it */
  double x[30], rem, out[12];
  int lv[512];
  dtm_memo_clear();
  for (int i = 0; i < 1512; i++) {
    element(DTM_TET10, 0.02 + 1e-5 * i, x);
    int l = dtm_ref_level_elem(DTM_TET10, x, &rem);
    assert_true(l > 0);
    if (i >= 1000) lv[i - 1000] = l;
  }
  long h0 = dtm_memo_hits();
  for (int i = 1000; i < 1512; i++) {
    element(DTM_TET10, 0.02 + 1e-5 * i, x);
    kept_numbers(DTM_TET10, x, lv[i - 1000], out);
  }
  print_message("memo: %ld of 1024 asked answered\n", dtm_memo_hits() - h0);
  assert_true(dtm_memo_hits() - h0 == 1024);
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_monomials),    cmocka_unit_test(test_straight_unchanged),
      cmocka_unit_test(test_exact_masses), cmocka_unit_test(test_converged_bound),
      cmocka_unit_test(test_offset),       cmocka_unit_test(test_corner_keeps_full),
      cmocka_unit_test(test_memo),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
