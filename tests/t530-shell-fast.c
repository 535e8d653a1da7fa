/* The faster path of the shell and beam bounds (issue 38; structural.h:
 * dtm_kernel_shell_bounds, dtm_kernel_beam_bounds, dtm_struct_eig_max,
 * dtm_section_element_screened) against the reference path it replaced in
 * the analysis (dtm_kernel_shell_physical and _scale, dtm_kernel_beam_lambda,
 * Householder + bisection), which stays callable:
 *   - the top eigenvalue of random symmetric positive semidefinite
 *     matrices of 1 to 24 unknowns, with simple, exactly double and nearly
 *     double (1e-7 apart) top eigenvalues, against
 *     dtm_eig_sym_max_tridiag;
 *   - lambda_membrane, s and lambda_physical of random flat tri3 and quad4
 *     shells (random shapes, orientations, Poisson's ratios, thickness
 *     ratios t/h from 1e-3 to 3, shear factors), of warped quad4 (corners
 *     off their mean plane, as on a curved surface) and of elements cut
 *     from a cylinder, and of random beams (circle and rectangle
 *     sections, orientations), both needs alone and together;
 *   - dtm_section_element under both rotary conventions (lambda, the
 *     scale, the translational and rotary masses of every node) against
 *     the numbers the reference kernels give;
 *   - the screen: lambda_physical is NaN exactly when a screen above it
 *     was proved, and the exact value below the screen.
 * Tolerance 1e-12 relative, the bound on how far the map may
 * move: both paths are backward stable on the same matrices (a few
 * hundred roundings, 1e-14) and the faster iteration stops within 2e-14
 * of the top eigenvalue. The certificates must fire on some elements (s =
 * 1 on thick ones) and not on others, so both branches are exercised. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/section.h"
#include "kernel-impl.h"
#include "structural.h"
#include "testutil.h"

#define TOL 1e-12

static double uniform(double a, double b) { return a + (b - a) * (rand() / (double)RAND_MAX); }

static void near(double got, double want, const char *what, int i) {
  if (isinf(want) && got == want) return;
  if (!(fabs(got - want) <= TOL * fabs(want)))
    fail_msg("%s (case %d): got %.17g, want %.17g (rel %.3g)", what, i, got, want, (got - want) / want);
}

/* A random orthogonal Q[n][n] (Gram-Schmidt of random columns). */
static void orthogonal(int n, double *Q) {
  for (int j = 0; j < n; j++) {
    for (int i = 0; i < n; i++) Q[i * n + j] = uniform(-1, 1);
    for (int k = 0; k < j; k++) {
      double d = 0;
      for (int i = 0; i < n; i++) d += Q[i * n + j] * Q[i * n + k];
      for (int i = 0; i < n; i++) Q[i * n + j] -= d * Q[i * n + k];
    }
    double r = 0;
    for (int i = 0; i < n; i++) r += Q[i * n + j] * Q[i * n + j];
    for (int i = 0; i < n; i++) Q[i * n + j] /= sqrt(r);
  }
}

static void test_eig_max(void **state) {
  (void)state;
  srand(530);
  for (int n = 1; n <= DTM_STRUCT_DOF; n++)
    for (int kind = 0; kind < 3; kind++)
      for (int r = 0; r < 40; r++) {
        double Q[DTM_STRUCT_DOF * DTM_STRUCT_DOF], A[DTM_STRUCT_DOF * DTM_STRUCT_DOF],
            B[DTM_STRUCT_DOF * DTM_STRUCT_DOF];
        double lam[DTM_STRUCT_DOF], scale = pow(10, uniform(-8, 12));
        orthogonal(n, Q);
        for (int k = 0; k < n; k++) lam[k] = uniform(0, 1);
        lam[0] = 1.5;
        if (n > 1 && kind) lam[1] = kind == 1 ? 1.5 : 1.5 * (1 - 1e-7);
        for (int i = 0; i < n; i++)
          for (int j = 0; j < n; j++) {
            double s = 0;
            for (int k = 0; k < n; k++) s += Q[i * n + k] * lam[k] * Q[j * n + k];
            A[i * n + j] = B[i * n + j] = scale * s;
          }
        double fast = dtm_struct_eig_max(n, A), ref = dtm_eig_sym_max_tridiag(n, B);
        near(fast, ref, "top eigenvalue", 1000 * n + 100 * kind + r);
        near(fast, 1.5 * scale, "top eigenvalue against its construction", 1000 * n + 100 * kind + r);
      }
  double nan[4] = {1, NAN, NAN, 1};
  assert_true(isnan(dtm_struct_eig_max(2, nan)));
}

