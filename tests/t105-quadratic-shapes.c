/* Second-order reference elements (src/kernel/ref_nodes.c,
 * ref_quadratic.c, ref_pyramid.c, quadrature.c): the type catalogue, the
 * node ordering against Gmsh's reference manual ("Node ordering"), the
 * shape functions (Kronecker property at the nodes, partition of unity,
 * reproduction of every quadratic polynomial in (u, v, w), which all ten
 * spaces contain, gradients against central differences) and the
 * full-integration rules against exact monomial integrals.
 * Tolerances: 1e-14 absolute for shape function values and sums (O(1)
 * numbers, a few dozen roundings); 1e-13 for quadratic reproduction (sums
 * of 27 products of O(1) terms); 2e-8 for gradients against central
 * differences with step 1e-5 (truncation h^2 |f'''|/6 ~ 1e-10 for these
 * polynomials of degree <= 6, rounding eps/h ~ 1e-11, with margin);
 * 1e-14 relative (1e-15 absolute for vanishing integrals) for the rules,
 * whose constants carry 20 digits. */
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

static const int types[] = {DTM_TRI6,  DTM_QUAD9, DTM_TET10, DTM_HEX27,   DTM_PRISM18,
                            DTM_PYR14, DTM_QUAD8, DTM_HEX20, DTM_PRISM15, DTM_PYR13};
#define NTYPES (sizeof types / sizeof types[0])

static void near_abs(double got, double want, double tol, const char *what, int type, int a) {
  if (!(fabs(got - want) <= tol))
    fail_msg("%s %s node %d: got %.17g, want %.17g (tol %g)", dtm_elem_name(type), what, a, got, want, tol);
}

static void test_catalogue(void **state) {
  (void)state;
  static const struct {
    int type, dim, nn, parent;
    const char *name;
  } t[] = {{9, 2, 6, DTM_TRI3, "tri6"},    {10, 2, 9, DTM_QUAD4, "quad9"},     {11, 3, 10, DTM_TET4, "tet10"},
           {12, 3, 27, DTM_HEX8, "hex27"}, {13, 3, 18, DTM_PRISM6, "prism18"}, {14, 3, 14, DTM_PYR5, "pyr14"},
           {16, 2, 8, DTM_QUAD4, "quad8"}, {17, 3, 20, DTM_HEX8, "hex20"},     {18, 3, 15, DTM_PRISM6, "prism15"},
           {19, 3, 13, DTM_PYR5, "pyr13"}};
  for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
    int dim = -1, nn = -1;
    dtm_error_clear();
    assert_int_equal(dtm_elem_info(t[i].type, &dim, &nn), DTM_OK);
    assert_int_equal(dim, t[i].dim);
    assert_int_equal(nn, t[i].nn);
    assert_true(nn <= DTM_MAX_NODES && nn <= DTM_K_NODES);
    assert_string_equal(dtm_elem_name(t[i].type), t[i].name);
    /* the simplex closed forms are for linear simplices only */
    assert_int_equal(dtm_elem_is_simplex(t[i].type), 0);
    assert_int_equal(dtm_elem_parent(t[i].type), t[i].parent);
    assert_int_equal(dtm_elem_parent(t[i].parent), t[i].parent);
    assert_int_equal(dtm_elem_serendipity(t[i].type), t[i].type >= 16);
    assert_ptr_equal(dtm_elem_topology(t[i].type), dtm_elem_topology(t[i].parent));
  }
  /* line3 (8), tet20 (29) and a point (15) stay unsupported. */
  const int bad[] = {8, 15, 29, 0, -1};
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    dtm_error_clear();
    assert_int_equal(dtm_elem_info(bad[i], NULL, NULL), DTM_ERR_INPUT);
    assert_string_equal(dtm_elem_name(bad[i]), "unknown");
    assert_int_equal(dtm_elem_parent(bad[i]), 0);
    assert_null(dtm_elem_topology(bad[i]));
  }
  dtm_error_clear();
}

/* Every non-corner node of each type as the list of corners it is the mean
 * of, transcribed from the figures of Gmsh's reference manual (section
 * "Node ordering"), independently of the kernel's tables. */
