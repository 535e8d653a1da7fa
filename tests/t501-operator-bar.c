/* The global operator, Lanczos and the verification run on 1D meshes built
 * by hand, where everything has a closed form.
 *
 * Hand values. A bar of length L, modulus E, density rho, unit section:
 * lumped masses rho L/2, K = (E/L) [[1, -1], [-1, 1]], so M^-1 K has the
 * eigenvalues 0 and 4E/(rho L^2): dt = 2/sqrt(lambda) = L/c, c = sqrt(E/rho).
 * A free-free chain of N equal elements h (N + 1 nodes, end masses rho h/2,
 * inner ones rho h): u_j = cos(k pi j/N) satisfies the inner rows,
 * (E/h)(2 u_j - u_{j-1} - u_{j+1}) = lambda rho h u_j with
 * lambda_k = (2E/(rho h^2))(1 - cos(k pi/N)) = (4E/(rho h^2)) sin^2(k pi/(2N)),
 * and the end rows, (E/h)(u_0 - u_1) = lambda (rho h/2) u_0, because
 * 1 - cos(k pi/N) is the same factor; k = 0..N gives all N + 1 eigenvalues,
 * so lambda_max = 4E/(rho h^2) (k = N, u_j = (-1)^j), the single-element
 * value; the next one is lower by the factor cos^2(pi/(2N)). Scalar
 * diffusion on the same chain (capacity c, conductivity k) has the same
 * matrices with E -> k, rho -> c: lambda_max = 4k/(c h^2).
 * Central differences on a mode of frequency omega are stable for
 * omega dt < 2; with the damping force on the lagged velocity and
 * xi = beta omega/2 the limit is (2/omega)(sqrt(1 + xi^2) - xi). Forward
 * Euler is stable for lambda dt < 2.
 *
 * Tolerances. 1e-12 relative on the single bar: T is 2 x 2 and the
 * bisection gives its top eigenvalue to a few eps, so only a handful of
 * roundings separate theta from 4E/(rho L^2). The chain runs Lanczos to
 * tol 1e-10: the top gap is cos^2(pi/100) ~ 1 - 1e-3, far larger than the
 * residual, so the bracket [theta - r, theta + r] must hold lambda_max; the
 * dense Jacobi eigenvalue agrees with the closed form to 1e-12 (51 x 51,
 * eps-level Jacobi). Verification: 0.99 and 1.01 of the limit are 1%
 * away, so the unstable runs grow by at least 1.02 (undamped, Euler) or
 * 1.045 (damped) per step and pass 1e6 well within the 2000-4000 steps;
 * the stable runs stay below 100 (the undamped central-difference
 * amplitude at 0.99 of the limit, starting from rest, is about 7, the
 * energy norm about 10). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/operator.h"
#include "fixtures.h"

static const double E = 210e9, RHO = 7850, NU = 0.3;

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

/* A chain of n line2 elements from x = 0 to x = len, along x at y = z = 0. */
typedef struct {
  dtm_mesh m;
  dtm_block b;
  double *xyz;
  size_t *conn, *tags;
  int *mat;
} chain;

static void chain_init(chain *c, int n, double len) {
  memset(c, 0, sizeof *c);
  c->xyz = calloc(3 * (size_t)(n + 1), sizeof *c->xyz);
  c->conn = malloc(2 * (size_t)n * sizeof *c->conn);
  c->tags = malloc((size_t)n * sizeof *c->tags);
  c->mat = calloc((size_t)n, sizeof *c->mat);
  for (int i = 0; i <= n; i++) c->xyz[3 * i] = len * i / n;
  for (int e = 0; e < n; e++) {
    c->conn[2 * e] = (size_t)e, c->conn[2 * e + 1] = (size_t)e + 1;
    c->tags[e] = (size_t)e + 100;
  }
  c->b = (dtm_block){
      .type = DTM_LINE2, .dim = 1, .nn = 2, .n = (size_t)n, .tags = c->tags, .conn = c->conn, .mat = c->mat};
  c->m = (dtm_mesh){.dim = 1, .nnodes = (size_t)n + 1, .xyz = c->xyz, .nblocks = 1, .blocks = &c->b};
}

static void chain_free(chain *c) { free(c->xyz), free(c->conn), free(c->tags), free(c->mat); }

static dtm_operator_coeffs bar_coeffs(void) {
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO};
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_BAR, E, NU, RHO, &c.mod), DTM_OK);
  return c;
}