/* A random shell element of type: a random shape of size about h,
 * turned and moved at random; warp: quad4 corners off their plane by
 * up to warp h. */
static void random_shell(int type, double h, double warp, double *x) {
  int nn = type == DTM_TRI3 ? 3 : 4;
  double p[4][3] = {{0, 0, 0}, {h, 0, 0}, {h, h, 0}, {0, h, 0}};
  if (nn == 3) p[2][0] = uniform(0.2, 0.8) * h;
  for (int a = 0; a < nn; a++) {
    p[a][0] += uniform(-0.2, 0.2) * h, p[a][1] += uniform(-0.2, 0.2) * h;
    if (nn == 4) p[a][2] = (a % 2 ? 1 : -1) * warp * h;
  }
  double ax[3] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}, th = uniform(0, 3), o[3] = {uniform(-5, 5), 1, 2};
  double r = sqrt(dtm_v3_dot(ax, ax)), c = cos(th), s = sin(th);
  for (int i = 0; i < 3; i++) ax[i] /= r;
  for (int a = 0; a < nn; a++) { /* Rodrigues' rotation of p[a] about ax by th */
    double cr[3], d = dtm_v3_dot(ax, p[a]);
    dtm_v3_cross(ax, p[a], cr);
    for (int i = 0; i < 3; i++) x[3 * a + i] = o[i] + p[a][i] * c + cr[i] * s + ax[i] * d * (1 - c);
  }
}

/* Corners of element k of a cylinder of radius 1 about y at size h. */
static void cylinder_shell(int type, double h, int k, double *x) {
  double a0 = 0.3 * k * h, y0 = 0.1 * k, ang[4] = {a0, a0 + h, a0 + h, a0}, y[4] = {y0, y0, y0 + h, y0 + h};
  if (type == DTM_TRI3) ang[2] = a0 + 0.5 * h;
  for (int a = 0; a < (type == DTM_TRI3 ? 3 : 4); a++)
    x[3 * a] = sin(ang[a]), x[3 * a + 1] = y[a], x[3 * a + 2] = cos(ang[a]);
}

/* The fast shell path against the reference path on one element; counts
 * the elements whose certificate gave s = 1 in *cert. */
