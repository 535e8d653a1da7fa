/* The natural modes of dtm_modes_lowest (src/spectral/modes.c) and their
 * comparison (modes_compare.c) against closed forms.
 * - A free bar of n equal trusses (steel: c = sqrt(E / rho), lumped mass:
 *   half a truss's mass at each end node): the chain's eigenvalues are
 *   exactly lambda_k = (2 c / h)^2 sin^2(k pi / 2n), k = 0 .. n, the k = 0
 *   one the rigid translation. The lowest 5 elastic ones must agree to 1e-9
 *   relative: the Lanczos test (DTM_MODES_TOL 1e-9 on the residual) leaves
 *   an eigenvalue error of order 1e-18 / gap, and the factorisation's
 *   rounding at the shift's condition (1e6) about 1e-10; the one rigid
 *   mode must be named and the residuals small (1e-8).
 * - One truss with a point mass P at one end (dtm_csr_point_masses): lambda
 *   = k (1 / m1 + 1 / (m2 + P)), k = EA / h = lambda_0 m1 / 2 from the
 *   unloaded closed form, m1 = m2 the operator's own lumped masses.
 * - dtm_modes_compare with every node's mass raised by a factor 1 + a (point
 *   masses a m_i): every frequency falls by exactly 1 / sqrt(1 + a), the
 *   shapes do not change, so each mode matches itself (MAC 1 to 1e-10)
 *   with a shift of 100 (1 / sqrt(1 + a) - 1) % (to 1e-7 %).
 * - dtm_csr_minus_lumped: M + P (a whole mass matrix) minus M is P again,
 *   entry for entry (exact: one subtraction of the same double).
 * - A plane-stress square of two triangles (8 unknowns): 3 rigid modes
 *   named, and with all 5 elastic modes asked for, every eigenvalue of
 *   M^-1/2 K M^-1/2 is found: their sum equals its trace and the largest its
 *   largest by cyclic Jacobi on the dense matrix (dtm_eig_sym_max), both to
 *   1e-9 relative (Jacobi is within a few eps of the norm; Lanczos within
 *   1e-18 / gap once the basis spans the whole space).
 * - Bad input: an extra mass of the wrong size, n < 1, and diffusion. */
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

#define E_STEEL 200e9
#define RHO 8000.0
#define H 0.05 /* truss length, m */
#define PI 3.14159265358979323846

static void near(double got, double want, double rel, const char *what) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s: got %.17g, want %.17g (rel %.3g, tol %g)", what, got, want, (got - want) / want, rel);
}

static dtm_operator *bar_operator(const dtm_mesh *m) {
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO};
  dtm_operator *op = NULL;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_BAR, E_STEEL, 0.3, RHO, &c.mod), 0);
  if (dtm_operator_create(m, DTM_OP_ELASTIC, &c, NULL, NULL, 1, &op)) fail_msg("create: %s", dtm_error_message());
  return op;
}

static dtm_mesh *bar(int n) {
  double *len = malloc((size_t)n * sizeof *len);
  for (int e = 0; e < n; e++) len[e] = H;
  dtm_mesh *m = tu_bar_mesh(n, len, NULL, NULL);
  free(len);
  return m;
}

static double chain(int n, int k) {
  double s = sin(k * PI / (2.0 * n));
  return 4 * E_STEEL / RHO / (H * H) * s * s;
}