static dtm_operator *make(const chain *c, const dtm_operator_coeffs *k, const double *beta) {
  dtm_operator *op = NULL;
  dtm_error_clear();
  int r = dtm_operator_create(&c->m, k->kind, k, NULL, beta, 1, &op);
  if (r) fail_msg("create: %s", dtm_error_message());
  return op;
}

static dtm_lanczos_result lanczos(const dtm_operator *op, double tol, int maxit) {
  dtm_lanczos_result r;
  dtm_error_clear();
  if (dtm_lanczos_max(op, tol, maxit, 7, &r)) fail_msg("lanczos: %s", dtm_error_message());
  return r;
}

/* Largest eigenvalue of the dense M^-1/2 K M^-1/2, by unit vectors. */
static double dense_top(const dtm_operator *op) {
  double *a = tu_operator_dense(op, 1), top = dtm_eig_sym_max((int)dtm_operator_ndof(op), a);
  free(a);
  return top;
}

static void test_single_bar(void **state) {
  (void)state;
  const double L = 0.25, want = 4 * E / (RHO * L * L);
  chain c;
  chain_init(&c, 1, L);
  dtm_operator_coeffs k = bar_coeffs();
  dtm_operator *op = make(&c, &k, NULL);
  assert_int_equal(dtm_operator_ndof(op), 2);
  assert_int_equal(dtm_operator_ncomp(op), 1);
  assert_int_equal(dtm_operator_kind(op), DTM_OP_ELASTIC);
  near(dtm_operator_mass(op)[0], RHO * L / 2, 1e-14, "m0");
  near(dtm_operator_mass(op)[1], RHO * L / 2, 1e-14, "m1");
  double u[2] = {1, -1}, y[2];
  dtm_operator_apply(op, u, y);
  near(y[0], 2 * E / L, 1e-14, "K u");
  near(y[1], -2 * E / L, 1e-14, "K u");
  dtm_lanczos_result r = lanczos(op, 1e-12, 10);
  near(r.theta, want, 1e-12, "theta");
  near(2 / sqrt(r.theta), L / sqrt(E / RHO), 1e-12, "dt = L/c");
  assert_true(r.converged);
  assert_true(r.iterations <= 2);
  assert_true(r.residual <= 1e-12 * r.theta);
  assert_true(r.seconds >= 0);
  /* mode: u^T M u = 1, the alternating shape */
  const double *m = dtm_operator_mass(op);
  near(m[0] * r.mode[0] * r.mode[0] + m[1] * r.mode[1] * r.mode[1], 1, 1e-13, "uMu");
  near(r.mode[0], -r.mode[1], 1e-12, "mode shape");
  free(r.mode);
  dtm_operator_destroy(&op);
  assert_null(op);
  chain_free(&c);
}

static void test_chain(void **state) {
  (void)state;
  const int N = 50;
  const double L = 2, h = L / N, want = 4 * E / (RHO * h * h);
  chain c;
  chain_init(&c, N, L);
  dtm_operator_coeffs k = bar_coeffs();
  dtm_operator *op = make(&c, &k, NULL);
  near(dense_top(op), want, 1e-12, "dense lambda_max");
  dtm_lanczos_result r = lanczos(op, 1e-10, 200);
  print_message("chain: theta %.17g after %d steps, residual %.3g\n", r.theta, r.iterations, r.residual / r.theta);
  assert_true(r.converged);
  assert_true(r.residual <= 1e-10 * r.theta);
  assert_true(fabs(r.theta - want) <= r.residual + 1e-14 * want);
  near(r.theta, want, 1e-10, "theta");
  /* the Rayleigh quotient of the mode is theta, and u^T M u = 1 */
  size_t n = dtm_operator_ndof(op);
  double *ku = malloc(n * sizeof *ku), uku = 0, umu = 0;
  dtm_operator_apply(op, r.mode, ku);
  for (size_t i = 0; i < n; i++) uku += r.mode[i] * ku[i], umu += dtm_operator_mass(op)[i] * r.mode[i] * r.mode[i];
  near(umu, 1, 1e-12, "uMu");
  near(uku, r.theta, 1e-10, "Rayleigh quotient");
  /* without the mode: the same first pass, so the same theta bit for bit,
   * and Paige's estimate is the residual; the bracket still holds */
  dtm_lanczos_result q;
  assert_int_equal(dtm_lanczos_max_ex(op, 1e-10, 200, 7, 0, &q), 0);
  assert_null(q.mode);
  assert_true(q.theta == r.theta && q.iterations == r.iterations && q.converged);
  assert_true(fabs(q.theta - want) <= q.residual + 1e-14 * want);
  free(ku), free(r.mode);
  dtm_operator_destroy(&op);
  chain_free(&c);
}

