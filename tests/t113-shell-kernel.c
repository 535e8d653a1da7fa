/* The flat facet Reissner-Mindlin shell kernel (src/kernel/structural.h,
 * shell.c) against closed forms and an independent code.
 *
 * Closed forms (docs/structural-kernels.md derives them):
 *   - rigid body modes: the 6 global rigid motions (u = c + w x X,
 *     theta = w) are in the null space of K, for both element types in a
 *     tilted plane; K is symmetric.
 *   - membrane: lambda_membrane equals dtm_kernel_elastic_lambda with
 *     plane-stress moduli (same element, t cancels).
 *   - bending: for a constant-curvature field (beta = (k_x x + k_xy y/2,
 *     k_y y + k_xy x/2), w = -(k_x x^2 + k_y y^2 + k_xy x y)/2 at the
 *     nodes), u^T K u = A k^T D_b k exactly: the shear strain vanishes at
 *     the quad's centre and in every MITC3 edge integral, and 2x2 Gauss
 *     (constant on tri3) integrates the bending energy exactly.
 *   - thickness shear, square quad4 of side h: the modes w = c x,
 *     beta = b (uniform) span an invariant subspace, with the eigenvalue
 *     12 k G/(rho t^2) (1 + t^2/(3 h^2)); the rest of the transverse
 *     problem is bending only, topped by the membrane value lambda_m =
 *     4E/((1-nu) rho h^2) (nu >= 0). So lambda_physical = max of the two
 *     and s = max(1, 12 k G/(rho t^2) / (lambda_m - 4 k G/(rho h^2))).
 *   - thickness shear, equilateral MITC3 triangle: as t/h -> 0,
 *     lambda_physical rho t^2/(k G) -> 15 (the top eigenvalue 5A/12 of the
 *     shear "mass" int Pi(N_a e_i) . Pi(N_b e_j) with w held, over the
 *     rotary inertia t^2/12 A/3).
 *   - scaled convention: s >= 1, lambda_scaled <= lambda_membrane
 *     (1 + 1e-10), and s agrees with a bisection on lambda_max(M(s)^-1 K)
 *     of the global matrices.
 *   - rotation invariance: an element turned and moved in 3D gives the
 *     same four numbers.
 * Tolerances: 1e-12 relative for closed forms and invariance (a few
 * hundred roundings on O(1) entries, Jacobi converged to eps^2); rigid
 * modes and symmetry 1e-12 of max|K| |r| (cancellation of entries of size
 * max|K|); 1e-7 for the thin-triangle limit (the O(t^2/h^2) correction is
 * 6e-9 at t/h = 1e-4); 1e-9 for s against a bisection to 1e-12.
 * The last test writes the kernel's results for 3 shapes x 3 thicknesses
 * and runs tests/reference/shell_ref.py (numpy, written independently),
 * which must agree to 1e-9 (it prints the table). */
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
#include "dtmap/kernel.h"
#include "kernel-impl.h"
#include "structural.h"
#include "testutil.h"

#include <unistd.h>

static const double E = 200e9, NU = 0.3, RHO = 7800, K5 = 5.0 / 6.0;

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

static dtm_shell_section section(double t) {
  dtm_shell_section s = {E, NU, RHO, t, 0};
  return s;
}

/* R = Rz(c) Ry(b) Rx(a), row-major. */
static void rotation(double a, double b, double c, double R[3][3]) {
  double ca = cos(a), sa = sin(a), cb = cos(b), sb = sin(b), cc = cos(c), sc = sin(c);
  double r[3][3] = {{cc * cb, cc * sb * sa - sc * ca, cc * sb * ca + sc * sa},
                    {sc * cb, sc * sb * sa + cc * ca, sc * sb * ca - cc * sa},
                    {-sb, cb * sa, cb * ca}};
  memcpy(R, r, sizeof r);
}

/* x[nn][3] = R (p, 0) + o for the planar points p[nn][2]. */
static void place(int nn, const double *p, const double R[3][3], const double *o, double *x) {
  for (int a = 0; a < nn; a++)
    for (int i = 0; i < 3; i++) x[3 * a + i] = R[i][0] * p[2 * a] + R[i][1] * p[2 * a + 1] + o[i];
}

static const double tri_p[6] = {0, 0, 1.1, 0.15, 0.35, 0.95};
static const double quad_p[8] = {0, 0, 1.2, 0, 0.9, 0.8, 0.1, 1.0}; /* not a parallelogram */
static const double square_p[8] = {-0.5, -0.5, 0.5, -0.5, 0.5, 0.5, -0.5, 0.5};
static const double origin[3] = {3, -2, 5};

static dtm_shell_lambda bounds(int type, double t, const double *x) {
  dtm_shell_section s = section(t);
  dtm_shell_lambda o;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_shell_lambda(type, &s, x, &o), DTM_OK);
  return o;
}

