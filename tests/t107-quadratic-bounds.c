/* Element bounds of the second-order types (dtm_kernel_elastic_lambda and
 * dtm_kernel_diffusion_lambda through the generic quadrature + HRZ +
 * eigenvalue path): reference values, comparison with the linear parent,
 * invariances, the safe length, curved and invalid elements.
 *
 * Reference values, on the reference element of each type (Gmsh's
 * reference coordinates), lam = mu = rho = 1 (E = 2.5, nu = 0.25) and
 * alpha = 1: independent of dtmap, the nodal bases rebuilt by inverting
 * the Vandermonde matrix of Gmsh's function space at the nodes (sympy,
 * exact), the matrices integrated with Gauss rules of higher order than
 * dtmap's (5 points per direction, Duffy-collapsed on simplices and
 * pyramids) in 30-digit arithmetic (mpmath), HRZ lumping, mpmath's
 * symmetric eigensolver. tri6, quad8, quad9 and tet10 were also
 * integrated exactly in sympy, with the same values.
 * Tolerances: 1e-12 relative against the references (exact quadrature,
 * then an eigenvalue accurate to a small multiple of n eps for n <= 81);
 * 1e-12 for invariance under rotation and scaling by 1e-6 (rounding of
 * the assembly, amplified at most by the conditioning of a few dozen
 * sums); 1e-9 under translation (see there: the coordinates themselves are
 * rounded); factor 4 with 1e-13 for E x 4. */
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

static const int types[] = {DTM_TRI6,  DTM_QUAD9, DTM_TET10, DTM_HEX27,   DTM_PRISM18,
                            DTM_PYR14, DTM_QUAD8, DTM_HEX20, DTM_PRISM15, DTM_PYR13};
#define NTYPES (sizeof types / sizeof types[0])

static void near(double got, double want, double rel, const char *what, int type) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s %s: got %.17g, want %.17g (rel %.3g, tol %g)", dtm_elem_name(type), what, got, want,
             (got - want) / want, rel);
}

static int dim_of(int type) {
  int d = 0;
  dtm_elem_info(type, &d, NULL);
  return d;
}

static int nodes_of(int type) {
  int nn = 0;
  dtm_elem_info(type, NULL, &nn);
  return nn;
}

static void reference(int type, double *x) {
  for (int a = 0; a < nodes_of(type); a++) dtm_ref_node_uvw(type, a, x + 3 * a);
}

static dtm_elastic_moduli moduli(int type, double E, double nu, double rho) {
  dtm_elastic_moduli m;
  int f = dim_of(type) == 3 ? DTM_FORM_3D : DTM_FORM_PLANE_STRAIN;
  assert_int_equal(dtm_elastic_moduli_init(f, E, nu, rho, &m), DTM_OK);
  return m;
}

static double elastic(int type, const dtm_elastic_moduli *m, const double *x) {
  double l = NAN;
  dtm_error_clear();
  if (dtm_kernel_elastic_lambda(type, m, x, &l)) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static double diffusion(int type, double alpha, const double *x) {
  double l = NAN;
  dtm_error_clear();
  if (dtm_kernel_diffusion_lambda(type, alpha, x, &l)) fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  return l;
}

static void test_reference_values(void **state) {
  (void)state;
  static const struct {
    int type;
    double elastic, diffusion;
  } ref[] = {{DTM_TRI6, 163.4795314513835974485, 53.44661152927215566838},
             {DTM_QUAD8, 44.16089473648777202836, 20.05555555555555555556},
             {DTM_QUAD9, 25.2, 7.2},
             {DTM_TET10, 308.7004761163051102053, 101.5753482498959337283},
             {DTM_HEX20, 42.84055933070777543585, 22.88095238095238095238},
             {DTM_HEX27, 32.4, 9.0},
             {DTM_PRISM15, 273.6990369495602594907, 92.95830893995000030788},
             {DTM_PRISM18, 167.0485907450354399577, 55.11497648169570805788},
             {DTM_PYR13, 153.9468617615100573306, 55.41299049511888447443},
             {DTM_PYR14, 112.216146781731620032, 37.29067922119773364983}};
  for (size_t k = 0; k < sizeof ref / sizeof ref[0]; k++) {
    double x[3 * DTM_MAX_NODES];
    int type = ref[k].type;
    reference(type, x);
    dtm_elastic_moduli m = moduli(type, 2.5, 0.25, 1);
    assert_true(fabs(m.lam - 1) < 1e-15 && fabs(m.mu - 1) < 1e-15);
    near(elastic(type, &m, x), ref[k].elastic, 1e-12, "elastic reference", type);
    near(diffusion(type, 1, x), ref[k].diffusion, 1e-12, "diffusion reference", type);
  }
}

/* x = 1e-3 (A xi + b): a sheared, stretched image of the reference
 * element, of size ~1e-3 m near the origin (2D types stay in a plane
 * z = const), so its coordinates carry no rounding beyond eps of its size. */
static void affine(int type, const double *xi, double *x) {
  static const double A3[3][3] = {{2, 0.5, 0.25}, {0.5, 1.5, -0.5}, {0, 0.3, 1.2}};
  static const double A2[3][3] = {{2, 0.5, 0}, {0.25, 1.5625, 0}, {0, 0, 0}};
  static const double b[3] = {1, -2, 0.5};
  const double(*A)[3] = dim_of(type) == 3 ? A3 : A2;
  for (int a = 0; a < nodes_of(type); a++)
    for (int i = 0; i < 3; i++) {
      x[3 * a + i] = 1e-3 * b[i];
      for (int j = 0; j < 3; j++) x[3 * a + i] += 1e-3 * A[i][j] * xi[3 * a + j];
    }
}

/* A straight-sided second-order element has the parent's modes and more:
 * its bound must be at least the parent's. */
static void test_above_parent(void **state) {
  (void)state;
  const double nus[] = {0, 0.3, 0.49};
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], parent = dtm_elem_parent(type);
    double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES];
    reference(type, xi);
    for (int pass = 0; pass < 2; pass++) {
      if (pass)
        affine(type, xi, x);
      else
        memcpy(x, xi, sizeof x);
      for (size_t k = 0; k < sizeof nus / sizeof nus[0]; k++) {
        dtm_elastic_moduli m = moduli(type, 60e9, nus[k], 2700);
        double l2 = elastic(type, &m, x), l1 = elastic(parent, &m, x);
        if (!(l2 >= l1)) fail_msg("%s: %g < parent %g", dtm_elem_name(type), l2, l1);
      }
      double d2 = diffusion(type, 1e-6, x), d1 = diffusion(parent, 1e-6, x);
      if (!(d2 >= d1)) fail_msg("%s diffusion: %g < parent %g", dtm_elem_name(type), d2, d1);
    }
  }
}