/* Verification of the single bar at f x the limit, from its top mode. */
static dtm_verify_result verify_bar(double f, double xi, int steps) {
  const double L = 0.1;
  chain c;
  chain_init(&c, 1, L);
  dtm_operator_coeffs k = bar_coeffs();
  double w = sqrt(4 * E / (RHO * L * L)), beta = 2 * xi / w;
  dtm_operator *op = make(&c, &k, xi > 0 ? &beta : NULL);
  dtm_lanczos_result lr = lanczos(op, 1e-12, 10);
  near(sqrt(lr.theta), w, 1e-12, "omega");
  double dt = f * (2 / w) * (sqrt(1 + xi * xi) - xi);
  dtm_verify_result r;
  dtm_error_clear();
  if (dtm_verify_run(op, dt, steps, lr.mode, &r)) fail_msg("verify: %s", dtm_error_message());
  print_message("bar verify f=%.2f xi=%.1f: growth %.4g after %d steps%s\n", f, xi, r.growth, r.steps,
                r.unstable ? " (unstable)" : "");
  free(lr.mode);
  dtm_operator_destroy(&op);
  chain_free(&c);
  return r;
}

static void test_verify_bar(void **state) {
  (void)state;
  dtm_verify_result r = verify_bar(0.99, 0, 2000);
  assert_false(r.unstable);
  assert_int_equal(r.steps, 2000);
  assert_true(r.growth >= 1 && r.growth < 100);
  r = verify_bar(1.01, 0, 2000);
  assert_true(r.unstable);
  assert_true(r.growth > 1e6);
  assert_true(r.steps < 2000);
  /* Rayleigh beta with xi = 0.5 at the top frequency */
  r = verify_bar(0.99, 0.5, 2000);
  assert_false(r.unstable);
  assert_true(r.growth < 1);
  r = verify_bar(1.01, 0.5, 2000);
  assert_true(r.unstable);
  /* the undamped limit is unstable once damped this much */
  r = verify_bar(0.99 / (sqrt(1.25) - 0.5), 0.5, 2000);
  assert_true(r.unstable);
}

static void test_damping_apply(void **state) {
  (void)state;
  chain c;
  chain_init(&c, 3, 1);
  c.mat[1] = 1;
  dtm_operator_coeffs k[2] = {bar_coeffs(), bar_coeffs()};
  double alpha[2] = {3, 5}, beta[2] = {1e-6, 0}, v[4] = {1, -2, 0.5, 4}, y[4], ky[4];
  dtm_operator *op = NULL;
  dtm_error_clear();
  assert_int_equal(dtm_operator_create(&c.m, DTM_OP_ELASTIC, k, alpha, beta, 2, &op), 0);
  dtm_operator_apply_damping(op, v, y);
  /* by hand: element e has mass rho h/2 per node, stiffness E/h */
  double h = 1.0 / 3, m = RHO * h / 2, s = E / h;
  double al[4] = {3 * m, 3 * m + 5 * m, 5 * m + 3 * m, 3 * m};
  ky[0] = beta[0] * s * (v[0] - v[1]);
  ky[1] = beta[0] * s * (v[1] - v[0]);
  ky[2] = beta[0] * s * (v[2] - v[3]);
  ky[3] = beta[0] * s * (v[3] - v[2]);
  for (int i = 0; i < 4; i++) near(y[i], al[i] * v[i] + ky[i], 1e-14, "C v");
  dtm_operator_destroy(&op);
  /* undamped: C = 0 */
  assert_int_equal(dtm_operator_create(&c.m, DTM_OP_ELASTIC, k, NULL, NULL, 2, &op), 0);
  dtm_operator_apply_damping(op, v, y);
  for (int i = 0; i < 4; i++) assert_true(y[i] == 0);
  dtm_operator_destroy(&op);
  chain_free(&c);
}

static dtm_operator_coeffs heat(void) {
  return (dtm_operator_coeffs){.kind = DTM_OP_DIFFUSION, .capacity = 2.4e6, .conductivity = 3};
}