static void compare_shell(int type, const dtm_shell_section *sec, const double *x, int i, int *cert) {
  double ref[3], refs[2], fast[3], fasts[3], m0[DTM_STRUCT_DOF], m1[DTM_STRUCT_DOF];
  int nn0, nn1;
  assert_int_equal(dtm_kernel_shell_physical(type, sec, x, ref, m0, &nn0), DTM_OK);
  assert_int_equal(dtm_kernel_shell_scale(type, sec, x, refs, m0, &nn0), DTM_OK);
  assert_int_equal(
      dtm_kernel_shell_bounds(type, sec, x, DTM_STRUCT_NEED_SCALE | DTM_STRUCT_NEED_PHYSICAL, 0, fast, m1, &nn1),
      DTM_OK);
  assert_int_equal(nn0, nn1);
  for (int k = 0; k < 6 * nn0; k++) near(m1[k], m0[k], "shell mass", i);
  near(fast[0], ref[0], "shell lambda_membrane", i);
  near(fast[1], ref[1], "shell s", i);
  near(fast[2], ref[2], "shell lambda_physical", i);
  assert_int_equal(dtm_kernel_shell_bounds(type, sec, x, DTM_STRUCT_NEED_SCALE, 0, fasts, m1, &nn1), DTM_OK);
  near(fasts[0], refs[0], "shell lambda_membrane (scale alone)", i);
  near(fasts[1], refs[1], "shell s (scale alone)", i);
  assert_int_equal(dtm_kernel_shell_bounds(type, sec, x, DTM_STRUCT_NEED_PHYSICAL, 0, fasts, m1, &nn1), DTM_OK);
  near(fasts[2], ref[2], "shell lambda_physical (physical alone)", i);
  /* the screen: NaN only when proved below it */
  assert_int_equal(dtm_kernel_shell_bounds(type, sec, x, DTM_STRUCT_NEED_PHYSICAL | DTM_STRUCT_NEED_SCALE,
                                           ref[2] * 0.999, fasts, m1, &nn1),
                   DTM_OK);
  near(fasts[2], ref[2], "shell lambda_physical above its screen", i);
  assert_int_equal(dtm_kernel_shell_bounds(type, sec, x, DTM_STRUCT_NEED_PHYSICAL | DTM_STRUCT_NEED_SCALE,
                                           ref[2] * 1.001, fasts, m1, &nn1),
                   DTM_OK);
  if (!isnan(fasts[2])) near(fasts[2], ref[2], "shell lambda_physical below its screen", i);
  if (!isnan(fasts[2]) && fasts[2] != fasts[0]) fail_msg("case %d: a screen above lambda_physical not proved", i);
  *cert += fast[1] == 1 && ref[2] == ref[0];
}

static void test_shells(void **state) {
  (void)state;
  int i = 0, cert = 0, total = 0;
  srand(38);
  for (int type = DTM_TRI3; type <= DTM_QUAD4; type++)
    for (int r = 0; r < 400; r++, i++, total++) {
      double x[12], h = pow(10, uniform(-3, 0)), ks[3] = {0, 1, 0.5};
      dtm_shell_section sec = {uniform(1e9, 3e11), uniform(-0.5, 0.49), uniform(1e3, 2e4),
                               h * pow(10, uniform(-3, log10(3))), ks[r % 3]};
      random_shell(type, h, type == DTM_QUAD4 && r % 2 ? uniform(0, 0.1) : 0, x);
      compare_shell(type, &sec, x, i, &cert);
    }
  for (int type = DTM_TRI3; type <= DTM_QUAD4; type++)
    for (int k = 0; k < 40; k++, i++, total++) {
      double x[12];
      dtm_shell_section sec = {210e9, 0.3, 7850, 0.005 * (1 + k % 4), 0};
      cylinder_shell(type, 0.005 * (1 + k % 5), k, x);
      compare_shell(type, &sec, x, i, &cert);
    }
  print_message("%d of %d elements settled by the certificate (s = 1)\n", cert, total);
  assert_true(cert > 0 && cert < total);
}

