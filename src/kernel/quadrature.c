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
 *          3 in w) exactly on affine pyramids, and the volume on any. */
#include <math.h>

#include "kernel/kernel_impl.h"

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
        add(q, x[i], d > 1 ? x[j] : 0, d > 2 ? x[k] : 0,
            w[i] * (d > 1 ? w[j] : 1) * (d > 2 ? w[k] : 1));
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
  default: break;
  }
}