static void test_diffusion_chain(void **state) {
  (void)state;
  const int N = 50;
  const double L = 0.5, h = L / N;
  chain c;
  chain_init(&c, N, L);
  dtm_operator_coeffs k = heat();
  dtm_operator *op = make(&c, &k, NULL);
  assert_int_equal(dtm_operator_kind(op), DTM_OP_DIFFUSION);
  size_t n = dtm_operator_ndof(op);
  assert_int_equal(n, N + 1);
  double *one = malloc(n * sizeof *one), *y = malloc(n * sizeof *y), tot = 0;
  for (size_t i = 0; i < n; i++) one[i] = 1;
  dtm_operator_apply(op, one, y);
  for (size_t i = 0; i < n; i++) assert_true(fabs(y[i]) <= 1e-13 * 2 * k.conductivity / h);
  for (size_t i = 0; i < n; i++) tot += dtm_operator_mass(op)[i];
  near(tot, k.capacity * L, 1e-14, "total capacity");
  double want = 4 * k.conductivity / (k.capacity * h * h);
  dtm_lanczos_result lr = lanczos(op, 1e-10, 200);
  assert_true(lr.converged);
  near(lr.theta, want, 1e-10, "lambda_max diffusion");
  dtm_verify_result r;
  assert_int_equal(dtm_verify_run(op, 0.99 * 2 / lr.theta, 4000, lr.mode, &r), 0);
  assert_false(r.unstable);
  assert_true(r.growth < 1);
  assert_int_equal(dtm_verify_run(op, 1.01 * 2 / lr.theta, 4000, lr.mode, &r), 0);
  print_message("diffusion at 1.01: growth %.3g after %d steps\n", r.growth, r.steps);
  assert_true(r.unstable);
  free(one), free(y), free(lr.mode);
  dtm_operator_destroy(&op);
  chain_free(&c);
}

/* Nodes of no element get no mass, no force, and stay 0. */
static void test_orphan_node(void **state) {
  (void)state;
  chain c;
  chain_init(&c, 4, 1);
  c.b.n = 3; /* node 4 belongs to no element */
  dtm_operator_coeffs k = bar_coeffs();
  dtm_operator *op = make(&c, &k, NULL);
  assert_true(dtm_operator_mass(op)[4] == 0);
  double u[5] = {1, 2, 3, 4, 5}, y[5];
  dtm_operator_apply_sym(op, u, y);
  assert_true(y[4] == 0);
  dtm_lanczos_result lr = lanczos(op, 1e-12, 50);
  assert_true(lr.mode[4] == 0);
  near(lr.theta, 4 * E / (RHO * 0.25 * 0.25), 1e-10, "theta with orphan");
  free(lr.mode);
  dtm_operator_destroy(&op);
  chain_free(&c);
}

/* The chain as trusses in 3D: turned onto an oblique axis t, it spans 3D
 * space, so the operator has 3 unknowns per node and each element acts
 * along t only (stiffness (EA/h) t t^T, mass rho A h/2 per component).
 * The axial modes are the 1D chain's, the transverse ones have zero
 * stiffness, so lambda_max is the closed form 4E/(rho h^2) whatever the
 * area (section_factor): 1e-10, the Lanczos tolerance of the chain test,
 * and 1e-12 for the dense eigenvalue (eps-level Jacobi on 21 x 21). An
 * L-shaped chain (a right angle at its middle node) in the plane z = 0.25
 * spans 2D: 2 unknowns per node. Its middle node moves freely across each
 * leg, so it acts as an end with twice the mass and the alternating mode
 * is no longer exact: the top eigenvalue is below the element bound
 * 4E/(rho h^2) (to rounding, 1e-12) and above half of it (each leg alone
 * would reach it with a free end). */
