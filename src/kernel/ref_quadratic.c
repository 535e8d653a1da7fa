/* Shape functions of the second-order types other than pyramids, in Gmsh's
 * node ordering, from each node's reference coordinates (ref_nodes.c):
 *   tri6, tet10    complete quadratic Lagrange on the simplex: corner i
 *                  L_i (2 L_i - 1), edge node on i-j 4 L_i L_j (L the
 *                  barycentric coordinates);
 *   quad9, hex27   tensor products of the 1D quadratic Lagrange functions
 *                  l_-1(x) = x (x - 1)/2, l_0 = 1 - x^2, l_1 = x (x + 1)/2;
 *   quad8, hex20   serendipity: corner s 2^-d prod_i (1 + s_i x_i)
 *                  (sum_i s_i x_i - d + 1), mid-edge node (s_k = 0)
 *                  2^(1-d) (1 - x_k^2) prod_(i != k) (1 + s_i x_i);
 *   prism18        quadratic triangle x quadratic line;
 *   prism15        serendipity wedge, spanning P2(u, v) x P1(w) plus
 *                  P1(u, v) w^2 (Gmsh's space): corner i at level s
 *                  L_i (2 L_i - 1)(1 + s w)/2 - L_i (1 - w^2)/2, triangle
 *                  edge node 2 L_i L_j (1 + s w), vertical edge node
 *                  L_i (1 - w^2).
 * A nodal basis is fixed by its space and its nodes, so these are Gmsh's
 * functions. Gradients are with respect to (u, v, w). Each node's role
 * (corner, edge, ...) is read off its reference coordinates
 * (dtm_ref_nodes). */
#include "kernel-impl.h"

/* Barycentric coordinates of a d-simplex at p and their gradients. */
static void barycentric(int d, const double *p, double *L, double (*dL)[3]) {
  L[0] = 1;
  for (int j = 0; j < 3; j++) dL[0][j] = 0;
  for (int i = 0; i < d; i++) {
    L[0] -= p[i];
    dL[0][i] = -1;
    L[i + 1] = p[i];
    for (int j = 0; j < 3; j++) dL[i + 1][j] = j == i;
  }
}

/* The barycentric indices (i, j) of a node of the quadratic d-simplex at
 * reference point q: i == j at a corner. */
static void simplex_pair(int d, const double *q, int *i, int *j) {
  *i = *j = -1;
  for (int k = 0; k <= d; k++) {
    double L = k ? q[k - 1] : 1 - q[0] - q[1] - (d > 2 ? q[2] : 0);
    if (L < 0.25) continue;
    if (*i < 0) *i = k;
    *j = k;
  }
}

/* Quadratic Lagrange function of node pair (i, j), value and gradient. */
static double p2(const double *L, const double (*dL)[3], int i, int j, double *g) {
  for (int k = 0; k < 3; k++) g[k] = i == j ? (4 * L[i] - 1) * dL[i][k] : 4 * (dL[i][k] * L[j] + L[i] * dL[j][k]);
  return i == j ? L[i] * (2 * L[i] - 1) : 4 * L[i] * L[j];
}

static void simplex2(int type, int d, int nn, const double *p, double *N, double (*dN)[3]) {
  const double(*q)[3] = dtm_ref_nodes(type);
  double L[4], dL[4][3];
  barycentric(d, p, L, dL);
  for (int a = 0; a < nn; a++) {
    int i, j;
    simplex_pair(d, q[a], &i, &j);
    N[a] = p2(L, (const double(*)[3])dL, i, j, dN[a]);
  }
}

/* 1D quadratic Lagrange function of the node at s in {-1, 0, 1}. */
static double lag(double s, double x, double *dl) {
  if (s == 0) {
    *dl = -2 * x;
    return 1 - x * x;
  }
  *dl = x + s / 2;
  return x * (x + s) / 2;
}

static void tensor2(int type, int d, int nn, const double *p, double *N, double (*dN)[3]) {
  const double(*q)[3] = dtm_ref_nodes(type);
  double l[3], dl[3];
  for (int a = 0; a < nn; a++) {
    N[a] = 1;
    for (int i = 0; i < d; i++) N[a] *= l[i] = lag(q[a][i], p[i], &dl[i]);
    for (int k = 0; k < d; k++) {
      dN[a][k] = dl[k];
      for (int i = 0; i < d; i++)
        if (i != k) dN[a][k] *= l[i];
    }
  }
}

/* Product of f[i] over i < d except i = skip, and its gradient given the
 * factor derivatives df[i] (the skipped direction gets 0). */