typedef struct {
  int type, node, k, c[8];
} node_def;

static const node_def manual[] = {
    {DTM_TRI6, 3, 2, {0, 1}},
    {DTM_TRI6, 4, 2, {1, 2}},
    {DTM_TRI6, 5, 2, {2, 0}},
    {DTM_QUAD9, 4, 2, {0, 1}},
    {DTM_QUAD9, 5, 2, {1, 2}},
    {DTM_QUAD9, 6, 2, {2, 3}},
    {DTM_QUAD9, 7, 2, {3, 0}},
    {DTM_QUAD9, 8, 4, {0, 1, 2, 3}},
    {DTM_TET10, 4, 2, {0, 1}},
    {DTM_TET10, 5, 2, {1, 2}},
    {DTM_TET10, 6, 2, {0, 2}},
    {DTM_TET10, 7, 2, {0, 3}},
    {DTM_TET10, 8, 2, {2, 3}},
    {DTM_TET10, 9, 2, {1, 3}},
    {DTM_HEX27, 8, 2, {0, 1}},
    {DTM_HEX27, 9, 2, {0, 3}},
    {DTM_HEX27, 10, 2, {0, 4}},
    {DTM_HEX27, 11, 2, {1, 2}},
    {DTM_HEX27, 12, 2, {1, 5}},
    {DTM_HEX27, 13, 2, {2, 3}},
    {DTM_HEX27, 14, 2, {2, 6}},
    {DTM_HEX27, 15, 2, {3, 7}},
    {DTM_HEX27, 16, 2, {4, 5}},
    {DTM_HEX27, 17, 2, {4, 7}},
    {DTM_HEX27, 18, 2, {5, 6}},
    {DTM_HEX27, 19, 2, {6, 7}},
    {DTM_HEX27, 20, 4, {0, 1, 2, 3}},
    {DTM_HEX27, 21, 4, {0, 1, 4, 5}},
    {DTM_HEX27, 22, 4, {0, 3, 4, 7}},
    {DTM_HEX27, 23, 4, {1, 2, 5, 6}},
    {DTM_HEX27, 24, 4, {2, 3, 6, 7}},
    {DTM_HEX27, 25, 4, {4, 5, 6, 7}},
    {DTM_HEX27, 26, 8, {0, 1, 2, 3, 4, 5, 6, 7}},
    {DTM_PRISM18, 6, 2, {0, 1}},
    {DTM_PRISM18, 7, 2, {0, 2}},
    {DTM_PRISM18, 8, 2, {0, 3}},
    {DTM_PRISM18, 9, 2, {1, 2}},
    {DTM_PRISM18, 10, 2, {1, 4}},
    {DTM_PRISM18, 11, 2, {2, 5}},
    {DTM_PRISM18, 12, 2, {3, 4}},
    {DTM_PRISM18, 13, 2, {3, 5}},
    {DTM_PRISM18, 14, 2, {4, 5}},
    {DTM_PRISM18, 15, 4, {0, 1, 3, 4}},
    {DTM_PRISM18, 16, 4, {0, 2, 3, 5}},
    {DTM_PRISM18, 17, 4, {1, 2, 4, 5}},
    {DTM_PYR14, 5, 2, {0, 1}},
    {DTM_PYR14, 6, 2, {0, 3}},
    {DTM_PYR14, 7, 2, {0, 4}},
    {DTM_PYR14, 8, 2, {1, 2}},
    {DTM_PYR14, 9, 2, {1, 4}},
    {DTM_PYR14, 10, 2, {2, 3}},
    {DTM_PYR14, 11, 2, {2, 4}},
    {DTM_PYR14, 12, 2, {3, 4}},
    {DTM_PYR14, 13, 4, {0, 1, 2, 3}},
};

