/* The fast element bound (src/kernel/generic.c, affine.c, tridiag.c)
 * against the path it replaced, kept callable as
 * dtm_elastic_lambda_reference / dtm_diffusion_lambda_reference (set up,
 * check, then separate stiffness and mass passes, bisection on the
 * tridiagonal), on every type the generic path serves, straight-sided and
 * curved, random shapes, several Poisson ratios and the three integration
 * models; and the kept rule level through the kernel and the elastic
 * effect.
 *
 * Tolerances and their reasons:
 *  - 1e-12 relative between the fast and the reference bound (what the
 *    issue allows the map to move). The table pass is bitwise the
 *    reference's matrices; the affine shortcut of straight tri6 / tet10
 *    sums the same products in another order (a few eps per entry); the
 *    eigenvalue differs by the stopping of the tridiagonal's iteration (a
 *    few eps of |T|, |T| ~ lambda_max). The largest difference seen is
 *    printed.
 *  - straight elements with their mid-edge nodes moved by 0.9e-14 of the
 *    edge (just inside the affine tolerance): the shortcut ignores the
 *    move, which changes the bound by a small multiple of it; 1e-12 too.
 *  - equality (==) for the kept level against the searched one: the same
 *    rule, the same operations.
 *  - the tridiagonal's top by Laguerre against bisection: 1e-13 of the
 *    largest |eigenvalue| on random matrices with clustered and repeated
 *    tops (both are within a few eps of it). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/effect.h"
#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "assemble-impl.h"
#include "fixtures.h"
#include "kernel-impl.h"

extern const dtm_effect_class dtm_effect_elastic;

static const int types[] = {DTM_TRI6,    DTM_QUAD8, DTM_QUAD9, DTM_TET10, DTM_HEX20, DTM_HEX27,  DTM_PRISM15,
                            DTM_PRISM18, DTM_PYR13, DTM_PYR14, DTM_QUAD4, DTM_HEX8,  DTM_PRISM6, DTM_PYR5};
#define NTYPES (sizeof types / sizeof types[0])
#define TOL 1e-12

static uint64_t seed = 0x9e3779b97f4a7c15u;

static double urand(void) { /* uniform in [-1, 1) */
  seed = seed * 6364136223846793005u + 1442695040888963407u;
  return (double)(seed >> 11) / 4503599627370496.0 - 1;
}

static double worst; /* largest relative difference seen */

static void near(double got, double want, double tol, const char *what, int type) {
  double rel = fabs(got - want) / fabs(want);
  if (rel > worst) worst = rel;
  if (!(rel <= tol))
    fail_msg("%s %s: fast %.17g, reference %.17g (rel %.3g, tol %g)", dtm_elem_name(type), what, got, want, rel, tol);
}

/* A random element of type: corners of the regular element moved by up to
 * 15 % of h, the other nodes where the parent's map puts them, then moved
 * by up to curve h (0: straight-sided); 2D elements tilted out of the xy
 * plane. */
static void shape(int type, double curve, double *x) {
  int d, nn;
  dtm_elem_info(type, &d, &nn);
  assert_int_equal(tu_random_element(type, curve, urand, x), DTM_OK);
  if (d == 2) /* tilt: z = 0.3 x + 0.2 y, and shift away from the origin */
    for (int a = 0; a < nn; a++) x[3 * a + 2] = 0.3 * x[3 * a] + 0.2 * x[3 * a + 1] + 5;
}

static dtm_elastic_moduli moduli(int type, double nu, int model) {
  dtm_elastic_moduli m;
  int d;
  dtm_elem_info(type, &d, NULL);
  assert_int_equal(dtm_elastic_moduli_init(d == 3 ? DTM_FORM_3D : DTM_FORM_PLANE_STRAIN, 210e9, nu, 7850, &m), DTM_OK);
  m.integration = model;
  return m;
}

