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
#include "dtmap/operator.h"
#include "spectral.h"
#include "testutil.h"

/* The two operators of analysis a: the default one and one keeping points. */
static void both_ways(const dtm_analysis *a, dtm_operator **stored, dtm_operator **points) {
  assert_int_equal(dtm_analysis_operator(a, 0, 0.0, stored), 0);
  dtm_operator_store = 0;
  int r = dtm_analysis_operator(a, 0, 0.0, points);
  dtm_operator_store = 1;
  assert_int_equal(r, 0);
}

/* K x of both on three random x, to 1e-12 of the result's largest entry. */
static void same_products(const dtm_operator *ms, const dtm_operator *pts) {
  size_t n = dtm_operator_ndof(ms);
  double *x = malloc(n * sizeof *x), *y1 = malloc(n * sizeof *y1), *y2 = malloc(n * sizeof *y2);
  for (unsigned seed = 1; seed <= 3; seed++) {
    double big = 0;
    dtm_operator_draw(ms, seed, -1, 1, x);
    dtm_operator_apply(ms, x, y1);
    dtm_operator_apply(pts, x, y2);
    for (size_t i = 0; i < n; i++) big = fmax(big, fabs(y2[i]));
    for (size_t i = 0; i < n; i++)
      if (!(fabs(y1[i] - y2[i]) <= 1e-12 * big)) fail_msg("dof %zu: %.17g stored, %.17g from points", i, y1[i], y2[i]);
  }
  free(x), free(y1), free(y2);
}

/* The certified bound theta + residual of op (Lanczos to 1e-8). */
static double proven_bound(const dtm_operator *op) {
  dtm_lanczos_result l;
  assert_int_equal(dtm_lanczos_max_certified(op, 1e-8, 400, 7, 0, 1e12, 0, &l), 0);
  assert_int_equal(l.certified, DTM_CERT_PROVEN);
  return l.theta + l.residual;
}

static void stored_against_points(void **unused) {
  char path[600];
  dtm_scene *scene = NULL;
  dtm_operator *ms = NULL, *pts = NULL;
  snprintf(path, sizeof path, "%s/ball.geo", tu_tmpdir());
  tu_write(path, "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 1};\nPhysical Volume(\"block\") = {1};\n");
  tu_steel_scene("ball", "<geometry file=\"ball.geo\"/>", "size=\"0.35\" order=\"2\"", "");
  dtm_analysis *a = tu_analyse("ball", &scene);
  both_ways(a, &ms, &pts);
  size_t ne = dtm_mesh_nelements(a->mesh), stored = dtm_operator_stored(ms);
  print_message("%zu of %zu tet10 stored as matrices\n", stored, ne);
  assert_true(stored > 0 && stored < ne);
  assert_int_equal(dtm_operator_stored(pts), 0);
  assert_memory_equal(dtm_operator_mass(ms), dtm_operator_mass(pts), dtm_operator_ndof(ms) * sizeof(double));
  same_products(ms, pts);
  double b1 = proven_bound(ms), b2 = proven_bound(pts);
  if (!(fabs(b1 - b2) <= 1e-9 * b2)) fail_msg("bound %.17g stored, %.17g from points", b1, b2);
  dtm_operator_destroy(&ms), dtm_operator_destroy(&pts);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&scene);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(stored_against_points)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  tu_gmsh_end();
  return r;
}