/* Corners of the linear reference elements (Gmsh's). */
static void ref_corner(int parent, int c, double p[3]) {
  static const double tri[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  static const double quad[4][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
  static const double tet[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  static const double pyr[5][3] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}};
  const double *s = NULL;
  double q[3];
  switch (parent) {
  case DTM_TRI3: s = tri[c]; break;
  case DTM_QUAD4: s = quad[c]; break;
  case DTM_TET4: s = tet[c]; break;
  case DTM_PYR5: s = pyr[c]; break;
  case DTM_HEX8:
    q[0] = quad[c % 4][0], q[1] = quad[c % 4][1], q[2] = c < 4 ? -1 : 1;
    s = q;
    break;
  case DTM_PRISM6:
    q[0] = tri[c % 3][0], q[1] = tri[c % 3][1], q[2] = c < 3 ? -1 : 1;
    s = q;
    break;
  default: fail();
  }
  memcpy(p, s, sizeof(double[3]));
}

/* The serendipity types share the first nodes of their complete sibling. */
static int complete_of(int type) {
  switch (type) {
  case DTM_QUAD8: return DTM_QUAD9;
  case DTM_HEX20: return DTM_HEX27;
  case DTM_PRISM15: return DTM_PRISM18;
  case DTM_PYR13: return DTM_PYR14;
  default: return type;
  }
}

static void test_node_order(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], parent = dtm_elem_parent(type), nn, nc, seen = 0;
    dtm_elem_info(type, NULL, &nn);
    dtm_elem_info(parent, NULL, &nc);
    for (int a = 0; a < nc; a++) { /* corners: those of the parent */
      double p[3], q[3];
      dtm_ref_node_uvw(type, a, p);
      ref_corner(parent, a, q);
      for (int i = 0; i < 3; i++) near_abs(p[i], q[i], 0, "corner", type, a);
    }
    for (size_t k = 0; k < sizeof manual / sizeof manual[0]; k++) {
      const node_def *m = &manual[k];
      if (m->type != complete_of(type) || m->node >= nn) continue;
      double p[3], q[3], want[3] = {0, 0, 0};
      for (int j = 0; j < m->k; j++) {
        ref_corner(parent, m->c[j], q);
        for (int i = 0; i < 3; i++) want[i] += q[i] / m->k;
      }
      dtm_ref_node_uvw(type, m->node, p);
      for (int i = 0; i < 3; i++) near_abs(p[i], want[i], 1e-15, "node", type, m->node);
      seen++;
    }
    assert_int_equal(seen, nn - nc);
    /* mid-edge node nc + e lies on edge e of the topology tables */
    const dtm_topology *topo = dtm_elem_topology(type);
    for (int e = 0; e < topo->nedge; e++) {
      double p[3], q0[3], q1[3];
      dtm_ref_node_uvw(type, nc + e, p);
      ref_corner(parent, topo->edge[e][0], q0);
      ref_corner(parent, topo->edge[e][1], q1);
      for (int i = 0; i < 3; i++) near_abs(p[i], 0.5 * (q0[i] + q1[i]), 1e-15, "edge table", type, nc + e);
    }
  }
}

/* Rule coordinates of the reference point (u, v, w): collapsed for the
 * pyramids (w < 1). */
static void to_rule(int type, const double *uvw, double *p) {
  memcpy(p, uvw, sizeof(double[3]));
  if (dtm_elem_parent(type) == DTM_PYR5) p[0] /= 1 - p[2], p[1] /= 1 - p[2];
}

static void test_kronecker(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], nn;
    dtm_elem_info(type, NULL, &nn);
    for (int b = 0; b < nn; b++) {
      double p[3], N[DTM_K_NODES], dN[DTM_K_NODES][3];
      dtm_ref_node(type, b, p);
      dtm_ref_eval(type, p, N, dN);
      for (int a = 0; a < nn; a++) near_abs(N[a], a == b, 1e-14, "N_a(x_b)", type, a);
    }
  }
}

/* A few interior points, in (u, v, w), valid for every reference shape. */
static const double pts[][3] = {{0.1, 0.2, 0.3},  {0.25, 0.05, -0.4}, {-0.3, 0.2, 0.55},
                                {0.05, 0.6, 0.1}, {0.3, 0.3, 0.02},   {-0.6, -0.1, 0.35}};

