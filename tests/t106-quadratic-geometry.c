/* Geometry of the second-order elements: measures, HRZ lumped weights,
 * topology (edges and facets of the linear parent on the corner nodes,
 * src/topology.c) and the characteristic lengths (dtm_kernel_length: the
 * geometric kinds on the corners, SAFE on the element itself).
 * Elements are straight-sided, mid-side nodes at the middle: the
 * reference element of each type, or its image under an affine map.
 * Hand values of the HRZ weights w_a = integral(N_a^2) / sum_b
 * integral(N_b^2) (the same on every affine image):
 *   tet10: integral of L^k over a tet is V k! 3!/(k+3)!, so a corner gives
 *     integral L^2 (2L - 1)^2 = V (4/35 - 4/20 + 1/10) = V/70 and a mid-edge
 *     node 16 integral L_i^2 L_j^2 = 16 V 2! 2! 3!/7! = 8V/105; the sum is
 *     4/70 + 48/105 = 18/35, so corners 1/36 and mid-edge nodes 4/27.
 *   tri6: likewise (k! 2!/(k+2)!) corners A/30, mid-edges 8A/45, so 1/19
 *     and 16/57 (the classical 3/57 and 16/57).
 *   quad9, hex27: tensor products of the 1D quadratic weights 1/6, 2/3,
 *     1/6 (the consistent 1D mass diagonal is L/30 (4, 16, 4)).
 *   prism18: tri6's weights times the 1D ones.
 *   quad8 (3/76, 16/76), hex20 (7/248, 16/248), prism15 (1/34 corners,
 *     4/51 triangle edges, 2/17 vertical edges), pyr13 and pyr14: exact
 *     rational integration in sympy, the nodal bases rebuilt independently
 *     of dtmap by inverting the Vandermonde matrix of Gmsh's function
 *     space at the nodes (for pyramids: Bergot's space in collapsed
 *     coordinates, as Gmsh's pyramidalBasis does).
 * Tolerances: 1e-14 relative for measures and weights (exact quadrature of
 * O(1) quantities, a few dozen roundings); lengths on the corners must
 * agree with the parent's to the last bit (same code, same corners), and
 * 1e-14 against hand values. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/topology.h"
#include "kernel-impl.h"

static const int types[] = {DTM_TRI6,  DTM_QUAD9, DTM_TET10, DTM_HEX27,   DTM_PRISM18,
                            DTM_PYR14, DTM_QUAD8, DTM_HEX20, DTM_PRISM15, DTM_PYR13};
#define NTYPES (sizeof types / sizeof types[0])

static void near(double got, double want, double rel, const char *what, int type) {
  if (!(fabs(got - want) <= rel * fabs(want)))
    fail_msg("%s %s: got %.17g, want %.17g (rel tol %g)", dtm_elem_name(type), what, got, want, rel);
}

static int nodes_of(int type) {
  int nn = 0;
  dtm_elem_info(type, NULL, &nn);
  return nn;
}

/* The reference element of type: Gmsh's reference coordinates of its
 * nodes (checked against the manual in t105). */
static void reference(int type, double *x) {
  for (int a = 0; a < nodes_of(type); a++) dtm_ref_node_uvw(type, a, x + 3 * a);
}

/* x = A xi + b for every node; A has determinant det_A() = 3.6375 (2D:
 * A2, determinant 3, and the map stays in the plane z = b[2]). */
static void affine(int type, const double *xi, double *x) {
  static const double A[3][3] = {{2, 0.5, 0.25}, {0.5, 1.5, -0.5}, {0, 0.3, 1.2}};
  static const double b[3] = {10, -20, 5};
  int d;
  dtm_elem_info(type, &d, NULL);
  double A2[3][3] = {{2, 0.5, 0}, {0.25, 1.5625, 0}, {0, 0, 0}}; /* det 3 */
  for (int a = 0; a < nodes_of(type); a++)
    for (int i = 0; i < 3; i++) {
      x[3 * a + i] = b[i];
      for (int j = 0; j < 3; j++) x[3 * a + i] += (d == 3 ? A[i][j] : A2[i][j]) * xi[3 * a + j];
    }
}

