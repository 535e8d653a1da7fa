/* Shape functions of the second-order pyramids pyr14 and pyr13, in Gmsh's
 * node ordering, evaluated in collapsed coordinates (a, b, w), u = (1 - w)
 * a, v = (1 - w) b, like pyr5 (ref_elem.c); gradients are with respect to
 * (u, v, w). Gmsh's space for these (Bergot's, BergotBasis.cpp) is
 * spanned by a^i b^j (1 - w)^max(i,j) w^k with i, j <= 2 and k <= 2 -
 * max(i, j), without (i, j) = (2, 2) for the serendipity pyr13. Its nodal
 * basis, written out (Q_n the quad9 or quad8 function of base node n on
 * the base square, B_c the bilinear function of base corner c):
 *   apex                            w (2 w - 1)
 *   lateral edge node above corner c 4 w (1 - w) B_c(a, b)
 *   base edge node and base centre  Q_n(a, b) (1 - w)^2
 *   base corner c                   Q_c(a, b) (1 - w)^2 - w (1 - w) B_c(a, b)
 * Each lies in the space, is 1 at its node and 0 at the others (a corner
 * function is Q_c/4 = 1/4 at the lateral node above it before the
 * correction), and they sum to 1; the pyr13 base functions are exactly the
 * quad8 ones, so it is the classical 13-node pyramid. For f = F(a, b)
 * phi(w), d/du = F_a phi/(1 - w), d/dw = F phi' + (a F_a + b F_b)
 * phi/(1 - w); every phi here carries a factor (1 - w), so the gradients
 * below are polynomial and finite at the apex. */
#include "kernel-impl.h"

static const double sx[4] = {-1, 1, 1, -1};
static const double sy[4] = {-1, -1, 1, 1};

/* f = F(a, b) phi(w) with phi = (1 - w) psi(w): gradient from F, F_a, F_b,
 * psi and phi'. */
static void grad(double a, double b, double F, double Fa, double Fb, double psi, double dphi, double *g) {
  g[0] = Fa * psi;
  g[1] = Fb * psi;
  g[2] = F * dphi + (a * Fa + b * Fb) * psi;
}

/* Index of the base corner whose signs are (qa, qb). */
static int corner_of(double qa, double qb) {
  for (int c = 0; c < 4; c++)
    if (sx[c] == qa && sy[c] == qb) return c;
  return 0;
}

/* Index of the quad8/quad9 node at (qa, qb). */
static int quad_node(int quad, int nq, double qa, double qb) {
  const double(*q)[3] = dtm_ref_nodes(quad);
  for (int k = 0; k < nq; k++)
    if (q[k][0] == qa && q[k][1] == qb) return k;
  return 0;
}

void dtm_ref_eval_pyramid2(int type, const double p[3], double *N, double (*dN)[3]) {
  int quad = type == DTM_PYR14 ? DTM_QUAD9 : DTM_QUAD8;
  int nn = type == DTM_PYR14 ? 14 : 13, nq = type == DTM_PYR14 ? 9 : 8;
  const double(*t)[3] = dtm_ref_nodes(type);
  double a = p[0], b = p[1], w = p[2], ab[3] = {a, b, 0}, g[3];
  double Q[DTM_K_NODES], dQ[DTM_K_NODES][3];
  for (int k = 0; k < nq; k++) dQ[k][0] = dQ[k][1] = dQ[k][2] = 0;
  dtm_ref_eval_quadratic(quad, ab, Q, dQ);
  for (int n = 0; n < nn; n++) {
    const double *q = t[n];
    if (q[2] == 1) { /* apex */
      N[n] = w * (2 * w - 1);
      dN[n][0] = dN[n][1] = 0, dN[n][2] = 4 * w - 1;
      continue;
    }
    double qa = q[0] / (1 - q[2]), qb = q[1] / (1 - q[2]);
    int c = corner_of(qa, qb);
    double B = 0.25 * (1 + sx[c] * a) * (1 + sy[c] * b);
    double Ba = 0.25 * sx[c] * (1 + sy[c] * b), Bb = 0.25 * sy[c] * (1 + sx[c] * a);
    if (q[2] > 0) { /* lateral edge: phi = 4 w (1 - w) */
      N[n] = 4 * w * (1 - w) * B;
      grad(a, b, B, Ba, Bb, 4 * w, 4 - 8 * w, dN[n]);
      continue;
    }
    int k = quad_node(quad, nq, qa, qb); /* base: phi = (1 - w)^2 */
    N[n] = Q[k] * (1 - w) * (1 - w);
    grad(a, b, Q[k], dQ[k][0], dQ[k][1], 1 - w, -2 * (1 - w), dN[n]);
    if (n >= 4) continue;
    N[n] -= w * (1 - w) * B; /* corner: phi = w (1 - w) */
    grad(a, b, B, Ba, Bb, w, 1 - 2 * w, g);
    for (int i = 0; i < 3; i++) dN[n][i] -= g[i];
  }
}
