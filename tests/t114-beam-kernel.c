/* The two-node Timoshenko beam kernel (src/kernel/structural.h, beam.c)
 * against closed forms (docs/structural-kernels.md derives them).
 *
 * For one element of length L (G = E/(2(1+nu)), I_p = I_y + I_z):
 *   - rigid body modes: the 6 global rigid motions are in the null space
 *     of K, which is symmetric; M is symmetric and its rotary blocks are
 *     R^T diag(I_p, I_y, I_z) R rho L/2.
 *   - axial: lambda_axial = 4E/(rho L^2).
 *   - torsion: theta = +/- e1 at the two nodes is an eigenvector with
 *     lambda = 4 G J_t/(rho I_p L^2) (K v = lambda M v, global axes).
 *   - bending plane with I: uniform rotation b and w = +/- c L/2 span an
 *     invariant subspace with lambda = 4kG/(rho L^2) + kGA/(rho s I); the
 *     antisymmetric rotation gives 4E/(s rho L^2). So lambda_physical =
 *     max(4E/(rho L^2), 4kG/(rho L^2) + kGA/(rho I_min), 4 G J_t/(rho I_p
 *     L^2)) and s = max(1, kGA L^2/(4 I_min (E - kG)), G J_t/(E I_p)).
 *   - constant moment: theta = kappa x e2-rotation, w with zero midpoint
 *     shear: u^T K u = E I_y kappa^2 L.
 *   - cantilever (node 0 clamped, tip load P along e3): one element gives
 *     P L^3/(4 E I_y) + P L/(kGA); N elements P L^3/(3 E I_y) (1 - 1/(4
 *     N^2)) + P L/(kGA), the Euler-Bernoulli value as N grows.
 *   - sections: circle; square J_t = 0.14057701495515... a^4 (Saint-Venant
 *     series, 40-digit reference); a 100:1 rectangle, where every tanh is
 *     1 in double, J_t = a c^3/3 (1 - (186/pi^5) zeta(5) c/a).
 *   - rotation invariance of the four numbers; default orientation.
 * Tolerances: 1e-12 relative (closed forms, a few roundings; Jacobi to
 * eps^2; the cantilever solves are well conditioned for these sections,
 * condition ~1e6, so 1e-9 there); rigid modes 1e-12 of max|K| |r|. */
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
#include "structural.h"

static const double E = 210e9, NU = 0.3, RHO = 7850, K5 = 5.0 / 6.0, PI = 3.14159265358979323846;

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

/* A 20 x 30 mm rectangle (b along e2, h along e3). */
static dtm_beam_section section(void) {
  dtm_beam_section s = {E, NU, RHO, 0, 0, 0, 0, 0, {0, 0, 0}, 0};
  assert_int_equal(dtm_beam_section_rect(0.02, 0.03, &s), DTM_OK);
  return s;
}

static const double x0[6] = {0.3, -0.2, 0.1, 0.6, 0.1, 0.45}; /* a skew beam */

static double length(const double *x) {
  double d[3];
  dtm_v3_sub(x + 3, x, d);
  return sqrt(dtm_v3_dot(d, d));
}

static dtm_beam_lambda bounds(const dtm_beam_section *s, const double *x) {
  dtm_beam_lambda o;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_beam_lambda(s, x, &o), DTM_OK);
  return o;
}

static dtm_struct_matrices matrices(const dtm_beam_section *s, const double *x, dtm_rotary_convention c) {
  dtm_struct_matrices m;
  dtm_error_clear();
  assert_int_equal(dtm_kernel_beam_matrices(s, x, c, &m), DTM_OK);
  return m;
}

static void mat_vec(int n, const double *A, const double *v, double *r) {
  for (int i = 0; i < n; i++) {
    r[i] = 0;
    for (int j = 0; j < n; j++) r[i] += A[i * n + j] * v[j];
  }
}

