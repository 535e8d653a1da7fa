/* Quadrature rules of rising accuracy for curved second-order elements
 * (curved.c), indexed by a level n = the number of Gauss-Legendre points
 * per direction:
 *   quadrangles, hexahedra  n-point Gauss per direction on [-1, 1]: exact
 *                           for degree 2n - 1 in each variable;
 *   triangles               the collapsed (Duffy) product u = a (1 - b),
 *                           v = b, (a, b) in [0, 1]^2 with Jacobian 1 - b:
 *                           a polynomial of total degree p becomes degree
 *                           p in a and p + 1 in b, so the rule is exact
 *                           for p <= 2n - 2;
 *   tetrahedra              u = a (1 - b)(1 - c), v = b (1 - c), w = c,
 *                           Jacobian (1 - b)(1 - c)^2: exact for total
 *                           degree p <= 2n - 3;
 *   prisms                  the triangle rule times n-point Gauss in w.
 * Every weight is positive (products of Gauss weights and of positive
 * Duffy factors), which the safe length relies on (length.c). The
 * Gauss-Legendre points are the roots of P_n found by Newton's method from
 * Tricomi's approximation, the weights 2 / ((1 - x^2) P_n'(x)^2): both to
 * a few ulps for the n <= DTM_K_LEVEL_MAX used here (t115 checks monomials
 * up to the stated degrees against their exact integrals). Pyramids get no
 * levelled rule (their basis is rational): level 0 is returned. */
#include <math.h>

#include "kernel-impl.h"

/* Legendre P_n and its derivative at x. */
static void legendre(int n, double x, double *p, double *dp) {
  double p0 = 1, p1 = x;
  for (int k = 2; k <= n; k++) {
    double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
    p0 = p1, p1 = p2;
  }
  *p = n == 0 ? 1 : p1;
  *dp = n * (x * *p - p0) / (x * x - 1);
}

void dtm_gauss_legendre(int n, double *x, double *w) {
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; i++) {
    double t = cos(pi * (i + 0.75) / (n + 0.5)), p, dp;
    for (int it = 0; it < 100; it++) {
      legendre(n, t, &p, &dp);
      double step = p / dp;
      t -= step;
      if (fabs(step) < 1e-16) break;
    }
    legendre(n, t, &p, &dp);
    x[n - 1 - i] = t; /* ascending */
    w[n - 1 - i] = 2 / ((1 - t * t) * dp * dp);
  }
}

static void add(dtm_qrule *q, double u, double v, double w, double wt) {
  q->p[q->n][0] = u, q->p[q->n][1] = v, q->p[q->n][2] = w;
  q->w[q->n++] = wt;
}

/* Gauss points mapped to [0, 1]. */
static void unit_gauss(int n, double *x, double *w) {
  dtm_gauss_legendre(n, x, w);
  for (int i = 0; i < n; i++) x[i] = 0.5 * (1 + x[i]), w[i] *= 0.5;
}

static void tensor(dtm_qrule *q, int d, int n) {
  double x[DTM_K_LEVEL_MAX], w[DTM_K_LEVEL_MAX];
  dtm_gauss_legendre(n, x, w);
  int nk = d > 2 ? n : 1;
  for (int k = 0; k < nk; k++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++) add(q, x[i], x[j], d > 2 ? x[k] : 0, w[i] * w[j] * (d > 2 ? w[k] : 1));
}

/* The collapsed triangle rule at height w with factor wt. */
static void triangle(dtm_qrule *q, int n, double w, double wt) {
  double x[DTM_K_LEVEL_MAX], c[DTM_K_LEVEL_MAX];
  unit_gauss(n, x, c);
  for (int j = 0; j < n; j++)
    for (int i = 0; i < n; i++) add(q, x[i] * (1 - x[j]), x[j], w, wt * c[i] * c[j] * (1 - x[j]));
}

static void tetrahedron(dtm_qrule *q, int n) {
  double x[DTM_K_LEVEL_MAX], c[DTM_K_LEVEL_MAX];
  unit_gauss(n, x, c);
  for (int k = 0; k < n; k++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++) {
        double s = 1 - x[k], r = 1 - x[j];
        add(q, x[i] * r * s, x[j] * s, x[k], c[i] * c[j] * c[k] * r * s * s);
      }
}

static void prism(dtm_qrule *q, int n) {
  double x[DTM_K_LEVEL_MAX], w[DTM_K_LEVEL_MAX];
  dtm_gauss_legendre(n, x, w);
  for (int k = 0; k < n; k++) triangle(q, n, x[k], w[k]);
}

int dtm_ref_rule_level(int type, int n, dtm_qrule *q) {
  q->n = 0;
  if (type == DTM_TET10 && n == DTM_K_RULE_C3D10) return dtm_ref_rule_c3d10(q), n;
  if (n < 1 || n > DTM_K_LEVEL_MAX) return 0;
  switch (type) {
  case DTM_TRI3:
  case DTM_TRI6: triangle(q, n, 0, 1); break;
  case DTM_TET4:
  case DTM_TET10: tetrahedron(q, n); break;
  case DTM_QUAD4:
  case DTM_QUAD8:
  case DTM_QUAD9: tensor(q, 2, n); break;
  case DTM_HEX8:
  case DTM_HEX20:
  case DTM_HEX27: tensor(q, 3, n); break;
  case DTM_PRISM6:
  case DTM_PRISM15:
  case DTM_PRISM18: prism(q, n); break;
  default: return 0;
  }
  return n;
}