static void test_free_bar(void **state) {
  (void)state;
  int n = 12;
  dtm_mesh *m = bar(n);
  dtm_operator *op = bar_operator(m);
  dtm_modes md;
  if (dtm_modes_lowest(op, NULL, 5, &md)) fail_msg("modes: %s", dtm_error_message());
  assert_true(md.converged);
  assert_int_equal(md.nrigid, 1);
  assert_int_equal(md.nelastic, 5);
  assert_int_equal(md.counted, 1);
  assert_int_equal(md.sturm, 6); /* the rigid mode and 5 elastic ones below 1 + 1e-6 times the fifth */
  assert_true(md.mode[0].rigid);
  assert_true(fabs(md.mode[0].lambda) <= 1e-10 * chain(n, 1));
  for (int k = 1; k <= 5; k++) {
    near(md.mode[k].lambda, chain(n, k), 1e-9, "bar eigenvalue");
    near(md.mode[k].freq, sqrt(chain(n, k)) / (2 * PI), 1e-9, "bar frequency");
    assert_false(md.mode[k].rigid);
    assert_true(md.mode[k].residual <= 1e-8);
  }
  print_message("bar of %d trusses: f1 = %.6f Hz, sigma = %.3g, %d steps, residuals %.2g .. %.2g\n", n, md.mode[1].freq,
                md.sigma, md.steps, md.mode[1].residual, md.mode[5].residual);
  dtm_modes_free(&md);
  dtm_operator_destroy(&op);
  dtm_mesh_destroy(&m);
}

static void test_point_mass(void **state) {
  (void)state;
  dtm_mesh *m = bar(1);
  dtm_operator *op = bar_operator(m);
  double m1 = dtm_operator_mass(op)[0], kg[2] = {0, 3.5 * m1};
  near(dtm_operator_mass(op)[1], m1, 1e-15, "equal end masses");
  dtm_csr pm;
  assert_int_equal(dtm_csr_point_masses(op, kg, 2, &pm), 0);
  dtm_modes md;
  if (dtm_modes_lowest(op, &pm, 1, &md)) fail_msg("modes: %s", dtm_error_message());
  double k = chain(1, 1) * m1 / 2;
  assert_int_equal(md.nrigid, 1);
  assert_int_equal(md.nelastic, 1);
  near(md.mode[1].lambda, k * (1 / m1 + 1 / (m1 + kg[1])), 1e-10, "spring-mass eigenvalue");
  dtm_modes_free(&md);
  if (dtm_modes_lowest(op, &pm, 5, &md)) fail_msg("modes: %s", dtm_error_message());
  assert_int_equal(md.nelastic, 1); /* more asked than the model has: all it has, converged */
  assert_true(md.converged);
  dtm_modes_free(&md);
  double whole[2] = {m1 + kg[0], dtm_operator_mass(op)[1] + kg[1]};
  size_t rowptr[3] = {0, 1, 2}, col[2] = {0, 1};
  dtm_csr full = {2, rowptr, col, whole}, back;
  assert_int_equal(dtm_csr_minus_lumped(op, &full, &back), 0);
  assert_int_equal(back.rowptr[2], 1); /* node 0's zero dropped */
  assert_int_equal(back.col[0], 1);
  assert_true(back.val[0] == (dtm_operator_mass(op)[1] + kg[1]) - dtm_operator_mass(op)[1]);
  dtm_csr_free(&back);
  dtm_csr_free(&pm);
  dtm_operator_destroy(&op);
  dtm_mesh_destroy(&m);
}

static void test_uniform_scaling(void **state) {
  (void)state;
  int n = 10;
  double a = 0.44;
  dtm_mesh *m = bar(n);
  dtm_operator *op = bar_operator(m);
  double *kg = malloc((size_t)(n + 1) * sizeof *kg);
  for (int v = 0; v <= n; v++) kg[v] = a * dtm_operator_mass(op)[v];
  dtm_csr pm;
  assert_int_equal(dtm_csr_point_masses(op, kg, (size_t)n + 1, &pm), 0);
  dtm_modes base, mod;
  assert_int_equal(dtm_modes_lowest(op, NULL, 4, &base), 0);
  assert_int_equal(dtm_modes_lowest(op, &pm, 4, &mod), 0);
  dtm_mode_shift sh[4];
  assert_int_equal(dtm_modes_compare(op, &base, &mod, sh), 0);
  for (int i = 0; i < 4; i++) {
    assert_int_equal(sh[i].base, i);
    assert_int_equal(sh[i].match, i);
    assert_true(fabs(sh[i].mac - 1) <= 1e-10);
    assert_true(fabs(sh[i].shift - 100 * (1 / sqrt(1 + a) - 1)) <= 1e-7);
  }
  free(kg);
  dtm_modes_free(&base), dtm_modes_free(&mod);
  dtm_csr_free(&pm);
  dtm_operator_destroy(&op);
  dtm_mesh_destroy(&m);
}