static void test_rigid_modes(void **state) {
  (void)state;
  dtm_beam_section s = section();
  dtm_struct_matrices m = matrices(&s, x0, DTM_ROTARY_PHYSICAL);
  double km = 0, r[12], Kr[12];
  for (int i = 0; i < 144; i++) km = fmax(km, fabs(m.K[i]));
  for (int i = 0; i < 12; i++)
    for (int j = 0; j < 12; j++) {
      assert_true(fabs(m.K[i * 12 + j] - m.K[j * 12 + i]) <= 1e-13 * km);
      assert_true(fabs(m.M[i * 12 + j] - m.M[j * 12 + i]) <= 1e-16 * m.m[0]);
    }
  for (int k = 0; k < 6; k++) {
    double c[3] = {0, 0, 0}, w[3] = {0, 0, 0};
    (k < 3 ? c : w)[k % 3] = 1;
    for (int a = 0; a < 2; a++) {
      dtm_v3_cross(w, x0 + 3 * a, r + 6 * a);
      for (int i = 0; i < 3; i++) r[6 * a + i] += c[i], r[6 * a + 3 + i] = w[i];
    }
    mat_vec(12, m.K, r, Kr);
    for (int i = 0; i < 12; i++)
      if (fabs(Kr[i]) > 1e-12 * km * 2) fail_msg("rigid mode %d: (K r)_%d = %g, max|K| %g", k, i, Kr[i], km);
  }
}

static void test_closed_forms(void **state) {
  (void)state;
  dtm_beam_section s = section();
  double L = length(x0), G = E / (2 * (1 + NU)), Ip = s.iy + s.iz, Imin = fmin(s.iy, s.iz);
  double lax = 4 * E / (RHO * L * L), lt = 4 * G * s.jt / (RHO * Ip * L * L);
  double lsh = 4 * K5 * G / (RHO * L * L) + K5 * G * s.area / (RHO * Imin);
  double sc = fmax(1, fmax(K5 * G * s.area * L * L / (4 * Imin * (E - K5 * G)), G * s.jt / (E * Ip)));
  for (int shorten = 0; shorten < 2; shorten++) { /* as given, and 100 times shorter: s = 1 */
    double x[6];
    for (int i = 0; i < 6; i++) x[i] = i < 3 ? x0[i] : x0[i - 3] + (x0[i] - x0[i - 3]) * (shorten ? 0.01 : 1);
    double f = shorten ? 1e4 : 1, sf = shorten ? fmax(1, sc * 1e-4) : sc;
    dtm_beam_lambda o = bounds(&s, x);
    near(o.lambda_axial, lax * f, 1e-13, "axial");
    near(o.lambda_physical, fmax(fmax(lax * f, lt * f), lsh + 4 * K5 * G / (RHO * L * L) * (f - 1)), 1e-12, "physical");
    near(o.scale, sf, 1e-12, "scale");
    near(o.lambda_scaled, lax * f, 1e-12, "scaled");
  }
}

static void test_torsion_mode(void **state) {
  (void)state;
  dtm_beam_section s = section();
  dtm_struct_matrices m = matrices(&s, x0, DTM_ROTARY_PHYSICAL);
  double L = length(x0), G = E / (2 * (1 + NU)), lt = 4 * G * s.jt / (RHO * (s.iy + s.iz) * L * L);
  double v[12] = {0}, Kv[12], Mv[12], scale = 0;
  for (int i = 0; i < 3; i++) v[3 + i] = m.axes[0][i], v[9 + i] = -m.axes[0][i];
  mat_vec(12, m.K, v, Kv);
  mat_vec(12, m.M, v, Mv);
  for (int i = 0; i < 12; i++) scale = fmax(scale, fabs(Kv[i]));
  for (int i = 0; i < 12; i++)
    if (fabs(Kv[i] - lt * Mv[i]) > 1e-12 * scale) fail_msg("torsion residual %g at %d", Kv[i] - lt * Mv[i], i);
}