static void test_beams(void **state) {
  (void)state;
  srand(39);
  for (int i = 0; i < 400; i++) {
    dtm_beam_section b = {uniform(1e9, 3e11), uniform(-0.3, 0.49), uniform(1e3, 2e4), 0, 0, 0, 0, 0, {0, 0, 0}, i % 2};
    double L = pow(10, uniform(-3, 1)), x[6] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
    double dir[3] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}, n = sqrt(dtm_v3_dot(dir, dir));
    for (int k = 0; k < 3; k++) x[3 + k] = x[k] + L * dir[k] / n;
    if (i % 3 == 0)
      assert_int_equal(dtm_beam_section_circle(L * uniform(0.01, 0.5), &b), DTM_OK);
    else
      assert_int_equal(dtm_beam_section_rect(L * uniform(0.01, 0.5), L * uniform(0.01, 0.5), &b), DTM_OK);
    if (i % 4 == 1) b.ref[0] = 1, b.ref[1] = 0.3, b.ref[2] = -0.2;
    if (fabs(dtm_v3_dot(dir, b.ref)) > 0.99 * n * sqrt(dtm_v3_dot(b.ref, b.ref))) continue;
    dtm_beam_lambda ref;
    double fast[3], m0[12], m1[12], refs[2];
    assert_int_equal(dtm_kernel_beam_lambda(&b, x, &ref), DTM_OK);
    assert_int_equal(dtm_kernel_beam_scale(&b, x, refs, m0), DTM_OK);
    assert_int_equal(dtm_kernel_beam_bounds(&b, x, DTM_STRUCT_NEED_SCALE | DTM_STRUCT_NEED_PHYSICAL, 0, fast, m1),
                     DTM_OK);
    for (int k = 0; k < 12; k++) near(m1[k], m0[k], "beam mass", i);
    near(fast[0], ref.lambda_axial, "beam lambda_axial", i);
    near(fast[1], ref.scale, "beam s", i);
    near(fast[2], ref.lambda_physical, "beam lambda_physical", i);
    if (isfinite(ref.scale)) near(fast[0], ref.lambda_scaled, "beam lambda_scaled", i);
  }
}

/* dtm_section_element (the faster path) against the reference kernels'
 * numbers, under both conventions. */
static void test_section_element(void **state) {
  (void)state;
  srand(40);
  for (int i = 0; i < 200; i++) {
    int type = i % 2 ? DTM_QUAD4 : DTM_TRI3, nn = type == DTM_TRI3 ? 3 : 4;
    double x[12], h = pow(10, uniform(-3, 0)), E = 210e9, nu = 0.3, rho = 7850, ref[3], m[DTM_STRUCT_DOF];
    dtm_section s = {0};
    s.kind = DTM_SECTION_SHELL, s.thickness = h * pow(10, uniform(-2, 0.5)), s.rotary = i % 4 < 2;
    random_shell(type, h, type == DTM_QUAD4 ? 0.05 : 0, x);
    dtm_shell_section sh = {E, nu, rho, s.thickness, 0};
    int n0;
    assert_int_equal(dtm_kernel_shell_physical(type, &sh, x, ref, m, &n0), DTM_OK);
    dtm_section_bounds b, c;
    assert_int_equal(dtm_section_element(&s, type, E, nu, rho, x, &b), DTM_OK);
    int scaled = s.rotary == DTM_ROTARY_SCALED_INERTIA;
    near(b.lambda, scaled ? ref[0] : ref[2], "section lambda", i);
    near(b.lambda_physical, ref[2], "section lambda_physical", i);
    near(b.lambda_reference, ref[0], "section lambda_reference", i);
    near(b.scale, scaled ? ref[1] : 1, "section scale", i);
    for (int a = 0; a < nn; a++) {
      near(b.mt[a], m[6 * a], "section translational mass", i);
      near(b.mr[a], m[6 * a + 3] * (scaled ? ref[1] : 1), "section rotary inertia", i);
    }
    assert_int_equal(dtm_section_element_screened(&s, type, E, nu, rho, x, 2 * ref[2], &c), DTM_OK);
    near(c.lambda, b.lambda, "screened lambda", i);
    near(c.scale, b.scale, "screened scale", i);
    if (scaled && ref[2] > ref[0] * (1 + 1e-9) && !isnan(c.lambda_physical))
      fail_msg("case %d: lambda_physical computed below a screen twice its value", i);
    if (!scaled) near(c.lambda_physical, ref[2], "physical convention: never screened", i);
  }
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_eig_max),
      cmocka_unit_test(test_shells),
      cmocka_unit_test(test_beams),
      cmocka_unit_test(test_section_element),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
