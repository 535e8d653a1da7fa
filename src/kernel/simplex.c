/* Barycentric metric of the linear simplices, the fast path under every
 * simplex kernel: with g_a the gradients of the barycentric coordinates
 * (taken in the element's own line or plane for line2 and tri3), it forms
 * S = sum_a g_a g_a^T (d x d) and the measure, straight from edge vectors
 * and cross products, without the generic quadrature machinery. S is
 * returned as scale * s with s built from the unscaled cross products and
 * scale = 1/det(J)^2, which keeps the division off the critical path of
 * the eigenvalue computations that follow (they are homogeneous in S). A simplex
 * is degenerate or inverted unless its Jacobian determinant exceeds 32 eps
 * times the product of the edge lengths from node 0 (see map.c). */
#include <float.h>
#include <math.h>

#include "dtmap/error.h"
#include "kernel-impl.h"

#define FLAT_TOL (32 * DBL_EPSILON)

static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *c) {
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
}

static int degenerate(int type, double measure) {
  return DTM_ERR(DTM_ERR_INPUT, "degenerate or inverted %s element (signed measure %g)", dtm_elem_name(type), measure);
}

/* s += c c^T for a 3-vector c. */
static void add_outer3(double s[6], const double *c) {
  s[0] += c[0] * c[0], s[1] += c[1] * c[1], s[2] += c[2] * c[2];
  s[3] += c[0] * c[1], s[4] += c[0] * c[2], s[5] += c[1] * c[2];
}

static int tet(const double *x, double s[6], double *scale, double *measure) {
  double e[3][3], c[4][3];
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < 3; i++) e[k][i] = x[3 * (k + 1) + i] - x[i];
  cross3(e[1], e[2], c[1]);
  cross3(e[2], e[0], c[2]);
  cross3(e[0], e[1], c[3]);
  double dj = dot3(e[0], c[1]);
  *measure = dj / 6;
  double bound = dot3(e[0], e[0]) * dot3(e[1], e[1]) * dot3(e[2], e[2]);
  if (!(dj > 0 && dj * dj > FLAT_TOL * FLAT_TOL * bound) || !isfinite(dj)) return degenerate(DTM_TET4, *measure);
  for (int i = 0; i < 3; i++) c[0][i] = -(c[1][i] + c[2][i] + c[3][i]);
  *scale = 1 / (dj * dj);
  for (int i = 0; i < 6; i++) s[i] = 0;
  for (int a = 0; a < 4; a++) add_outer3(s, c[a]);
  return DTM_OK;
}

/* In the frame with e1 along the x axis: e1 = (l, 0), e2 = (p, h), and
 * det J = l h; the barycentric gradients are (h, -p), (0, l) and minus
 * their sum, over det J. */
static int tri(const double *x, double s[6], double *scale, double *measure) {
  double e1[3], e2[3], n[3];
  for (int i = 0; i < 3; i++) e1[i] = x[3 + i] - x[i], e2[i] = x[6 + i] - x[i];
  cross3(e1, e2, n);
  double l2 = dot3(e1, e1), dj = sqrt(dot3(n, n));
  *measure = dj / 2;
  if (!(dj > FLAT_TOL * sqrt(l2 * dot3(e2, e2))) || !isfinite(dj)) return degenerate(DTM_TRI3, *measure);
  double l = sqrt(l2), p = dot3(e1, e2) / l, h = dj / l;
  double c[3][2] = {{h, -p}, {0, l}, {-h, p - l}};
  *scale = 1 / (dj * dj);
  for (int i = 0; i < 6; i++) s[i] = 0;
  for (int a = 0; a < 3; a++) {
    s[0] += c[a][0] * c[a][0];
    s[1] += c[a][1] * c[a][1];
    s[3] += c[a][0] * c[a][1];
  }
  return DTM_OK;
}

static int line(const double *x, double s[6], double *scale, double *measure) {
  double e[3] = {x[3] - x[0], x[4] - x[1], x[5] - x[2]};
  double l2 = dot3(e, e);
  *measure = sqrt(l2);
  if (!(l2 > 0) || !isfinite(l2)) return degenerate(DTM_LINE2, *measure);
  for (int i = 0; i < 6; i++) s[i] = 0;
  s[0] = 2;
  *scale = 1 / l2;
  return DTM_OK;
}

int dtm_simplex_metric(int type, const double *x, int *d, double s[6], double *scale, double *measure) {
  switch (type) {
  case DTM_TET4: *d = 3; return tet(x, s, scale, measure);
  case DTM_TRI3: *d = 2; return tri(x, s, scale, measure);
  case DTM_LINE2: *d = 1; return line(x, s, scale, measure);
  default: return DTM_ERR(DTM_ERR_INTERNAL, "%s is not a simplex", dtm_elem_name(type));
  }
}