/* R = rotation by angle t about the unit axis k (Rodrigues). */
static void rotation(const double k[3], double t, double R[3][3]) {
  double c = cos(t), s = sin(t), K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) R[i][j] = (i == j) * c + s * K[i][j] + (1 - c) * k[i] * k[j];
}

static void test_invariance(void **state) {
  (void)state;
  const double axis[3] = {2 / 3.0, -1 / 3.0, 2 / 3.0}, shift[3] = {-4, 250, 3.5};
  double R[3][3];
  rotation(axis, 0.7, R);
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], nn = nodes_of(type);
    double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES], y[3 * DTM_MAX_NODES];
    reference(type, xi);
    affine(type, xi, x);
    dtm_elastic_moduli m = moduli(type, 60e9, 0.25, 2700);
    dtm_elastic_moduli m4 = moduli(type, 240e9, 0.25, 2700);
    double l = elastic(type, &m, x), dl = diffusion(type, 1e-6, x);
    /* rotation about node 0 (a 2D element leaves its plane: only its own
     * frame matters) */
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < 3; i++) {
        y[3 * a + i] = x[i];
        for (int j = 0; j < 3; j++) y[3 * a + i] += R[i][j] * (x[3 * a + j] - x[j]);
      }
    near(elastic(type, &m, y), l, 1e-12, "rotated", type);
    near(diffusion(type, 1e-6, y), dl, 1e-12, "rotated diffusion", type);
    /* translation by up to 250 m of an element of size ~1e-3 m: the
     * shifted coordinates are rounded to eps x 250 = 6e-14 m, 6e-11 of the
     * element size, and lambda goes with 1/size^2: 1e-9 */
    for (int i = 0; i < 3 * nn; i++) y[i] = x[i] + shift[i % 3];
    near(elastic(type, &m, y), l, 1e-9, "translated", type);
    near(diffusion(type, 1e-6, y), dl, 1e-9, "translated diffusion", type);
    /* scaling by 1e-6: lambda by 1e12, dt = 2/sqrt(lambda) by 1e-6 */
    for (int i = 0; i < 3 * nn; i++) y[i] = 1e-6 * x[i];
    near(2 / sqrt(elastic(type, &m, y)), 1e-6 * 2 / sqrt(l), 1e-12, "scaled dt", type);
    near(diffusion(type, 1e-6, y), 1e12 * dl, 1e-12, "scaled diffusion", type);
    /* E x 4: c doubles, dt halves */
    near(2 / sqrt(elastic(type, &m4, x)), 0.5 * 2 / sqrt(l), 1e-13, "E x 4", type);
    near(diffusion(type, 4e-6, x), 4 * dl, 1e-13, "alpha x 4", type);
  }
}

