/* Hard cases, slivers: a 4x4x4 grid of 1 cm cubes, Kuhn-split into tets,
 * where cube (1,1,1) is cut into two triangular prisms whose shared
 * diagonal rectangle is triangulated along different diagonals from each
 * side, and the gap is one sliver tet (its four vertices nearly coplanar,
 * the fourth at height flatness x 1 cm above the plane of the other three,
 * made by moving one cube corner off the rectangle; the cube above is
 * split around its centre to match the flipped face). Flatness 1e-1 to
 * 1e-4, elastic (steel), plus a thermal-only run at 1e-3. Each case must
 * pass the corpus check of hardcase.h: Lanczos converged, element and
 * nodal bounds at or below the global estimate, verify bounded at the
 * recommended step and unbounded at 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>

#include "hardcase.h"
#include "testutil.h"

#define N 4    /* cubes per side */
#define H 1e-2 /* cube edge (m) */
#define SI 1   /* the sliver cube is (SI, SI, SI) */

#define STEEL                                                                                                          \
  "  <material name=\"steel\" groups=\"solid\" E=\"210e9\" nu=\"0.3\" rho=\"7850\" "                                   \
  "conductivity=\"45\" heat-capacity=\"460\"/>"

typedef struct {
  const char *name;
  double flatness;
  const char *effects;
} sliver_case;

static size_t tag_at(int i, int j, int k) { return hc_grid_tag(1, N, N, i, j, k); }

/* Corner (a, b, c) of cube (i, j, k). */
static size_t corner(int i, int j, int k, int a, int b, int c) { return tag_at(i + a, j + b, k + c); }

/* The sliver cube: prism y >= z (Kuhn tets with y before z), prism
 * y <= z with the rectangle cut along v100-v011 and the top face along
 * v011-v101, and the sliver v000 v100 v111 v011 between them. */
static void sliver_cube(hc_mesh *m, int i, int j, int k) {
  static const int t[7][4][3] = {
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {1, 1, 1}}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 1, 1}},
      {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {1, 1, 1}}, {{0, 1, 1}, {1, 0, 0}, {1, 0, 1}, {1, 1, 1}},
      {{0, 1, 1}, {0, 0, 0}, {0, 0, 1}, {1, 0, 1}}, {{0, 1, 1}, {0, 0, 0}, {1, 0, 1}, {1, 0, 0}},
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 1}, {0, 1, 1}}};
  for (int e = 0; e < 7; e++) {
    size_t n[4];
    for (int v = 0; v < 4; v++) n[v] = corner(i, j, k, t[e][v][0], t[e][v][1], t[e][v][2]);
    if (e < 6)
      hc_simplex(m, n, 0);
    else
      hc_elem(m, n, 0); /* flat until the corner moves; positive after */
  }
}

/* Face (axis, side) of cube (i, j, k) as two triangles plus the centre:
 * cut along q00-q11 (Kuhn), or along q10-q01 where flip is set. */
static void centre_face(hc_mesh *m, int i, int j, int k, int axis, int side, int flip, size_t centre) {
  size_t q[2][2];
  for (int u = 0; u < 2; u++)
    for (int v = 0; v < 2; v++) {
      int l[3];
      l[axis] = side, l[(axis + 1) % 3] = u, l[(axis + 2) % 3] = v;
      q[u][v] = corner(i, j, k, l[0], l[1], l[2]);
    }
  size_t a[4] = {q[0][0], q[1][0], q[1][1], centre}, b[4] = {q[0][0], q[1][1], q[0][1], centre};
  size_t c[4] = {q[1][0], q[1][1], q[0][1], centre}, d[4] = {q[1][0], q[0][1], q[0][0], centre};
  hc_simplex(m, flip ? c : a, 0);
  hc_simplex(m, flip ? d : b, 0);
}

/* Cube (i, j, k) split around a new centre node, its bottom face flipped. */
static void centre_cube(hc_mesh *m, int i, int j, int k) {
  size_t centre = hc_node(m, (i + 0.5) * H, (j + 0.5) * H, (k + 0.5) * H);
  for (int axis = 0; axis < 3; axis++)
    for (int side = 0; side < 2; side++) centre_face(m, i, j, k, axis, side, axis == 2 && side == 0, centre);
}

