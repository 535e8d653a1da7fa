/* Hard cases, needles, each limiting the step: (1) a 4x4x4 grid of 1 cm
 * cubes, Kuhn-split into tets, where one tet at an interior node A gets a
 * point P close to A (1-4 split) and the tet (A, P, C, D) then a point Q
 * close to A and P (1-4 split): tets with the three close vertices A, P, Q
 * and one far vertex are needles; P and Q are placed so that the worst
 * longest-over-shortest edge ratio of the new tets is 20 (3D, steel);
 * (2) the same cubes in three layers with the middle layer 20 cm thick, so
 * that layer is needles of ratio 20.05 between regular layers (they do not
 * limit: the cubes do); (3) an 8x8 grid of 1 cm squares cut into triangles
 * with one interior edge split at sqrt(2)/40 cm from its end, giving a
 * triangle of edge ratio 40 (plane strain, steel). Each case must pass the
 * corpus check of hardcase.h: Lanczos converged, element and nodal bounds
 * at or below the global estimate, verify bounded at the recommended step
 * and unbounded at 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <math.h>
#include <stdio.h>

#include "hardcase.h"
#include "testutil.h"

#define H 1e-2
#define STEEL "  <material name=\"steel\" groups=\"solid\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>"

/* Coordinates with unit steps of H except step `big` x H at position at. */
static void steps(double *x, int n, int at, double big) {
  x[0] = 0;
  for (int i = 0; i < n; i++) x[i + 1] = x[i] + (i == at ? big : 1.0) * H;
}

/* Every element positive, and the measures add up to `total`. */
static void check_tiling(const hc_mesh *m, double total) {
  double sum = 0;
  for (size_t e = 0; e < m->ne; e++) {
    double v = hc_simplex_measure(m, m->conn + (size_t)m->npe * e);
    assert_true(v > 0);
    sum += v;
  }
  assert_true(fabs(sum - total) <= 1e-12 * total);
}

/* The Kuhn grid with the two insertions at scale t (|AP| = 1.25 t H);
 * returns the worst edge ratio of the tets they create. */
static double pinched_grid(hc_mesh *m, double t) {
  double x[5];
  steps(x, 4, -1, 1);
  hc_mesh_init(m, 3, HC_TET4, 4, "solid");
  hc_box(m, x, 4, x, 4, x, 4);
  size_t e = 6 * (2 + 4 * (2 + 4 * 2)), ne0 = m->ne; /* first tet of cube (2,2,2) */
  const size_t *n = m->conn + 4 * e;
  const double *a = m->xyz + 3 * (n[0] - 1), *c = m->xyz + 3 * (n[2] - 1), *d = m->xyz + 3 * (n[3] - 1);
  double p[3], q[3];
  for (int k = 0; k < 3; k++) p[k] = a[k] + t * (3 - k) * H / 3; /* towards the centroid (3,2,1)/3 */
  for (int k = 0; k < 3; k++) q[k] = a[k] + 0.5 * (p[k] - a[k]) + 0.36 * t * (c[k] + d[k] - 2 * a[k]);
  size_t tp = hc_node(m, p[0], p[1], p[2]), tq = hc_node(m, q[0], q[1], q[2]);
  hc_split_simplex(m, e, tp); /* (P,B,C,D) in place, (A,P,C,D) at ne0, ... */
  hc_split_simplex(m, ne0, tq);
  double worst = hc_aspect(m, e);
  for (size_t k = ne0; k < m->ne; k++) worst = fmax(worst, hc_aspect(m, k));
  return worst;
}

static void needle_tets(void **unused) {
  hc_mesh m;
  double lo = 1e-4, hi = 0.2; /* the ratio falls as t grows */
  for (int it = 0; it < 60; it++) {
    double t = 0.5 * (lo + hi);
    double ar = pinched_grid(&m, t);
    hc_mesh_free(&m);
    if (ar > 20)
      lo = t;
    else
      hi = t;
  }
  assert_true(fabs(pinched_grid(&m, hi) - 20) < 1e-6);
  check_tiling(&m, pow(4 * H, 3));
  hc_mesh_write(&m, "needle-tet-ar20");
  hc_mesh_free(&m);
  hc_scene_write("needle-tet-ar20", STEEL, "<elastic formulation=\"3d\"/>");
  hc_result r;
  hc_check("needle-tet-ar20", &r);
  (void)unused;
}

static void needle_slab(void **unused) {
  double xy[5], z[4];
  hc_mesh m;
  steps(xy, 4, -1, 1), steps(z, 3, 1, 20);
  hc_mesh_init(&m, 3, HC_TET4, 4, "solid");
  hc_box(&m, xy, 4, xy, 4, z, 3);
  double ar = 0;
  for (size_t e = 0; e < m.ne; e++) ar = fmax(ar, hc_aspect(&m, e));
  assert_true(ar >= 20 && ar <= 20.1);
  hc_mesh_write(&m, "needle-slab-ar20");
  hc_mesh_free(&m);
  hc_scene_write("needle-slab-ar20", STEEL, "<elastic formulation=\"3d\"/>");
  hc_result r;
  hc_check("needle-slab-ar20", &r);
  (void)unused;
}

static void needle_triangles(void **unused) {
  double x[9];
  hc_mesh m;
  steps(x, 8, -1, 1);
  hc_mesh_init(&m, 2, HC_TRI3, 3, "solid");
  hc_rect(&m, x, 8, x, 8);
  /* split the edge (4,4)-(5,4) at w = sqrt(2) H / 40 from (4,4): the
   * triangle with (5,5) has edges w, |P-(5,5)| < sqrt(2) H, sqrt(2) H */
  size_t a = hc_grid_tag(1, 8, 8, 4, 4, 0), b = a + 1;
  size_t p = hc_node(&m, 4 * H + sqrt(2.0) * H / 40, 4 * H, 0);
  assert_int_equal(hc_split_edge(&m, a, b, p), 2);
  double ar = 0;
  for (size_t e = 0; e < m.ne; e++) ar = fmax(ar, hc_aspect(&m, e));
  assert_true(fabs(ar - 40) < 1e-9);
  check_tiling(&m, 64 * H * H);
  hc_mesh_write(&m, "needle-tri-ar40");
  hc_mesh_free(&m);
  hc_scene_write("needle-tri-ar40", STEEL, "<elastic formulation=\"plane-strain\"/>");
  hc_result r;
  hc_check("needle-tri-ar40", &r);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(needle_tets), cmocka_unit_test(needle_slab),
                                     cmocka_unit_test(needle_triangles)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