/* Is (u, v, w) inside the reference element of the type's parent? */
static int inside(int parent, const double *p) {
  double u = p[0], v = p[1], w = p[2];
  switch (parent) {
  case DTM_TRI3: return u > 0 && v > 0 && u + v < 1;
  case DTM_QUAD4: return fabs(u) < 1 && fabs(v) < 1;
  case DTM_TET4: return u > 0 && v > 0 && w > 0 && u + v + w < 1;
  case DTM_HEX8: return fabs(u) < 1 && fabs(v) < 1 && fabs(w) < 1;
  case DTM_PRISM6: return u > 0 && v > 0 && u + v < 1 && fabs(w) < 1;
  case DTM_PYR5: return w > 0 && w < 1 && fabs(u) < 1 - w && fabs(v) < 1 - w;
  default: return 0;
  }
}

/* q(u, v, w): a quadratic with all ten coefficients nonzero. */
static double quadratic(const double *p) {
  double u = p[0], v = p[1], w = p[2];
  return 0.3 - 1.1 * u + 0.7 * v + 0.4 * w + 0.9 * u * u - 0.6 * v * v + 1.3 * w * w + 0.8 * u * v - 0.5 * u * w +
         1.7 * v * w;
}

static void test_partition_and_reproduction(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], nn, d, used = 0;
    dtm_elem_info(type, &d, &nn);
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
      double x[3] = {pts[k][0], pts[k][1], d == 3 ? pts[k][2] : 0}, p[3];
      if (!inside(dtm_elem_parent(type), x)) continue;
      double N[DTM_K_NODES], dN[DTM_K_NODES][3], s = 0, g[3] = {0, 0, 0};
      double lin[3] = {0, 0, 0}, q = 0;
      to_rule(type, x, p);
      dtm_ref_eval(type, p, N, dN);
      for (int a = 0; a < nn; a++) {
        double y[3];
        dtm_ref_node_uvw(type, a, y);
        s += N[a];
        q += N[a] * quadratic(y);
        for (int i = 0; i < 3; i++) g[i] += dN[a][i], lin[i] += N[a] * y[i];
      }
      near_abs(s, 1, 1e-14, "sum N", type, (int)k);
      for (int i = 0; i < 3; i++) {
        near_abs(g[i], 0, 1e-14, "sum dN", type, i);
        near_abs(lin[i], x[i], 1e-14, "linear field", type, i);
      }
      near_abs(q, quadratic(x), 1e-13, "quadratic field", type, (int)k);
      used++;
    }
    assert_true(used >= 3);
  }
}

static void test_gradients(void **state) {
  (void)state;
  const double h = 1e-5;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], nn, d;
    dtm_elem_info(type, &d, &nn);
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; k++) {
      double x[3] = {pts[k][0], pts[k][1], d == 3 ? pts[k][2] : 0}, p[3];
      if (!inside(dtm_elem_parent(type), x)) continue;
      double N[DTM_K_NODES], dN[DTM_K_NODES][3], Np[DTM_K_NODES], Nm[DTM_K_NODES], tmp[DTM_K_NODES][3];
      to_rule(type, x, p);
      dtm_ref_eval(type, p, N, dN);
      for (int i = 0; i < d; i++) {
        double xp[3], xm[3];
        memcpy(xp, x, sizeof xp), memcpy(xm, x, sizeof xm);
        xp[i] += h, xm[i] -= h;
        to_rule(type, xp, p), dtm_ref_eval(type, p, Np, tmp);
        to_rule(type, xm, p), dtm_ref_eval(type, p, Nm, tmp);
        for (int a = 0; a < nn; a++) near_abs(dN[a][i], (Np[a] - Nm[a]) / (2 * h), 2e-8, "dN/du_i", type, a);
      }
      for (int a = 0; a < nn; a++)
        for (int i = d; i < 3; i++) near_abs(dN[a][i], 0, 0, "unused dN", type, a);
      for (int a = nn; a < DTM_K_NODES; a++)
        for (int i = 0; i < 3; i++) near_abs(dN[a][i], 0, 0, "unused row", type, a);
    }
  }
}