static double fast(int type, const dtm_elastic_moduli *m, const double *x, int level) {
  double l = NAN;
  if (dtm_elastic_lambda_at(type, m, x, level, &l)) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static double slow(int type, const dtm_elastic_moduli *m, const double *x) {
  double l = NAN;
  if (dtm_elastic_lambda_reference(type, m, x, &l)) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static void one(int type, double curve, const char *what) {
  static const double nus[] = {0.3, 0.0, -0.4, 0.49};
  double x[3 * DTM_K_NODES];
  shape(type, curve, x);
  for (int model = DTM_INTEGRATION_CONVERGED; model <= DTM_INTEGRATION_CALCULIX; model++)
    for (size_t k = 0; k < sizeof nus / sizeof nus[0]; k++) {
      dtm_elastic_moduli m = moduli(type, nus[k], model);
      near(fast(type, &m, x, -1), slow(type, &m, x), TOL, what, type);
    }
  double lf = NAN, lr = NAN;
  assert_int_equal(dtm_diffusion_lambda_generic(type, 1e-5, x, &lf), DTM_OK);
  assert_int_equal(dtm_diffusion_lambda_reference(type, 1e-5, x, &lr), DTM_OK);
  near(lf, lr, TOL, "diffusion", type);
}

static void fast_equals_reference(void **state) {
  (void)state;
  worst = 0;
  for (size_t t = 0; t < NTYPES; t++)
    for (int r = 0; r < 40; r++) {
      one(types[t], 0, "straight");
      if (dtm_elem_parent(types[t]) != types[t]) one(types[t], 0.08, "curved");
    }
  print_message("fast against reference bound: largest relative difference %.3g\n", worst);
}

/* Straight tri6 / tet10 with the mid-edge nodes off the middle by just
 * under the affine tolerance (1e-14 of the edge): still the shortcut. */
static void affine_tolerance(void **state) {
  (void)state;
  worst = 0;
  static const int simplex2[] = {DTM_TRI6, DTM_TET10};
  for (int t = 0; t < 2; t++)
    for (int r = 0; r < 200; r++) {
      int type = simplex2[t], nn, nc, d;
      double x[3 * DTM_K_NODES], xl[DTM_K_NODES][3], K[DTM_K_DOF * DTM_K_DOF], mass[DTM_K_NODES];
      dtm_elem_info(type, &d, &nn);
      nc = d + 1;
      shape(type, 0, x);
      const dtm_topology *tp = dtm_elem_topology(type);
      for (int a = nc; a < nn; a++) {
        const double *p = x + 3 * tp->edge[a - nc][0], *q = x + 3 * tp->edge[a - nc][1];
        double h = sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
        double u[3] = {urand(), urand(), d == 3 ? urand() : 0}, s = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int i = 0; i < 3; i++) x[3 * a + i] = 0.5 * (p[i] + q[i]) + 0.9e-14 * h * u[i] / s;
      }
      if (d == 2)
        for (int a = 0; a < nn; a++) x[3 * a + 2] = 0; /* keep it in its plane: the frame is the identity */
      assert_int_equal(dtm_elem_local(type, x, xl), 0);
      dtm_elastic_moduli m = moduli(type, 0.3, DTM_INTEGRATION_CONVERGED);
      assert_int_equal(dtm_affine_matrices(type, d, nn, (const double(*)[3])xl, &m, K, mass), 1);
      near(fast(type, &m, x, -1), slow(type, &m, x), TOL, "mid-nodes off by 0.9e-14", type);
    }
  print_message("affine shortcut at its tolerance: largest relative difference %.3g\n", worst);
}

/* The level kept by the analysis gives the searched level's bound bitwise,
 * and the elastic effect uses the level its batch hands it: a curved tet10
 * given level 0 gets the full rule's bound, not the converged one. */
static void kept_level(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t];
    if (dtm_elem_parent(type) == type) continue;
    double x[3 * DTM_K_NODES];
    dtm_qrule q;
    shape(type, 0.08, x);
    int level = dtm_ref_rule_elem(type, x, DTM_INTEGRATION_CONVERGED, &q);
    for (int model = DTM_INTEGRATION_CONVERGED; model <= DTM_INTEGRATION_CALCULIX; model++) {
      dtm_elastic_moduli m = moduli(type, 0.3, model);
      double searched = NAN, kept = NAN;
      assert_int_equal(dtm_kernel_elastic_lambda(type, &m, x, &searched), DTM_OK);
      assert_int_equal(dtm_kernel_elastic_lambda_at(type, &m, x, level, &kept), DTM_OK);
      if (!(kept == searched))
        fail_msg("%s model %d: kept level %.17g, searched %.17g", dtm_elem_name(type), model, kept, searched);
    }
  }
  double x[3 * DTM_K_NODES], dt[2], len[2], full = NAN, conv = NAN;
  dtm_qrule q;
  shape(DTM_TET10, 0.08, x);
  assert_true(dtm_ref_rule_elem(DTM_TET10, x, DTM_INTEGRATION_CONVERGED, &q) > 0);
  dtm_material mat;
  tu_material(&mat, "steel", "E", 210e9, "nu", 0.3, "rho", 7850.0, NULL);
  const dtm_material *mats[1] = {&mat};
  dtm_elastic_moduli m = moduli(DTM_TET10, 0.3, DTM_INTEGRATION_FULL);
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_TET10, &m, x, &full), DTM_OK);
  m.integration = DTM_INTEGRATION_CONVERGED;
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_TET10, &m, x, &conv), DTM_OK);
  assert_true(fabs(full / conv - 1) > 1e-9); /* the two models differ on this element */
  tu_effect_fixture f;
  void *st = NULL;
  tu_fixture_init(&f, "elastic", 3, NULL);
  assert_int_equal(dtm_effect_elastic.create(&f.args, &st), DTM_OK);
  dtm_batch b = tu_batch1(DTM_TET10, x, mats);
  assert_int_equal(dtm_effect_elastic.element_dt(st, &b, &dt[0], &len[0]), DTM_OK);
  unsigned char zero = 0;
  b.level = &zero; /* wrong on purpose: the full rule */
  assert_int_equal(dtm_effect_elastic.element_dt(st, &b, &dt[1], &len[1]), DTM_OK);
  dtm_effect_elastic.destroy(&st);
  if (!(dt[0] == 2 / sqrt(conv) && dt[1] == 2 / sqrt(full)))
    fail_msg("effect: %.17g %.17g, kernel %.17g %.17g", dt[0], dt[1], 2 / sqrt(conv), 2 / sqrt(full));
}