static void test_constant_moment(void **state) {
  (void)state;
  dtm_beam_section s = section();
  dtm_struct_matrices m = matrices(&s, x0, DTM_ROTARY_PHYSICAL);
  double L = length(x0), kap = 0.37, u[12] = {0}, Ku[12], U = 0;
  for (int i = 0; i < 3; i++) {
    u[9 + i] = kap * L * m.axes[1][i];          /* theta_y(L) = kappa L about e2 */
    u[6 + i] = -kap * L * L / 2 * m.axes[2][i]; /* w(L): zero shear at the midpoint */
  }
  mat_vec(12, m.K, u, Ku);
  for (int i = 0; i < 12; i++) U += u[i] * Ku[i];
  near(U, E * s.iy * kap * kap * L, 1e-12, "constant-moment energy");
}

/* Solve A[n][n] x = b by Gaussian elimination with partial pivoting. */
static void solve(int n, double *A, double *b) {
  for (int k = 0; k < n; k++) {
    int p = k;
    for (int i = k + 1; i < n; i++)
      if (fabs(A[i * n + k]) > fabs(A[p * n + k])) p = i;
    for (int j = 0; j < n; j++) {
      double t = A[k * n + j];
      A[k * n + j] = A[p * n + j], A[p * n + j] = t;
    }
    double t = b[k];
    b[k] = b[p], b[p] = t;
    for (int i = k + 1; i < n; i++) {
      double f = A[i * n + k] / A[k * n + k];
      for (int j = k; j < n; j++) A[i * n + j] -= f * A[k * n + j];
      b[i] -= f * b[k];
    }
  }
  for (int i = n - 1; i >= 0; i--) {
    for (int j = i + 1; j < n; j++) b[i] -= A[i * n + j] * b[j];
    b[i] /= A[i * n + i];
  }
}

/* Tip deflection along e3 of a cantilever of ne elements, length L, along
 * x0's direction, node 0 clamped, load P along e3 at the tip. */
static double cantilever(const dtm_beam_section *s, int ne, double P, double *e3) {
  enum { NE = 8, N = 6 * NE };
  static double A[N * N];
  double b[N] = {0}, x[6];
  memset(A, 0, sizeof A);
  for (int e = 0; e < ne; e++) {
    for (int i = 0; i < 6; i++) x[i] = x0[i % 3] + (x0[3 + i % 3] - x0[i % 3]) * (e + i / 3) / (double)ne;
    dtm_struct_matrices m = matrices(s, x, DTM_ROTARY_PHYSICAL);
    memcpy(e3, m.axes[2], sizeof(double[3]));
    for (int i = 0; i < 12; i++)
      for (int j = 0; j < 12; j++) {
        int gi = 6 * e + i - 6, gj = 6 * e + j - 6; /* node 0 removed */
        if (gi >= 0 && gj >= 0) A[gi * 6 * ne + gj] += m.K[i * 12 + j];
      }
  }
  for (int i = 0; i < 3; i++) b[6 * (ne - 1) + i] = P * e3[i];
  solve(6 * ne, A, b);
  return dtm_v3_dot(b + 6 * (ne - 1), e3);
}

static void test_cantilever(void **state) {
  (void)state;
  dtm_beam_section s = section();
  double L = length(x0), G = E / (2 * (1 + NU)), P = 1e3, e3[3];
  double shear = P * L / (K5 * G * s.area), eb = P * L * L * L / (3 * E * s.iy);
  for (int ne = 1; ne <= 8; ne *= 2)
    near(cantilever(&s, ne, P, e3), eb * (1 - 1 / (4.0 * ne * ne)) + shear, 1e-9, "cantilever tip");
}

static void test_sections(void **state) {
  (void)state;
  dtm_beam_section s = section();
  assert_int_equal(dtm_beam_section_circle(0.1, &s), DTM_OK);
  near(s.area, PI * 0.01, 1e-15, "circle area");
  near(s.jt, PI * 1e-4 / 2, 1e-15, "circle J");
  near(s.iy, s.iz, 0, "circle I");
  assert_int_equal(dtm_beam_section_rect(2, 2, &s), DTM_OK);
  near(s.jt, 0.14057701495515371559 * 16, 1e-13, "square J"); /* mpmath, 40 digits */
  assert_int_equal(dtm_beam_section_rect(0.01, 1, &s), DTM_OK);
  double zeta5 = 1.0369277551433699263;
  near(s.jt, 1e-6 / 3 * (1 - 186 / pow(PI, 5) * zeta5 * 0.01), 1e-13, "thin rectangle J");
  near(s.iz, 1 * 1e-6 / 12, 1e-15, "rectangle I_z");
  near(s.iy, 0.01 / 12, 1e-15, "rectangle I_y");
}