/* DTM_LEN_SAFE / C_D never exceeds the element's own step for nu >= 0. */
static void test_safe_length(void **state) {
  (void)state;
  const double nus[] = {0, 0.25, 0.45, 0.499};
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t];
    double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES];
    reference(type, xi);
    affine(type, xi, x);
    double L = dtm_kernel_length(type, DTM_LEN_SAFE, x);
    for (size_t k = 0; k < sizeof nus / sizeof nus[0]; k++) {
      dtm_elastic_moduli m = moduli(type, 60e9, nus[k], 2700);
      double dt = 2 / sqrt(elastic(type, &m, x));
      if (!(L / m.cd <= dt * (1 + 1e-12)))
        fail_msg("%s nu %g: safe %g > dt %g", dtm_elem_name(type), nus[k], L / m.cd, dt);
    }
  }
}

static void expect_error(int type, const dtm_elastic_moduli *m, const double *x, const char *word) {
  double l = NAN;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_elastic_lambda(type, m, x, &l), DTM_ERR_INPUT);
  if (!strstr(dtm_error_message(), word))
    fail_msg("%s: message \"%s\" lacks \"%s\"", dtm_elem_name(type), dtm_error_message(), word);
  dtm_error_clear();
}

static void test_curved_and_invalid(void **state) {
  (void)state;
  double x[30], y[30];
  reference(DTM_TET10, x);
  dtm_elastic_moduli m = moduli(DTM_TET10, 60e9, 0.25, 2700);
  double straight = elastic(DTM_TET10, &m, x);
  /* curved: mid-edge node 4 (edge 0-1) pushed off its edge by 0.15 */
  memcpy(y, x, sizeof y);
  y[3 * 4 + 1] -= 0.15;
  double curved = elastic(DTM_TET10, &m, y);
  assert_true(isfinite(curved) && curved > 0 && curved != straight);
  double dc = diffusion(DTM_TET10, 1e-6, y);
  assert_true(isfinite(dc) && dc > 0);
  double w[10];
  dtm_elem_lumped_weights(DTM_TET10, y, w);
  for (int a = 0; a < 10; a++) assert_true(w[a] > 0);
  /* inverted: the mirror image x -> -x */
  memcpy(y, x, sizeof y);
  for (int a = 0; a < 10; a++) y[3 * a] = -x[3 * a];
  expect_error(DTM_TET10, &m, y, "degenerate or inverted");
  assert_true(dtm_elem_measure(DTM_TET10, y) < 0);
  double l;
  assert_int_equal(dtm_kernel_diffusion_lambda(DTM_TET10, 1, y, &l), DTM_ERR_INPUT);
  dtm_error_clear();
  /* tangled: mid-edge node 4 at 0.9 of edge 0-1 (beyond the 3/4 point the
   * edge map folds back and det J < 0 at node 1) */
  memcpy(y, x, sizeof y);
  y[3 * 4] = 0.9;
  expect_error(DTM_TET10, &m, y, "degenerate or inverted");
  assert_true(isnan(dtm_kernel_length(DTM_TET10, DTM_LEN_SAFE, y)));
  /* formulations: a tri6 is 2D, a tet10 3D */
  double t6[18];
  reference(DTM_TRI6, t6);
  dtm_elastic_moduli m3 = moduli(DTM_TET10, 1e9, 0.3, 1000);
  dtm_elastic_moduli m2 = moduli(DTM_TRI6, 1e9, 0.3, 1000);
  expect_error(DTM_TRI6, &m3, t6, "3d");
  expect_error(DTM_TET10, &m2, x, "plane-strain");
  /* a collapsed hex20 (top face on the bottom one) */
  double h[60];
  reference(DTM_HEX20, h);
  for (int a = 0; a < 20; a++) h[3 * a + 2] = 0;
  expect_error(DTM_HEX20, &m3, h, "degenerate or inverted");
}

/* Plane stress on flat tri6, quad8 and quad9 elements rotated out of the
 * xy plane: the element frame (built on the corners) gives the values of
 * the element in the xy plane. */
static void test_plane_stress_tilted(void **state) {
  (void)state;
  const int t2[] = {DTM_TRI6, DTM_QUAD8, DTM_QUAD9};
  const double axis[3] = {0.6, 0, 0.8};
  double R[3][3];
  rotation(axis, 1.1, R);
  for (int t = 0; t < 3; t++) {
    double x[27], y[27];
    dtm_elastic_moduli m;
    assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, 70e9, 0.33, 2700, &m), 0);
    reference(t2[t], x);
    for (int a = 0; a < nodes_of(t2[t]); a++)
      for (int i = 0; i < 3; i++) {
        y[3 * a + i] = 0;
        for (int j = 0; j < 3; j++) y[3 * a + i] += R[i][j] * x[3 * a + j];
      }
    near(elastic(t2[t], &m, y), elastic(t2[t], &m, x), 1e-12, "tilted plane stress", t2[t]);
  }
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reference_values),   cmocka_unit_test(test_above_parent),
      cmocka_unit_test(test_invariance),         cmocka_unit_test(test_safe_length),
      cmocka_unit_test(test_curved_and_invalid), cmocka_unit_test(test_plane_stress_tilted),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