static void test_trusses_in_space(void **state) {
  (void)state;
  chain c;
  chain_init(&c, 6, 1.5);
  const double t[3] = {2.0 / 7, 3.0 / 7, 6.0 / 7}; /* a unit vector, exactly in rationals */
  for (int i = 0; i <= 6; i++)
    for (int j = 0; j < 3; j++) c.xyz[3 * i + j] = 1.5 * i / 6 * t[j] + 0.1 * j;
  dtm_operator_coeffs k = bar_coeffs();
  k.section_factor = 3.1e-4;
  dtm_operator *op = make(&c, &k, NULL);
  assert_int_equal(dtm_operator_ncomp(op), 3);
  near(dtm_operator_mass(op)[0], RHO * 3.1e-4 * 0.25 / 2, 1e-14, "end node mass rho A h/2");
  dtm_lanczos_result lr = lanczos(op, 1e-12, 60);
  near(lr.theta, 4 * E / (RHO * 0.25 * 0.25), 1e-10, "oblique truss chain");
  near(dense_top(op), 4 * E / (RHO * 0.25 * 0.25), 1e-12, "oblique truss chain, dense");
  free(lr.mode);
  dtm_operator_destroy(&op);
  for (int i = 0; i <= 6; i++) { /* along x to node 3, then along y, in z = 0.25 */
    c.xyz[3 * i] = i <= 3 ? 0.25 * i : 0.75;
    c.xyz[3 * i + 1] = i <= 3 ? 0 : 0.25 * (i - 3);
    c.xyz[3 * i + 2] = 0.25;
  }
  op = make(&c, &k, NULL);
  assert_int_equal(dtm_operator_ncomp(op), 2);
  double top = dense_top(op);
  if (!(top <= 4 * E / (RHO * 0.25 * 0.25) * (1 + 1e-12) && top > 0.5 * 4 * E / (RHO * 0.25 * 0.25)))
    fail_msg("bent chain: top %.17g, element bound %.17g", top, 4 * E / (RHO * 0.25 * 0.25));
  dtm_operator_destroy(&op);
  chain_free(&c);
}

static void expect_error(const chain *c, int kind, const dtm_operator_coeffs *k, int code, const char *text) {
  dtm_operator *op = (dtm_operator *)1;
  dtm_error_clear();
  assert_int_equal(dtm_operator_create(&c->m, kind, k, NULL, NULL, 1, &op), code);
  assert_null(op);
  if (!strstr(dtm_error_message(), text)) fail_msg("message '%s' lacks '%s'", dtm_error_message(), text);
}

static void test_errors(void **state) {
  (void)state;
  chain c;
  chain_init(&c, 2, 1);
  dtm_operator_coeffs k = bar_coeffs(), k3 = k, kh = heat();
  c.xyz[3 * 1 + 1] = 1e-12; /* within 1e-9 of the size: still a 1D mesh */
  dtm_operator *op = make(&c, &k, NULL);
  assert_int_equal(dtm_operator_ncomp(op), 1);
  dtm_operator_destroy(&op);
  c.xyz[3 * 1 + 1] = 0;
  c.mat[1] = -1;
  expect_error(&c, DTM_OP_ELASTIC, &k, DTM_ERR_INPUT, "element 101");
  c.mat[1] = 0;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, E, NU, RHO, &k3.mod), 0);
  expect_error(&c, DTM_OP_ELASTIC, &k3, DTM_ERR_INPUT, "formulation");
  expect_error(&c, DTM_OP_ELASTIC, &kh, DTM_ERR_INTERNAL, "kind");
  kh.capacity = 0;
  expect_error(&c, DTM_OP_DIFFUSION, &kh, DTM_ERR_INPUT, "capacity");
  c.xyz[3] = 0; /* zero-length element */
  expect_error(&c, DTM_OP_ELASTIC, &k, DTM_ERR_INPUT, "element 100");
  c.xyz[3] = 0.5;
  op = make(&c, &k, NULL);
  dtm_lanczos_result lr;
  dtm_verify_result vr;
  double u[3] = {0, 0, 0};
  assert_int_equal(dtm_lanczos_max(op, 1e-3, 0, 1, &lr), DTM_ERR_INPUT);
  assert_null(lr.mode);
  assert_int_equal(dtm_verify_run(op, 0, 10, u, &vr), DTM_ERR_INPUT);
  assert_int_equal(dtm_verify_run(op, 1e-6, 10, u, &vr), DTM_ERR_INPUT); /* no energy */
  dtm_operator_destroy(&op);
  chain_free(&c);
  dtm_error_clear();
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_single_bar),      cmocka_unit_test(test_chain),
      cmocka_unit_test(test_verify_bar),      cmocka_unit_test(test_damping_apply),
      cmocka_unit_test(test_diffusion_chain), cmocka_unit_test(test_orphan_node),
      cmocka_unit_test(test_errors),          cmocka_unit_test(test_trusses_in_space),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