static double det_A(void) { return 2 * (1.5 * 1.2 + 0.5 * 0.3) - 0.5 * (0.5 * 1.2) + 0.25 * (0.5 * 0.3); }

/* Reference measures: unit triangle 1/2, square [-1,1]^2 4, unit tet 1/6,
 * cube 8, prism 1/2 x 2, pyramid base 4 x height 1 / 3. */
static double ref_measure(int type) {
  switch (dtm_elem_parent(type)) {
  case DTM_TRI3: return 0.5;
  case DTM_QUAD4: return 4;
  case DTM_TET4: return 1.0 / 6;
  case DTM_HEX8: return 8;
  case DTM_PRISM6: return 1;
  case DTM_PYR5: return 4.0 / 3;
  default: return NAN;
  }
}

static void test_measure(void **state) {
  (void)state;
  double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES];
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], d;
    dtm_elem_info(type, &d, NULL);
    reference(type, xi);
    near(dtm_elem_measure(type, xi), ref_measure(type), 1e-14, "reference measure", type);
    affine(type, xi, x);
    near(dtm_elem_measure(type, x), (d == 3 ? det_A() : 3) * ref_measure(type), 1e-14, "affine image", type);
    /* the same as the parent's measure on the corners */
    near(dtm_elem_measure(type, x), dtm_elem_measure(dtm_elem_parent(type), x), 1e-14, "parent measure", type);
  }
}

/* A tri6 and a quad8 in a tilted plane: the frame comes from the corners,
 * so the area is that of the flat element. */
static void test_tilted(void **state) {
  (void)state;
  const int t2[] = {DTM_TRI6, DTM_QUAD8, DTM_QUAD9};
  for (int t = 0; t < 3; t++) {
    double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES], w[DTM_MAX_NODES];
    reference(t2[t], xi);
    for (int a = 0; a < nodes_of(t2[t]); a++) {
      /* Rodrigues: rotate (u, v, 0) by 60 degrees about k = (1,1,0)/sqrt2,
       * R r = r cos + (k x r) sin + k (k.r)(1 - cos), k x r = (0, 0, k(v - u)) */
      double u = xi[3 * a], v = xi[3 * a + 1], c = 0.5, s = sqrt(3) / 2;
      double k = 1 / sqrt(2.0), dotk = k * (u + v);
      x[3 * a] = u * c + k * dotk * (1 - c);
      x[3 * a + 1] = v * c + k * dotk * (1 - c);
      x[3 * a + 2] = s * k * (v - u);
      x[3 * a] += 7, x[3 * a + 1] -= 3, x[3 * a + 2] += 1;
    }
    near(dtm_elem_measure(t2[t], x), ref_measure(t2[t]), 1e-14, "tilted area", t2[t]);
    dtm_elem_lumped_weights(t2[t], x, w);
    for (int a = 0; a < nodes_of(t2[t]); a++) assert_true(w[a] > 0);
  }
}

/* HRZ weights by node class: corner, mid-edge, face centre, centre;
 * prisms split mid-edge nodes into triangle edges and vertical edges. */
typedef struct {
  int type;
  double corner, edge, vedge, face, centre;
} hrz_def;

static const hrz_def hrz[] = {
    {DTM_TRI6, 1.0 / 19, 16.0 / 57, 0, 0, 0},
    {DTM_QUAD9, 1.0 / 36, 1.0 / 9, 0, 0, 4.0 / 9},
    {DTM_TET10, 1.0 / 36, 4.0 / 27, 0, 0, 0},
    {DTM_HEX27, 1.0 / 216, 4.0 / 216, 0, 16.0 / 216, 64.0 / 216},
    {DTM_PRISM18, 1.0 / 114, 16.0 / 342, 4.0 / 114, 64.0 / 342, 0},
    {DTM_QUAD8, 3.0 / 76, 16.0 / 76, 0, 0, 0},
    {DTM_HEX20, 7.0 / 248, 16.0 / 248, 0, 0, 0},
    {DTM_PRISM15, 1.0 / 34, 4.0 / 51, 2.0 / 17, 0, 0},
};