static void test_plane_square(void **state) {
  (void)state;
  double xyz[12] = {0, 0, 0, 0.1, 0, 0, 0.1, 0.1, 0, 0, 0.1, 0};
  size_t conn[6] = {0, 1, 2, 0, 2, 3}, tags[2] = {1, 2}, ntags[4] = {1, 2, 3, 4};
  int mat[2] = {0, 0};
  dtm_block b = {.type = DTM_TRI3, .dim = 2, .nn = 3, .n = 2, .tags = tags, .conn = conn, .mat = mat};
  dtm_mesh m = {.dim = 2, .nnodes = 4, .node_tags = ntags, .xyz = xyz, .nblocks = 1, .blocks = &b};
  dtm_operator_coeffs c = {.kind = DTM_OP_ELASTIC, .capacity = RHO};
  dtm_operator *op = NULL;
  assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_PLANE_STRESS, E_STEEL, 0.3, RHO, &c.mod), 0);
  if (dtm_operator_create(&m, DTM_OP_ELASTIC, &c, NULL, NULL, 1, &op)) fail_msg("create: %s", dtm_error_message());
  assert_int_equal(dtm_operator_ndof(op), 8);
  double *a = tu_operator_dense(op, 1), trace = 0, sum = 0;
  for (int j = 0; j < 8; j++) trace += a[9 * j];
  double top = dtm_eig_sym_max(8, a);
  dtm_modes md;
  if (dtm_modes_lowest(op, NULL, 5, &md)) fail_msg("modes: %s", dtm_error_message());
  assert_int_equal(md.nrigid, 3);
  assert_int_equal(md.nelastic, 5);
  for (int i = 0; i < md.n; i++) sum += md.mode[i].lambda;
  near(sum, trace, 1e-9, "sum of the eigenvalues");
  near(md.mode[md.n - 1].lambda, top, 1e-9, "largest eigenvalue");
  free(a);
  dtm_modes_free(&md);
  dtm_operator_destroy(&op);
}

static void test_refusals(void **state) {
  (void)state;
  dtm_mesh *m = bar(3);
  dtm_operator *op = bar_operator(m);
  dtm_modes md;
  dtm_csr pm;
  double kg[2] = {1, 1};
  assert_int_equal(dtm_csr_point_masses(op, kg, 2, &pm), 0);
  pm.n = 2; /* a matrix of another model */
  dtm_error_clear();
  assert_int_equal(dtm_modes_lowest(op, &pm, 2, &md), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "unknowns"));
  pm.n = 4;
  dtm_error_clear();
  assert_int_equal(dtm_modes_lowest(op, NULL, 0, &md), DTM_ERR_INPUT);
  dtm_error_clear();
  dtm_csr_free(&pm);
  dtm_operator_destroy(&op);
  dtm_operator_coeffs c = {.kind = DTM_OP_DIFFUSION, .capacity = 1, .conductivity = 1};
  assert_int_equal(dtm_operator_create(m, DTM_OP_DIFFUSION, &c, NULL, NULL, 1, &op), 0);
  assert_int_equal(dtm_modes_lowest(op, NULL, 2, &md), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "not elastic"));
  dtm_error_clear();
  dtm_operator_destroy(&op);
  dtm_mesh_destroy(&m);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_free_bar), cmocka_unit_test(test_point_mass),
                                     cmocka_unit_test(test_uniform_scaling), cmocka_unit_test(test_plane_square),
                                     cmocka_unit_test(test_refusals)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