/* The shape check and the curvature measure of straight-sided tri6 and
 * tet10 take their one Jacobian (affine.c): valid, with the scaled
 * Jacobian of the corner simplex (1e-12: the same determinant and column
 * lengths summed in another order), ratio 1; an inverted one still goes
 * the sampled way and is refused. */
static void affine_shape(void **state) {
  (void)state;
  static const int simplex2[] = {DTM_TRI6, DTM_TET10}, parent[] = {DTM_TRI3, DTM_TET4};
  for (int t = 0; t < 2; t++)
    for (int r = 0; r < 100; r++) {
      int type = simplex2[t], d, nn;
      double x[3 * DTM_K_NODES];
      dtm_shape sh, lin;
      dtm_curvature c;
      dtm_elem_info(type, &d, &nn);
      shape(type, 0, x);
      assert_int_equal(dtm_kernel_shape(type, x, &sh), DTM_OK);
      assert_int_equal(dtm_kernel_shape(parent[t], x, &lin), DTM_OK);
      assert_int_equal(sh.status, DTM_SHAPE_VALID);
      near(sh.min_jacobian, lin.min_jacobian, TOL, "scaled Jacobian", type);
      assert_int_equal(dtm_kernel_curvature(type, x, &c), DTM_OK);
      assert_true(c.jac_ratio == 1 && c.level == 0);
      if (d == 3) { /* swap two corners and their edges' nodes: inverted */
        double y[3 * DTM_K_NODES];
        static const int perm[10] = {1, 0, 2, 3, 4,
                                     6, 5, 9, 8, 7}; /* corners 0 <-> 1: edges 1-2 <-> 0-2, 3-1 <-> 3-0 */
        for (int a = 0; a < 10; a++)
          for (int i = 0; i < 3; i++) y[3 * a + i] = x[3 * perm[a] + i];
        assert_int_equal(dtm_kernel_shape(type, y, &sh), DTM_OK);
        assert_int_equal(sh.status, DTM_SHAPE_FOLDED);
      }
    }
}

/* Random symmetric matrices A = Q diag(s) Q^T with a clustered or repeated
 * top, Q from Householder reflections. */
static void tridiagonal_top(void **state) {
  (void)state;
  double A[DTM_K_DOF * DTM_K_DOF], B[DTM_K_DOF * DTM_K_DOF], s[DTM_K_DOF], v[DTM_K_DOF];
  for (int r = 0; r < 400; r++) {
    int n = 13 + r % 69, kind = r % 4;
    for (int i = 0; i < n; i++) s[i] = urand();
    if (kind == 1) s[1] = s[2] = s[0] = 2;           /* a triple top */
    if (kind == 2) s[0] = 2, s[1] = 2 * (1 - 1e-9);  /* a close pair */
    if (kind == 3) s[0] = 2, s[1] = 2 * (1 - 1e-15); /* a pair to rounding */
    memset(A, 0, sizeof A);
    for (int i = 0; i < n; i++) A[i * n + i] = s[i];
    for (int h = 0; h < 3; h++) { /* A = H A H, H = I - 2 v v^T */
      double vv = 0;
      for (int i = 0; i < n; i++) v[i] = urand(), vv += v[i] * v[i];
      for (int i = 0; i < n; i++) v[i] /= sqrt(vv);
      double Av[DTM_K_DOF], vAv = 0;
      for (int i = 0; i < n; i++) {
        Av[i] = 0;
        for (int j = 0; j < n; j++) Av[i] += A[i * n + j] * v[j];
        vAv += v[i] * Av[i];
      }
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) A[i * n + j] += -2 * v[i] * Av[j] - 2 * Av[i] * v[j] + 4 * vAv * v[i] * v[j];
    }
    for (int i = 0; i < n; i++)
      for (int j = 0; j < i; j++) A[i * n + j] = A[j * n + i] = 0.5 * (A[i * n + j] + A[j * n + i]);
    double top = -INFINITY, big = 0;
    for (int i = 0; i < n; i++) top = fmax(top, s[i]), big = fmax(big, fabs(s[i]));
    memcpy(B, A, sizeof(double) * (size_t)(n * n));
    double f = dtm_eig_sym_max_tridiag(n, A), b = dtm_eig_sym_max_tridiag_bisect(n, B);
    if (!(fabs(f - b) <= 1e-13 * big)) fail_msg("n %d kind %d: Laguerre %.17g, bisection %.17g", n, kind, f, b);
    if (!(fabs(f - top) <= 1e-12 * big)) fail_msg("n %d kind %d: %.17g, exact %.17g", n, kind, f, top);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(fast_equals_reference), cmocka_unit_test(affine_tolerance), cmocka_unit_test(kept_level),
      cmocka_unit_test(affine_shape),          cmocka_unit_test(tridiagonal_top),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