static dtm_struct_matrices matrices(int type, double t, const double *x, dtm_rotary_convention c) {
  dtm_shell_section s = section(t);
  dtm_struct_matrices m;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_shell_matrices(type, &s, x, c, &m), DTM_OK);
  return m;
}

static double kmax(int n, const double *K) {
  double k = 0;
  for (int i = 0; i < n * n; i++) k = fmax(k, fabs(K[i]));
  return k;
}

/* |K r|_inf for the rigid motion r (translation c, rotation w) of x. */
static double rigid_residual(const dtm_struct_matrices *m, const double *x, const double *c, const double *w) {
  int n = 6 * m->nn;
  double r[24], res = 0;
  for (int a = 0; a < m->nn; a++) {
    dtm_v3_cross(w, x + 3 * a, r + 6 * a);
    for (int i = 0; i < 3; i++) r[6 * a + i] += c[i], r[6 * a + 3 + i] = w[i];
  }
  for (int i = 0; i < n; i++) {
    double s = 0;
    for (int j = 0; j < n; j++) s += m->K[i * n + j] * r[j];
    res = fmax(res, fabs(s));
  }
  return res;
}

static void check_rigid(int type, const double *x) {
  for (int conv = 0; conv < 2; conv++) {
    dtm_struct_matrices m = matrices(type, 0.05, x, conv);
    int n = 6 * m.nn;
    double km = kmax(n, m.K), scale = 10; /* |r|_inf <= 1 + |X| ~ 10 */
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++)
        if (fabs(m.K[i * n + j] - m.K[j * n + i]) > 1e-13 * km) fail_msg("K not symmetric at %d %d", i, j);
    for (int k = 0; k < 6; k++) {
      double c[3] = {0, 0, 0}, w[3] = {0, 0, 0};
      (k < 3 ? c : w)[k % 3] = 1;
      double res = rigid_residual(&m, x, c, w);
      if (res > 1e-12 * km * scale) fail_msg("type %d rigid mode %d: |K r| = %g (max|K| %g)", type, k, res, km);
    }
  }
}

static void test_rigid_modes(void **state) {
  (void)state;
  double R[3][3], xt[9], xq[12];
  rotation(0.3, -1.1, 2.0, R);
  place(3, tri_p, R, origin, xt);
  place(4, quad_p, R, origin, xq);
  check_rigid(DTM_TRI3, xt);
  check_rigid(DTM_QUAD4, xq);
}

static void test_membrane(void **state) {
  (void)state;
  double R[3][3], xt[9], xq[12], le;
  dtm_elastic_moduli pm;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E, NU, RHO, &pm), DTM_OK);
  rotation(0.7, 0.4, -0.2, R);
  place(3, tri_p, R, origin, xt);
  place(4, quad_p, R, origin, xq);
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_TRI3, &pm, xt, &le), DTM_OK);
  near(bounds(DTM_TRI3, 0.02, xt).lambda_membrane, le, 1e-12, "tri3 membrane");
  assert_int_equal(dtm_kernel_elastic_lambda(DTM_QUAD4, &pm, xq, &le), DTM_OK);
  near(bounds(DTM_QUAD4, 0.3, xq).lambda_membrane, le, 1e-12, "quad4 membrane");
}

/* u^T K u of the constant-curvature field k[3] on the element x (planar
 * points p[nn][2], placed by R and origin). */
static double bending_energy(int type, int nn, const double *p, const double R[3][3], const double *k, double t) {
  double x[12], u[24] = {0}, U = 0;
  place(nn, p, R, origin, x);
  dtm_struct_matrices m = matrices(type, t, x, DTM_ROTARY_PHYSICAL);
  for (int a = 0; a < nn; a++) {
    double px = p[2 * a], py = p[2 * a + 1], bx = k[0] * px + k[2] * py / 2, by = k[1] * py + k[2] * px / 2;
    double wl = -(k[0] * px * px + k[1] * py * py + k[2] * px * py) / 2, rl[3] = {-by, bx, 0}; /* beta -> theta */
    for (int i = 0; i < 3; i++) {
      u[6 * a + i] = R[i][2] * wl;
      u[6 * a + 3 + i] = R[i][0] * rl[0] + R[i][1] * rl[1] + R[i][2] * rl[2];
    }
  }
  for (int i = 0; i < 6 * nn; i++)
    for (int j = 0; j < 6 * nn; j++) U += u[i] * m.K[i * 6 * nn + j] * u[j];
  return U;
}