/* Class of node a from its reference coordinates: 0 corner, 1 edge, 2
 * vertical prism edge, 3 face centre, 4 element centre. */
static int node_class(int type, int a) {
  double p[3];
  int nc, parent = dtm_elem_parent(type);
  dtm_elem_info(parent, NULL, &nc);
  if (a < nc) return 0;
  dtm_ref_node_uvw(type, a, p);
  const dtm_topology *t = dtm_elem_topology(type);
  if (a < nc + t->nedge) {
    if (parent == DTM_PRISM6 && p[2] == 0) return 2;
    return 1;
  }
  if (parent == DTM_QUAD4 || (parent == DTM_HEX8 && a == 26)) return 4;
  return 3;
}

static void test_weights(void **state) {
  (void)state;
  double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES], w[DTM_MAX_NODES];
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], nn = nodes_of(type);
    reference(type, xi);
    for (int pass = 0; pass < 2; pass++) {
      if (pass)
        affine(type, xi, x);
      else
        memcpy(x, xi, sizeof x);
      double s = 0;
      dtm_elem_lumped_weights(type, x, w);
      for (int a = 0; a < nn; a++) {
        assert_true(w[a] > 0);
        s += w[a];
      }
      near(s, 1, 1e-14, "sum of weights", type);
      for (size_t k = 0; k < sizeof hrz / sizeof hrz[0]; k++) {
        if (hrz[k].type != type) continue;
        const double *want = &hrz[k].corner;
        for (int a = 0; a < nn; a++) near(w[a], want[node_class(type, a)], 1e-14, "HRZ", type);
      }
    }
  }
}

/* Pyramids: sympy's exact HRZ weights (see the header), by node class:
 * base corners 0-3, apex 4, base edges 5, 6, 8, 10, lateral edges 7, 9,
 * 11, 12 and the base centre 13 (pyr14). */
static void test_pyramid_weights(void **state) {
  (void)state;
  static const double p13[5] = {11.0 / 373, 9.0 / 373, 48.0 / 373, 32.0 / 373, 0};
  static const double p14[5] = {43.0 / 3078, 90.0 / 3078, 192.0 / 3078, 320.0 / 3078, 768.0 / 3078};
  static const int cls[14] = {0, 0, 0, 0, 1, 2, 2, 3, 2, 3, 2, 3, 3, 4};
  double x[3 * DTM_MAX_NODES], w[DTM_MAX_NODES];
  const int pyr[] = {DTM_PYR13, DTM_PYR14};
  for (int t = 0; t < 2; t++) {
    reference(pyr[t], x);
    dtm_elem_lumped_weights(pyr[t], x, w);
    for (int a = 0; a < nodes_of(pyr[t]); a++) near(w[a], (t ? p14 : p13)[cls[a]], 1e-14, "pyramid HRZ", pyr[t]);
  }
}

