/* The global operator keeps the element matrices of curved tet10 instead of
 * their points (issue 46; src/spectral/operator.c, stores_matrices), on a
 * real Gmsh mesh: a unit ball of OpenCASCADE meshed at 0.35 and raised to
 * second order, its mid-edge nodes on the sphere, analysed by dtmap (the
 * converged integration: the curved elements settle at high levels of
 * their rule). The operator built the default way and the one keeping
 * points everywhere (dtm_operator_store 0):
 * - the default stores matrices for some elements, the other for none;
 * - the lumped masses are bitwise the same (the same sums of dv);
 * - products agree to 1e-12 of the largest |entry| of the result (each
 *   element's forces are the same integrals over the same points, summed
 *   in another order: some hundred roundings of terms below that size);
 * - the global estimate is proven by the factorisation either way
 *   (DTM_CERT_PROVEN) and its bound, theta + residual, agrees to 1e-9
 *   (Lanczos to 1e-8: the two Krylov spaces agree up to rounding, and
 *   each bound includes its factorisation's rounding margin). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/gmsh.h"
#include "dtmap/operator.h"
#include "spectral.h"
#include "testutil.h"

static dtm_scene *scene;

static void setup_scene(void) {
  char path[600];
  snprintf(path, sizeof path, "%s/ball.geo", tu_tmpdir());
  tu_write(path, "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 1};\nPhysical Volume(\"block\") = {1};\n");
  tu_steel_scene("ball", "<geometry file=\"ball.geo\"/>", "size=\"0.35\" order=\"2\"", "");
  snprintf(path, sizeof path, "%s/ball.xml", tu_tmpdir());
  assert_int_equal(dtm_scene_load(path, &scene), 0);
}

static double max_abs(size_t n, const double *y) {
  double m = 0;
  for (size_t i = 0; i < n; i++) m = fmax(m, fabs(y[i]));
  return m;
}

static void stored_against_points(void **unused) {
  dtm_analysis *a = NULL;
  dtm_operator *ms = NULL, *pts = NULL;
  assert_int_equal(dtm_analysis_run(scene, &a), 0);
  assert_int_equal(dtm_analysis_operator(a, 0, 0.0, &ms), 0);
  dtm_operator_store = 0;
  int r = dtm_analysis_operator(a, 0, 0.0, &pts);
  dtm_operator_store = 1;
  assert_int_equal(r, 0);
  size_t n = dtm_operator_ndof(ms), ne = dtm_mesh_nelements(a->mesh), stored = dtm_operator_stored(ms);
  print_message("%zu of %zu tet10 stored as matrices\n", stored, ne);
  assert_true(stored > 0 && stored < ne);
  assert_int_equal(dtm_operator_stored(pts), 0);
  assert_memory_equal(dtm_operator_mass(ms), dtm_operator_mass(pts), n * sizeof(double));
  double *x = malloc(n * sizeof *x), *y1 = malloc(n * sizeof *y1), *y2 = malloc(n * sizeof *y2);
  for (unsigned seed = 1; seed <= 3; seed++) {
    dtm_operator_draw(ms, seed, -1, 1, x);
    dtm_operator_apply(ms, x, y1);
    dtm_operator_apply(pts, x, y2);
    double big = max_abs(n, y2);
    for (size_t i = 0; i < n; i++)
      if (!(fabs(y1[i] - y2[i]) <= 1e-12 * big)) fail_msg("dof %zu: %.17g stored, %.17g from points", i, y1[i], y2[i]);
  }
  dtm_lanczos_result l1, l2;
  assert_int_equal(dtm_lanczos_max_certified(ms, 1e-8, 400, 7, 0, 1e12, 0, &l1), 0);
  assert_int_equal(dtm_lanczos_max_certified(pts, 1e-8, 400, 7, 0, 1e12, 0, &l2), 0);
  assert_int_equal(l1.certified, DTM_CERT_PROVEN);
  assert_int_equal(l2.certified, DTM_CERT_PROVEN);
  double b1 = l1.theta + l1.residual, b2 = l2.theta + l2.residual;
  if (!(fabs(b1 - b2) <= 1e-9 * b2)) fail_msg("bound %.17g stored, %.17g from points", b1, b2);
  free(x), free(y1), free(y2);
  dtm_operator_destroy(&ms), dtm_operator_destroy(&pts);
  dtm_analysis_destroy(&a);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  if (dtm_gmsh_start(0)) return 3;
  setup_scene();
  const struct CMUnitTest tests[] = {cmocka_unit_test(stored_against_points)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_scene_destroy(&scene);
  dtm_gmsh_stop();
  return r;
}