static void test_bending_energy(void **state) {
  (void)state;
  double R[3][3], k[3] = {0.7, -0.4, 0.9}, t = 0.03;
  double Db = E * t * t * t / (12 * (1 - NU * NU));
  double kDk = Db * (k[0] * k[0] + k[1] * k[1] + 2 * NU * k[0] * k[1] + (1 - NU) / 2 * k[2] * k[2]);
  rotation(-0.5, 0.9, 1.3, R);
  near(bending_energy(DTM_QUAD4, 4, square_p, R, k, t), 1.0 * kDk, 1e-12, "square bending energy");
  double tri_area = 0.5 * (1.1 * 0.95 - 0.15 * 0.35);
  near(bending_energy(DTM_TRI3, 3, tri_p, R, k, t), tri_area * kDk, 1e-12, "tri3 bending energy");
}

static void test_thickness_shear_square(void **state) {
  (void)state;
  double R[3][3], x[12], h = 1, G = E / (2 * (1 + NU)), tr[4] = {0.01, 0.1, 0.5, 2};
  rotation(1.1, -0.3, 0.6, R);
  place(4, square_p, R, origin, x);
  for (int i = 0; i < 4; i++) {
    double t = tr[i] * h, lm = 4 * E / ((1 - NU) * RHO * h * h), lts0 = 12 * K5 * G / (RHO * t * t);
    double lts = lts0 * (1 + t * t / (3 * h * h)), s = fmax(1, lts0 / (lm - 4 * K5 * G / (RHO * h * h)));
    dtm_shell_lambda o = bounds(DTM_QUAD4, t, x);
    near(o.lambda_membrane, lm, 1e-12, "square membrane");
    near(o.lambda_physical, fmax(lm, lts), 1e-12, "square physical");
    near(o.scale, s, 1e-12, "square scale");
    near(o.lambda_scaled, lm, 1e-12, "square scaled");
  }
}

static void test_thickness_shear_triangle(void **state) {
  (void)state;
  double R[3][3], x[9], p[6] = {0, 0, 1, 0, 0.5, sqrt(3) / 2}, G = E / (2 * (1 + NU)), t = 1e-4;
  rotation(0.2, 0.5, -0.9, R);
  place(3, p, R, origin, x);
  near(bounds(DTM_TRI3, t, x).lambda_physical * RHO * t * t / (K5 * G), 15, 1e-7, "thin MITC3 limit");
}

/* lambda_max of the global problem with rotary masses times s. */
static double global_lambda(const dtm_struct_matrices *m, double s) {
  int n = 6 * m->nn;
  double a[576];
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++)
      a[i * n + j] = m->K[i * n + j] / sqrt(m->m[i] * (i % 6 >= 3 ? s : 1) * m->m[j] * (j % 6 >= 3 ? s : 1));
  return dtm_eig_sym_max(n, a);
}

static double bisect_scale(const dtm_struct_matrices *m, double target) {
  double lo = 1, hi = 1;
  if (global_lambda(m, 1) <= target) return 1;
  while (global_lambda(m, hi) > target) lo = hi, hi *= 2;
  while (hi - lo > 1e-12 * hi) {
    double mid = 0.5 * (lo + hi);
    if (global_lambda(m, mid) > target)
      lo = mid;
    else
      hi = mid;
  }
  return hi;
}

static void check_scaled(int type, const double *x, double t) {
  dtm_shell_lambda o = bounds(type, t, x);
  dtm_struct_matrices mp = matrices(type, t, x, DTM_ROTARY_PHYSICAL);
  dtm_struct_matrices ms = matrices(type, t, x, DTM_ROTARY_SCALED);
  assert_true(o.scale >= 1);
  assert_true(o.lambda_scaled <= o.lambda_membrane * (1 + 1e-10));
  near(global_lambda(&mp, 1), o.lambda_physical, 1e-11, "global physical");
  near(global_lambda(&ms, 1), o.lambda_scaled, 1e-11, "global scaled");
  /* the bisection's target carries 1e-12 of slack for the eigensolver's rounding */
  near(bisect_scale(&mp, o.lambda_membrane * (1 + 1e-12)), o.scale, 1e-9, "scale vs bisection");
  if (o.scale > 1) assert_true(global_lambda(&mp, o.scale * (1 - 1e-6)) > o.lambda_membrane);
}

static void test_scaled(void **state) {
  (void)state;
  double R[3][3], xt[9], xq[12], tr[4] = {0.01, 0.1, 0.5, 3};
  rotation(-1.2, 0.8, 0.1, R);
  place(3, tri_p, R, origin, xt);
  place(4, quad_p, R, origin, xq);
  for (int i = 0; i < 4; i++) check_scaled(DTM_TRI3, xt, tr[i]), check_scaled(DTM_QUAD4, xq, tr[i]);
}

