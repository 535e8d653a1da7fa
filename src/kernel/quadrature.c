/* Full-integration quadrature rules of the supported types, exact for the
 * stiffness and for the row sums of the consistent mass of affine elements
 * (parallelogram quadrangles, parallelepiped hexahedra, prisms with
 * parallel triangles and vertical edges, pyramids with a parallelogram
 * base):
 *   line2  2-point Gauss;  tri3  3-point degree-2 rule;  quad4  2x2 Gauss;
 *   tet4   4-point degree-2 rule;  hex8  2x2x2 Gauss;
 *   prism6 3-point triangle rule x 2-point Gauss along w;
 *   pyr5   3x3x3 Gauss on the collapsed cube (a, b) in [-1,1]^2, w in
 *          [0,1], weights times the Duffy factor (1 - w)^2. Gmsh's rational
 *          pyramid basis is polynomial in (a, b, w), its gradients are
 *          bilinear in (a, b) and free of w, so the rule integrates the
 *          stiffness (degree 2 per variable) and the mass row sums (degree
 *          3 in w) exactly on affine pyramids, and the volume on any.
 * Second-order types get rules exact for the whole consistent mass N_a N_b
 * (so also for its diagonal, which HRZ lumping needs, and its row sums)
 * and for the stiffness of straight-sided elements with mid-side nodes at
 * the middle (then the map is affine and det J constant; curved elements
 * are integrated approximately, as every code does). All weights are
 * positive, which the safe length (length.c) relies on:
 *   tri6          6-point degree-4 rule (Strang-Fix/Dunavant): mass degree
 *                 4, stiffness degree 2;
 *   tet10         14-point degree-5 rule (Walkington; Keast's degree-4
 *                 11-point rule has a negative weight): mass degree 4;
 *   quad8, quad9  3x3 Gauss (degree 5 per direction; the mass is degree 4
 *                 per direction);
 *   hex20, hex27  3x3x3 Gauss;
 *   prism15, 18   the 6-point degree-4 triangle rule x 3-point Gauss in w
 *                 (the mass is degree 4 in (u, v) and in w);
 *   pyr13, pyr14  3x3 Gauss in (a, b) x 3-point Gauss-Jacobi in w for the
 *                 weight (1 - w)^2 (the Duffy factor), exact for degree 5
 *                 in w times that weight: the mass is degree 4 in a, b
 *                 and w, the stiffness 4 in a, b and 2 in w (ref_pyramid.c).
 * The constants were computed to 50 digits (mpmath: moment equations for
 * the simplex rules, roots of the degree-3 orthogonal polynomial
 * 56 w^3 - 63 w^2 + 18 w - 1 for the Gauss-Jacobi rule) and are checked
 * against exact monomial integrals in tests/t105. */
#include <math.h>

#include "kernel-impl.h"

/* Gauss-Legendre points and weights on [-1,1], n = 2 or 3. */
static void gauss(int n, double *x, double *w) {
  if (n == 2) {
    x[0] = -1 / sqrt(3.0), x[1] = -x[0];
    w[0] = w[1] = 1;
  } else {
    x[0] = -sqrt(0.6), x[1] = 0, x[2] = -x[0];
    w[0] = w[2] = 5.0 / 9, w[1] = 8.0 / 9;
  }
}

static void add(dtm_qrule *q, double u, double v, double w, double wt) {
  q->p[q->n][0] = u, q->p[q->n][1] = v, q->p[q->n][2] = w;
  q->w[q->n++] = wt;
}

/* Tensor Gauss rule with n points per direction in the first d directions. */
static void tensor(dtm_qrule *q, int d, int n) {
  double x[3], w[3];
  gauss(n, x, w);
  int nk = d > 2 ? n : 1, nj = d > 1 ? n : 1;
  for (int k = 0; k < nk; k++)
    for (int j = 0; j < nj; j++)
      for (int i = 0; i < n; i++)
        add(q, x[i], d > 1 ? x[j] : 0, d > 2 ? x[k] : 0, w[i] * (d > 1 ? w[j] : 1) * (d > 2 ? w[k] : 1));
}

/* Degree-2 rules on the unit triangle and tetrahedron, times a factor
 * along w for prisms (w = 0, wt = 1 for the plain triangle). */
static void tri3pt(dtm_qrule *q, double w, double wt) {
  add(q, 1.0 / 6, 1.0 / 6, w, wt / 6);
  add(q, 2.0 / 3, 1.0 / 6, w, wt / 6);
  add(q, 1.0 / 6, 2.0 / 3, w, wt / 6);
}

