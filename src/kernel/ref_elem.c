/* Reference elements: shape functions and their gradients with respect to
 * Gmsh's reference coordinates, for every supported type, in Gmsh's node
 * ordering. Line [-1,1]; triangle and tetrahedron on the unit simplex;
 * quadrangle [-1,1]^2 and hexahedron [-1,1]^3 (bottom 0-1-2-3, top 4-5-6-7);
 * prism = unit triangle x [-1,1] (bottom 0-1-2, top 3-4-5); pyramid with
 * base [-1,1]^2 at w = 0 (0-1-2-3) and apex 4 at (0,0,1), with Gmsh's
 * rational first-order basis N_i = (1 - w + xi_i u)(1 - w + eta_i v) /
 * (4 (1 - w)), N_4 = w. Pyramids are evaluated in collapsed coordinates
 * (a, b, w), u = (1 - w) a, v = (1 - w) b, where the basis and its
 * gradients are polynomial (the gradients depend on a and b only).
 * Second-order types are in ref_quadratic.c and ref_pyramid.c, the node
 * coordinates in ref_nodes.c. */
#include <string.h>

#include "kernel-impl.h"

/* Corner signs of the quadrangle, hexahedron and pyramid base (the same
 * tables are in ref_nodes.c). */
static const double sx[8] = {-1, 1, 1, -1, -1, 1, 1, -1};
static const double sy[8] = {-1, -1, 1, 1, -1, -1, 1, 1};
static const double sz[8] = {-1, -1, -1, -1, 1, 1, 1, 1};

static void line2(const double *p, double *N, double (*dN)[3]) {
  N[0] = 0.5 * (1 - p[0]);
  N[1] = 0.5 * (1 + p[0]);
  dN[0][0] = -0.5;
  dN[1][0] = 0.5;
}

static void simplex(int d, const double *p, double *N, double (*dN)[3]) {
  N[0] = 1;
  for (int i = 0; i < d; i++) {
    N[0] -= p[i];
    N[i + 1] = p[i];
    dN[0][i] = -1;
    dN[i + 1][i] = 1;
  }
}

static void quad4(const double *p, double *N, double (*dN)[3]) {
  for (int a = 0; a < 4; a++) {
    double fu = 1 + sx[a] * p[0], fv = 1 + sy[a] * p[1];
    N[a] = 0.25 * fu * fv;
    dN[a][0] = 0.25 * sx[a] * fv;
    dN[a][1] = 0.25 * sy[a] * fu;
  }
}

static void hex8(const double *p, double *N, double (*dN)[3]) {
  for (int a = 0; a < 8; a++) {
    double fu = 1 + sx[a] * p[0], fv = 1 + sy[a] * p[1], fw = 1 + sz[a] * p[2];
    N[a] = 0.125 * fu * fv * fw;
    dN[a][0] = 0.125 * sx[a] * fv * fw;
    dN[a][1] = 0.125 * sy[a] * fu * fw;
    dN[a][2] = 0.125 * sz[a] * fu * fv;
  }
}

static void prism6(const double *p, double *N, double (*dN)[3]) {
  double t[3], dt[3][3] = {{0}};
  simplex(2, p, t, dt);
  for (int k = 0; k < 2; k++) {
    double s = k ? 1 : -1, h = 0.5 * (1 + s * p[2]);
    for (int i = 0; i < 3; i++) {
      int a = 3 * k + i;
      N[a] = t[i] * h;
      dN[a][0] = dt[i][0] * h;
      dN[a][1] = dt[i][1] * h;
      dN[a][2] = 0.5 * s * t[i];
    }
  }
}

/* p = (a, b, w) collapsed; gradients with respect to (u, v, w). */
static void pyr5(const double *p, double *N, double (*dN)[3]) {
  double a = p[0], b = p[1], w = p[2];
  for (int i = 0; i < 4; i++) {
    double fa = 1 + sx[i] * a, fb = 1 + sy[i] * b;
    N[i] = 0.25 * (1 - w) * fa * fb;
    dN[i][0] = 0.25 * sx[i] * fb;
    dN[i][1] = 0.25 * sy[i] * fa;
    dN[i][2] = 0.25 * (sx[i] * sy[i] * a * b - 1);
  }
  N[4] = w;
  dN[4][0] = dN[4][1] = 0;
  dN[4][2] = 1;
}

void dtm_ref_eval(int type, const double p[3], double *N, double (*dN)[3]) {
  memset(dN, 0, sizeof(double[DTM_K_NODES][3]));
  switch (type) {
  case DTM_LINE2: line2(p, N, dN); break;
  case DTM_TRI3: simplex(2, p, N, dN); break;
  case DTM_QUAD4: quad4(p, N, dN); break;
  case DTM_TET4: simplex(3, p, N, dN); break;
  case DTM_HEX8: hex8(p, N, dN); break;
  case DTM_PRISM6: prism6(p, N, dN); break;
  case DTM_PYR5: pyr5(p, N, dN); break;
  case DTM_PYR13:
  case DTM_PYR14: dtm_ref_eval_pyramid2(type, p, N, dN); break;
  default:
    if (dtm_elem_parent(type) > 0 && dtm_elem_parent(type) != type) dtm_ref_eval_quadratic(type, p, N, dN);
    break;
  }
}