static void test_rotation_invariance(void **state) {
  (void)state;
  dtm_beam_section s = section(), s2 = section();
  double R[3][3] = {{0.36, 0.48, -0.8}, {-0.8, 0.6, 0}, {0.48, 0.64, 0.6}}, x[6]; /* orthogonal */
  s.ref[0] = 0.2, s.ref[1] = -0.7, s.ref[2] = 0.4;
  for (int a = 0; a < 2; a++)
    for (int i = 0; i < 3; i++)
      x[3 * a + i] = 5 + R[i][0] * x0[3 * a] + R[i][1] * x0[3 * a + 1] + R[i][2] * x0[3 * a + 2];
  for (int i = 0; i < 3; i++) s2.ref[i] = R[i][0] * s.ref[0] + R[i][1] * s.ref[1] + R[i][2] * s.ref[2];
  dtm_beam_lambda a = bounds(&s, x0), b = bounds(&s2, x);
  near(b.lambda_axial, a.lambda_axial, 1e-12, "axial");
  near(b.lambda_physical, a.lambda_physical, 1e-12, "physical");
  near(b.lambda_scaled, a.lambda_scaled, 1e-12, "scaled");
  near(b.scale, a.scale, 1e-12, "scale");
}

static void test_orientation(void **state) {
  (void)state;
  dtm_beam_section s = section();
  double along_x[6] = {0, 0, 0, 2, 0, 0}, along_z[6] = {0, 0, 0, 0.01, 0, 2};
  dtm_struct_matrices m = matrices(&s, along_x, DTM_ROTARY_PHYSICAL);
  near(m.axes[1][2], 1, 1e-15, "default e2 = z");
  m = matrices(&s, along_z, DTM_ROTARY_PHYSICAL);
  assert_true(m.axes[1][1] > 0.999);
  s.ref[0] = 1;
  dtm_beam_lambda o;
  assert_int_equal(dtm_kernel_beam_lambda(&s, along_x, &o), DTM_ERR_INPUT); /* ref parallel */
  dtm_error_clear();
}

static void test_errors_and_infinite_scale(void **state) {
  (void)state;
  dtm_beam_section s = section();
  dtm_beam_lambda o;
  dtm_struct_matrices m;
  double same[6] = {1, 1, 1, 1, 1, 1};
  assert_int_equal(dtm_kernel_beam_lambda(&s, same, &o), DTM_ERR_INPUT);
  s.jt = 0;
  assert_int_equal(dtm_kernel_beam_lambda(&s, x0, &o), DTM_ERR_INPUT);
  s = section();
  s.k_shear = 3; /* k G = 1.15 E: no finite scale */
  o = bounds(&s, x0);
  double L = length(x0), G = E / (2 * (1 + NU));
  assert_true(isinf(o.scale));
  near(o.lambda_scaled, 4 * 3 * G / (RHO * L * L), 1e-12, "limit with rotations held");
  assert_int_equal(dtm_kernel_beam_matrices(&s, x0, DTM_ROTARY_SCALED, &m), DTM_ERR_INPUT);
  dtm_error_clear();
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rigid_modes),
      cmocka_unit_test(test_closed_forms),
      cmocka_unit_test(test_torsion_mode),
      cmocka_unit_test(test_constant_moment),
      cmocka_unit_test(test_cantilever),
      cmocka_unit_test(test_sections),
      cmocka_unit_test(test_rotation_invariance),
      cmocka_unit_test(test_orientation),
      cmocka_unit_test(test_errors_and_infinite_scale),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