static void test_topology(void **state) {
  (void)state;
  double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES];
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], parent = dtm_elem_parent(type);
    const int(*e)[2], (*pe)[2];
    const int(*f)[DTM_MAX_FACET_NODES], (*pf)[DTM_MAX_FACET_NODES], *fc, *pfc;
    reference(type, xi);
    affine(type, xi, x);
    int ne = dtm_elem_edges(type, &e), pne = dtm_elem_edges(parent, &pe);
    assert_true(ne > 0);
    assert_int_equal(ne, pne);
    assert_ptr_equal(e, pe);
    int nf = dtm_elem_facets(type, &f, &fc), pnf = dtm_elem_facets(parent, &pf, &pfc);
    assert_true(nf > 0 && nf <= DTM_MAX_FACETS);
    assert_int_equal(nf, pnf);
    assert_ptr_equal(f, pf);
    assert_ptr_equal(fc, pfc);
    assert_true(dtm_elem_mean_edge(type, x) == dtm_elem_mean_edge(parent, x));
    for (int k = 0; k < nf; k++) {
      assert_true(fc[k] <= DTM_MAX_FACET_NODES);
      assert_true(dtm_elem_facet_measure(type, k, x) == dtm_elem_facet_measure(parent, k, x));
    }
  }
  /* Hand values on the reference cube (edge 2) and unit tet. */
  reference(DTM_HEX20, x);
  near(dtm_elem_mean_edge(DTM_HEX20, x), 2, 1e-14, "cube mean edge", DTM_HEX20);
  near(dtm_elem_facet_measure(DTM_HEX20, 0, x), 4, 1e-14, "cube face", DTM_HEX20);
  reference(DTM_TET10, x);
  near(dtm_elem_mean_edge(DTM_TET10, x), (3 + 3 * sqrt(2.0)) / 6, 1e-14, "tet mean edge", DTM_TET10);
  double area = 0;
  const int(*f)[DTM_MAX_FACET_NODES];
  const int *fc;
  int nf = dtm_elem_facets(DTM_TET10, &f, &fc);
  for (int k = 0; k < nf; k++) area += dtm_elem_facet_measure(DTM_TET10, k, x);
  near(area, 1.5 + sqrt(3) / 2, 1e-14, "tet surface", DTM_TET10);
  /* an unsupported type has no edges or facets */
  const int(*e)[2];
  assert_int_equal(dtm_elem_edges(29, &e), 0);
  assert_true(isnan(dtm_elem_mean_edge(29, x)));
}

static void test_lengths(void **state) {
  (void)state;
  double xi[3 * DTM_MAX_NODES], x[3 * DTM_MAX_NODES];
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], parent = dtm_elem_parent(type);
    reference(type, xi);
    affine(type, xi, x);
    for (int k = DTM_LEN_MIN_EDGE; k <= DTM_LEN_VOLUME_AREA; k++) {
      double l = dtm_kernel_length(type, k, x), lp = dtm_kernel_length(parent, k, x);
      if (!(l == lp) || !(l > 0)) fail_msg("%s kind %d: %.17g, parent %.17g", dtm_elem_name(type), k, l, lp);
    }
    assert_true(isnan(dtm_kernel_length(type, DTM_LEN_EIGEN, x)));
    /* SAFE sees the mid-side nodes: the quadratic element is stiffer, so
     * its safe length is shorter than the parent's. */
    double s = dtm_kernel_length(type, DTM_LEN_SAFE, x);
    assert_true(s > 0 && s < dtm_kernel_length(parent, DTM_LEN_SAFE, x));
  }
  /* Hand values on the reference tet10: shortest edge 1, smallest
   * altitude 1/sqrt(3), 2 x inradius = 6 V / A = 1/(1.5 + sqrt(3)/2). */
  reference(DTM_TET10, x);
  near(dtm_kernel_length(DTM_TET10, DTM_LEN_MIN_EDGE, x), 1, 1e-14, "min edge", DTM_TET10);
  near(dtm_kernel_length(DTM_TET10, DTM_LEN_MIN_ALTITUDE, x), 1 / sqrt(3), 1e-14, "min altitude", DTM_TET10);
  near(dtm_kernel_length(DTM_TET10, DTM_LEN_INRADIUS, x), 1 / (1.5 + sqrt(3) / 2), 1e-14, "2 r", DTM_TET10);
  /* A curved tet10 (mid-edge node 4 moved off its edge) keeps the
   * geometric lengths of its corners. */
  double y[30];
  memcpy(y, x, sizeof y);
  y[3 * 4 + 1] += 0.1;
  near(dtm_kernel_length(DTM_TET10, DTM_LEN_MIN_EDGE, y), 1, 1e-14, "curved min edge", DTM_TET10);
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_measure),         cmocka_unit_test(test_tilted),   cmocka_unit_test(test_weights),
      cmocka_unit_test(test_pyramid_weights), cmocka_unit_test(test_topology), cmocka_unit_test(test_lengths),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