/* Height of vertex 3 of tet n above the plane of the other three. */
static double height(const hc_mesh *m, const size_t *n) {
  const double *p[3];
  for (int v = 0; v < 3; v++) p[v] = m->xyz + 3 * (n[v] - 1);
  double u[3], w[3], c[3];
  for (int d = 0; d < 3; d++) u[d] = p[1][d] - p[0][d], w[d] = p[2][d] - p[0][d];
  c[0] = u[1] * w[2] - u[2] * w[1], c[1] = u[2] * w[0] - u[0] * w[2], c[2] = u[0] * w[1] - u[1] * w[0];
  return 6 * fabs(hc_simplex_measure(m, n)) / sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

static void build(const char *name, double flatness) {
  hc_mesh m;
  double x[N + 1];
  for (int i = 0; i <= N; i++) x[i] = i * H;
  hc_mesh_init(&m, 3, HC_TET4, 4, "solid");
  hc_grid_nodes(&m, x, N, x, N, x, N);
  for (int k = 0; k < N; k++)
    for (int j = 0; j < N; j++)
      for (int i = 0; i < N; i++) {
        if (i == SI && j == SI && k == SI)
          sliver_cube(&m, i, j, k);
        else if (i == SI && j == SI && k == SI + 1)
          centre_cube(&m, i, j, k);
        else
          hc_kuhn_cell(&m, 1, N, N, i, j, k, 0);
      }
  /* move corner v011 of the sliver cube off the rectangle y = z, into the
   * y < z prism: the sliver's height is flatness x H. Every tet must stay
   * positive (hc_simplex oriented them before the move) and the volumes
   * must add up to the box's: the tets tile it without overlap. */
  double *p = m.xyz + 3 * (corner(SI, SI, SI, 0, 1, 1) - 1), s = flatness * H / sqrt(2.0), vol = 0;
  p[1] -= s, p[2] += s;
  for (size_t e = 0; e < m.ne; e++) {
    double v = hc_simplex_measure(&m, m.conn + 4 * e);
    assert_true(v > 0);
    vol += v;
  }
  assert_true(fabs(vol - pow(N * H, 3)) <= 1e-12 * pow(N * H, 3));
  size_t sl[4] = {corner(SI, SI, SI, 0, 0, 0), corner(SI, SI, SI, 1, 0, 0), corner(SI, SI, SI, 1, 1, 1),
                  corner(SI, SI, SI, 0, 1, 1)};
  assert_true(fabs(height(&m, sl) - flatness * H) <= 1e-9 * flatness * H);
  hc_mesh_write(&m, name);
  hc_mesh_free(&m);
}

static void sliver(void **state) {
  const sliver_case *c = *state;
  hc_result r;
  build(c->name, c->flatness);
  hc_scene_write(c->name, STEEL, c->effects);
  hc_check(c->name, &r);
}

#define ELASTIC "<elastic formulation=\"3d\"/>"
static const sliver_case cases[] = {
    {"sliver-1e-1", 1e-1, ELASTIC},
    {"sliver-1e-2", 1e-2, ELASTIC},
    {"sliver-1e-3", 1e-3, ELASTIC},
    {"sliver-1e-4", 1e-4, ELASTIC},
    {"sliver-1e-3-thermal", 1e-3, "<thermal/>"},
};

/* An unsafe length rule on the 1e-3 sliver: min-edge gives the sliver an
 * element "step" above the true global one (DESIGN.md: 1.3-17x on slivers),
 * so it must not raise the recommendation. The step dtmap vouches for rests
 * on the nodal bound, stays below the global estimate, and verify at the
 * recommended step stays bounded (exit 0). */
static void sliver_min_edge(void **unused) {
  char scene[600], *log = NULL;
  build("sliver-minedge", 1e-3);
  hc_scene_write("sliver-minedge", STEEL, "<elastic formulation=\"3d\" length=\"min-edge\"/>");
  double dt_min = hc_run_number("sliver-minedge", 1, "dt.min");
  double global = hc_run_number("sliver-minedge", 1, "dt.global");
  double rec = hc_run_number("sliver-minedge", 0, "dt.recommended");
  double nodal = hc_run_number("sliver-minedge", 0, "dt.nodal");
  assert_true(dt_min > global);                          /* the rule is unsafe here */
  assert_true(fabs(rec - 0.9 * nodal) <= 1e-14 * nodal); /* 17 digits in the report */
  assert_true(rec < global);
  snprintf(scene, sizeof scene, "%s/sliver-minedge.xml", tu_tmpdir());
  int code = tu_run(&log, "%s verify %s --steps 2000 -q", tu_cli(), scene);
  free(log);
  assert_int_equal(code, 0);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  enum { NC = sizeof cases / sizeof cases[0] };
  struct CMUnitTest tests[NC + 1];
  for (int i = 0; i < NC; i++) tests[i] = (struct CMUnitTest){cases[i].name, sliver, NULL, NULL, (void *)&cases[i]};
  tests[NC] = (struct CMUnitTest){"sliver-1e-3-min-edge", sliver_min_edge, NULL, NULL, NULL};
  int r = _cmocka_run_group_tests("t701", tests, NC + 1, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