static void same_bounds(dtm_shell_lambda a, dtm_shell_lambda b, const char *what) {
  near(b.lambda_membrane, a.lambda_membrane, 1e-12, what);
  near(b.lambda_physical, a.lambda_physical, 1e-12, what);
  near(b.lambda_scaled, a.lambda_scaled, 1e-12, what);
  near(b.scale, a.scale, 1e-12, what);
}

static void test_rotation_invariance(void **state) {
  (void)state;
  double R0[3][3], R1[3][3], x0[12], x1[12], zero[3] = {0, 0, 0};
  rotation(0, 0, 0, R0);
  rotation(2.1, -0.7, 0.4, R1);
  for (int type = DTM_TRI3; type <= DTM_QUAD4; type++) {
    int nn = type == DTM_TRI3 ? 3 : 4;
    const double *p = type == DTM_TRI3 ? tri_p : quad_p;
    place(nn, p, R0, zero, x0);
    place(nn, p, R1, origin, x1);
    same_bounds(bounds(type, 0.07, x0), bounds(type, 0.07, x1), "rotation invariance");
  }
}

static void test_errors(void **state) {
  (void)state;
  double x[12] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0}, xt[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  dtm_shell_section s = section(0.1);
  dtm_shell_lambda o;
  assert_int_equal(dtm_kernel_shell_lambda(DTM_TET4, &s, x, &o), DTM_ERR_INPUT);
  assert_int_equal(dtm_kernel_shell_lambda(DTM_TRI3, &s, xt, &o), DTM_ERR_INPUT); /* collinear */
  s.thickness = 0;
  assert_int_equal(dtm_kernel_shell_lambda(DTM_QUAD4, &s, x, &o), DTM_ERR_INPUT);
  s.thickness = 0.1, s.nu = 0.5;
  assert_int_equal(dtm_kernel_shell_lambda(DTM_QUAD4, &s, x, &o), DTM_ERR_INPUT);
  dtm_error_clear();
}

/* The Python with numpy and scipy: $DTM_TEST_PYTHON, else Debian's. */
static const char *python(void) {
  const char *p = getenv("DTM_TEST_PYTHON");
  if (p && *p) return p;
  return access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3" : "python3";
}

/* One line per case for shell_ref.py: type t nn coordinates, then the
 * four kernel numbers. */
static void write_case(FILE *f, const char *name, int type, const double *x, double t) {
  int nn = type == DTM_TRI3 ? 3 : 4;
  dtm_shell_lambda o = bounds(type, t, x);
  fprintf(f, "%s %d %.17g %.17g %.17g %.17g %.17g %.17g", name, type, E, NU, RHO, K5, t, dtm_elem_measure(type, x));
  for (int i = 0; i < 3 * nn; i++) fprintf(f, " %.17g", x[i]);
  fprintf(f, " %.17g %.17g %.17g %.17g\n", o.lambda_membrane, o.lambda_physical, o.lambda_scaled, o.scale);
}

static void test_reference(void **state) {
  (void)state;
  double R[3][3], xt[9], xs[12], xq[12], tr[3] = {0.01, 0.1, 0.5};
  char path[512], *out = NULL;
  rotation(0.3, -1.1, 2.0, R);
  place(3, tri_p, R, origin, xt);
  place(4, square_p, R, origin, xs);
  place(4, quad_p, R, origin, xq);
  snprintf(path, sizeof path, "%s/shell-cases.txt", tu_tmpdir());
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  for (int i = 0; i < 3; i++) {
    write_case(f, "tri3", DTM_TRI3, xt, tr[i] * sqrt(dtm_elem_measure(DTM_TRI3, xt)));
    write_case(f, "square", DTM_QUAD4, xs, tr[i] * sqrt(dtm_elem_measure(DTM_QUAD4, xs)));
    write_case(f, "quad4", DTM_QUAD4, xq, tr[i] * sqrt(dtm_elem_measure(DTM_QUAD4, xq)));
  }
  fclose(f);
  const char *py = python();
  if (tu_run(NULL, "'%s' -c 'import numpy, scipy'", py)) {
    print_message("skipped: %s has no numpy/scipy (set DTM_TEST_PYTHON)\n", py);
    skip();
  }
  int rc = tu_run(&out, "'%s' '%s/tests/reference/shell_ref.py' '%s'", py, tu_src(), path);
  for (char *line = out ? strtok(out, "\n") : NULL; line; line = strtok(NULL, "\n")) print_message("%s\n", line);
  free(out);
  assert_int_equal(rc, 0);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rigid_modes),
      cmocka_unit_test(test_membrane),
      cmocka_unit_test(test_bending_energy),
      cmocka_unit_test(test_thickness_shear_square),
      cmocka_unit_test(test_thickness_shear_triangle),
      cmocka_unit_test(test_scaled),
      cmocka_unit_test(test_rotation_invariance),
      cmocka_unit_test(test_errors),
      cmocka_unit_test(test_reference),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