static void tet4pt(dtm_qrule *q) {
  const double a = (5 - sqrt(5.0)) / 20, b = (5 + 3 * sqrt(5.0)) / 20;
  add(q, a, a, a, 1.0 / 24);
  add(q, b, a, a, 1.0 / 24);
  add(q, a, b, a, 1.0 / 24);
  add(q, a, a, b, 1.0 / 24);
}

void dtm_ref_rule_c3d10(dtm_qrule *q) {
  q->n = 0;
  tet4pt(q);
}

/* Degree-4 rule on the unit triangle, 6 points in two orbits
 * (a, a, 1 - 2a), times a factor along w as tri3pt. */
static void tri6pt(dtm_qrule *q, double w, double wt) {
  static const double a[2] = {0.44594849091596488632, 0.091576213509770743460};
  static const double c[2] = {0.11169079483900573285, 0.054975871827660933819};
  for (int k = 0; k < 2; k++) {
    double b = 1 - 2 * a[k];
    add(q, a[k], a[k], w, wt * c[k]);
    add(q, b, a[k], w, wt * c[k]);
    add(q, a[k], b, w, wt * c[k]);
  }
}

/* Degree-5 rule on the unit tetrahedron, 14 points: two orbits (a, a, a,
 * 1 - 3a) of 4 points and one (b, b, 1/2 - b, 1/2 - b) of 6 (barycentric). */
static void tet14pt(dtm_qrule *q) {
  static const double a[2] = {0.092735250310891226402, 0.31088591926330060980};
  static const double c[2] = {0.012248840519393658257, 0.018781320953002641800};
  const double b = 0.045503704125649649492, e = 0.5 - b, cb = 0.0070910034628469110730;
  for (int k = 0; k < 2; k++) {
    double r = 1 - 3 * a[k];
    add(q, a[k], a[k], a[k], c[k]);
    add(q, r, a[k], a[k], c[k]);
    add(q, a[k], r, a[k], c[k]);
    add(q, a[k], a[k], r, c[k]);
  }
  /* the six ways to put b on two of the four barycentric coordinates */
  add(q, b, e, e, cb);
  add(q, e, b, e, cb);
  add(q, e, e, b, cb);
  add(q, e, b, b, cb);
  add(q, b, e, b, cb);
  add(q, b, b, e, cb);
}

static void prism18pt(dtm_qrule *q) {
  double x[3], w[3];
  gauss(3, x, w);
  for (int k = 0; k < 3; k++) tri6pt(q, x[k], w[k]);
}

/* 3x3 Gauss in (a, b) x 3-point Gauss-Jacobi on [0, 1] for (1 - w)^2. */
static void pyramid27gj(dtm_qrule *q) {
  static const double z[3] = {0.072994024073149732156, 0.34700376603835188472, 0.70500220988849838312};
  static const double wz[3] = {0.15713636106488661332, 0.14624626925986602200, 0.029950703008580698011};
  double x[3], w[3];
  gauss(3, x, w);
  for (int k = 0; k < 3; k++)
    for (int j = 0; j < 3; j++)
      for (int i = 0; i < 3; i++) add(q, x[i], x[j], z[k], w[i] * w[j] * wz[k]);
}

static void prism(dtm_qrule *q) {
  double x[3], w[3];
  gauss(2, x, w);
  for (int k = 0; k < 2; k++) tri3pt(q, x[k], w[k]);
}

static void pyramid(dtm_qrule *q) {
  double x[3], w[3];
  gauss(3, x, w);
  for (int k = 0; k < 3; k++) {
    double z = 0.5 * (1 + x[k]), wz = 0.5 * w[k] * (1 - z) * (1 - z);
    for (int j = 0; j < 3; j++)
      for (int i = 0; i < 3; i++) add(q, x[i], x[j], z, w[i] * w[j] * wz);
  }
}

void dtm_ref_rule(int type, dtm_qrule *q) {
  q->n = 0;
  switch (type) {
  case DTM_LINE2: tensor(q, 1, 2); break;
  case DTM_TRI3: tri3pt(q, 0, 1); break;
  case DTM_QUAD4: tensor(q, 2, 2); break;
  case DTM_TET4: tet4pt(q); break;
  case DTM_HEX8: tensor(q, 3, 2); break;
  case DTM_PRISM6: prism(q); break;
  case DTM_PYR5: pyramid(q); break;
  case DTM_TRI6: tri6pt(q, 0, 1); break;
  case DTM_TET10: tet14pt(q); break;
  case DTM_QUAD8:
  case DTM_QUAD9: tensor(q, 2, 3); break;
  case DTM_HEX20:
  case DTM_HEX27: tensor(q, 3, 3); break;
  case DTM_PRISM15:
  case DTM_PRISM18: prism18pt(q); break;
  case DTM_PYR13:
  case DTM_PYR14: pyramid27gj(q); break;
  default: break;
  }
}