/* Pyramid gradients stay finite at the apex (they carry a factor 1 - w). */
static void test_pyramid_apex(void **state) {
  (void)state;
  const int pyr[] = {DTM_PYR13, DTM_PYR14};
  for (int t = 0; t < 2; t++) {
    double N[DTM_K_NODES], dN[DTM_K_NODES][3], p[3];
    int nn;
    dtm_elem_info(pyr[t], NULL, &nn);
    dtm_ref_node(pyr[t], 4, p);
    dtm_ref_eval(pyr[t], p, N, dN);
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < 3; i++) assert_true(isfinite(dN[a][i]));
    near_abs(dN[4][2], 3, 1e-15, "apex dN/dw = 4w - 1", pyr[t], 4);
  }
}

/* Exact integral of u^i v^j w^k over the reference element of parent. */
static double fact(int n) { return n <= 1 ? 1 : n * fact(n - 1); }
static double line_moment(int i) { return i % 2 ? 0 : 2.0 / (i + 1); } /* [-1,1] */
static double exact(int parent, int i, int j, int k) {
  switch (parent) {
  case DTM_TRI3: return fact(i) * fact(j) / fact(i + j + 2);
  case DTM_TET4: return fact(i) * fact(j) * fact(k) / fact(i + j + k + 3);
  case DTM_QUAD4: return line_moment(i) * line_moment(j);
  case DTM_HEX8: return line_moment(i) * line_moment(j) * line_moment(k);
  case DTM_PRISM6: return fact(i) * fact(j) / fact(i + j + 2) * line_moment(k);
  case DTM_PYR5: /* int_0^1 (1-w)^(i+j+2) w^k times the (a, b) moments */
    return line_moment(i) * line_moment(j) * fact(k) * fact(i + j + 2) / fact(i + j + k + 3);
  default: return NAN;
  }
}

/* Claimed exactness: total degree (simplices, pyramids in (u, v, w)), per
 * direction (quads, hexes) or triangle degree x line degree (prisms). */
static int within(int parent, int i, int j, int k) {
  switch (parent) {
  case DTM_TRI3: return i + j <= 4 && k == 0;
  case DTM_TET4: return i + j + k <= 5;
  case DTM_QUAD4: return i <= 5 && j <= 5 && k == 0;
  case DTM_HEX8: return i <= 5 && j <= 5 && k <= 5;
  case DTM_PRISM6: return i + j <= 4 && k <= 5;
  case DTM_PYR5: return i + j + k <= 5;
  default: return 0;
  }
}

static void test_rules(void **state) {
  (void)state;
  for (size_t t = 0; t < NTYPES; t++) {
    int type = types[t], parent = dtm_elem_parent(type), checked = 0;
    dtm_qrule q;
    dtm_ref_rule(type, &q);
    assert_true(q.n > 0 && q.n <= DTM_K_QP);
    for (int m = 0; m < q.n; m++) assert_true(q.w[m] > 0); /* positive weights */
    for (int i = 0; i <= 5; i++)
      for (int j = 0; j <= 5; j++)
        for (int k = 0; k <= 5; k++) {
          if (!within(parent, i, j, k)) continue;
          double s = 0, want = exact(parent, i, j, k);
          for (int m = 0; m < q.n; m++) {
            double u = q.p[m][0], v = q.p[m][1], w = q.p[m][2];
            if (parent == DTM_PYR5) u *= 1 - w, v *= 1 - w; /* collapsed */
            s += q.w[m] * pow(u, i) * pow(v, j) * pow(w, k);
          }
          if (!(fabs(s - want) <= 1e-14 * fabs(want) + 1e-15))
            fail_msg("%s rule: u^%d v^%d w^%d gives %.17g, want %.17g", dtm_elem_name(type), i, j, k, s, want);
          checked++;
        }
    assert_true(checked >= 15);
  }
}

int main(int argc, char **argv) {
  (void)argc, (void)argv; /* source dir and dtmap binary: not needed */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_catalogue), cmocka_unit_test(test_node_order),
      cmocka_unit_test(test_kronecker), cmocka_unit_test(test_partition_and_reproduction),
      cmocka_unit_test(test_gradients), cmocka_unit_test(test_pyramid_apex),
      cmocka_unit_test(test_rules),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