static double product(int d, int skip, const double *f, const double *df, double *g) {
  double v = 1;
  for (int i = 0; i < d; i++) v *= i == skip ? 1 : f[i];
  for (int k = 0; k < d; k++) {
    g[k] = 0;
    if (k == skip) continue;
    g[k] = df[k];
    for (int i = 0; i < d; i++)
      if (i != k && i != skip) g[k] *= f[i];
  }
  return v;
}

static void serendipity(int type, int d, int nn, const double *p, double *N, double (*dN)[3]) {
  const double(*t)[3] = dtm_ref_nodes(type);
  double f[3], df[3], g[3];
  for (int a = 0; a < nn; a++) {
    int mid = -1;
    double lin = 0, scale = 1;
    const double *q = t[a];
    for (int i = 0; i < d; i++) {
      f[i] = 1 + q[i] * p[i], df[i] = q[i];
      lin += q[i] * p[i];
      if (q[i] == 0) mid = i;
    }
    double pr = product(d, mid, f, df, g);
    if (mid < 0) { /* corner: 2^-d pr (lin - d + 1) */
      for (int i = 0; i < d; i++) scale /= 2;
      N[a] = scale * pr * (lin - d + 1);
      for (int k = 0; k < d; k++) dN[a][k] = scale * (g[k] * (lin - d + 1) + pr * q[k]);
    } else { /* mid-edge: 2^(1-d) (1 - x_mid^2) pr */
      for (int i = 1; i < d; i++) scale /= 2;
      double b = 1 - p[mid] * p[mid];
      N[a] = scale * b * pr;
      for (int k = 0; k < d; k++) dN[a][k] = scale * b * g[k];
      dN[a][mid] = -2 * scale * p[mid] * pr;
    }
  }
}

static void prism18(const double *p, double *N, double (*dN)[3]) {
  const double(*t)[3] = dtm_ref_nodes(DTM_PRISM18);
  double L[3], dL[3][3], g[3], dl;
  barycentric(2, p, L, dL);
  for (int a = 0; a < 18; a++) {
    int i, j;
    const double *q = t[a];
    simplex_pair(2, q, &i, &j);
    double t = p2(L, (const double(*)[3])dL, i, j, g);
    double l = lag(q[2], p[2], &dl);
    N[a] = t * l;
    dN[a][0] = g[0] * l, dN[a][1] = g[1] * l, dN[a][2] = t * dl;
  }
}

static void prism15(const double *p, double *N, double (*dN)[3]) {
  const double(*t)[3] = dtm_ref_nodes(DTM_PRISM15);
  double L[3], dL[3][3], w = p[2], b = 1 - w * w;
  barycentric(2, p, L, dL);
  for (int a = 0; a < 15; a++) {
    int i, j;
    const double *q = t[a];
    simplex_pair(2, q, &i, &j);
    double s = q[2], h = 1 + s * w, t, dt[2], dh;
    if (i != j) { /* triangle edge at level s: 2 L_i L_j (1 + s w) */
      double e = 2 * L[i] * L[j];
      t = e * h, dh = e * s;
      for (int k = 0; k < 2; k++) dt[k] = 2 * (dL[i][k] * L[j] + L[i] * dL[j][k]) * h;
    } else if (s == 0) { /* vertical edge: L_i (1 - w^2) */
      t = L[i] * b, dh = -2 * w * L[i];
      for (int k = 0; k < 2; k++) dt[k] = dL[i][k] * b;
    } else { /* corner */
      double c = L[i] * (2 * L[i] - 1);
      t = 0.5 * c * h - 0.5 * L[i] * b;
      dh = 0.5 * c * s + L[i] * w;
      for (int k = 0; k < 2; k++) dt[k] = 0.5 * (4 * L[i] - 1) * dL[i][k] * h - 0.5 * dL[i][k] * b;
    }
    N[a] = t, dN[a][0] = dt[0], dN[a][1] = dt[1], dN[a][2] = dh;
  }
}

void dtm_ref_eval_quadratic(int type, const double p[3], double *N, double (*dN)[3]) {
  switch (type) {
  case DTM_TRI6: simplex2(type, 2, 6, p, N, dN); break;
  case DTM_TET10: simplex2(type, 3, 10, p, N, dN); break;
  case DTM_QUAD9: tensor2(type, 2, 9, p, N, dN); break;
  case DTM_HEX27: tensor2(type, 3, 27, p, N, dN); break;
  case DTM_QUAD8: serendipity(type, 2, 8, p, N, dN); break;
  case DTM_HEX20: serendipity(type, 3, 20, p, N, dN); break;
  case DTM_PRISM18: prism18(p, N, dN); break;
  case DTM_PRISM15: prism15(p, N, dN); break;
  default: break;
  }
}
