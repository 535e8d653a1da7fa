/* A bound on the Jacobian determinant of a second-order simplex over the
 * whole element, not only at its nodes and integration points. On tri6
 * the map is quadratic, so det J is a polynomial of degree 2 in (u, v); on
 * tet10 of degree 3 in (u, v, w). Written in the Bernstein (Bezier) basis
 * of a simplex, det J = sum_a c_a B_a with B_a >= 0 and sum_a B_a = 1, so
 * min c_a <= det J <= max c_a over that simplex, and the coefficients at
 * the vertices are values of det J. The coefficients come from the values
 * of det J at the p-th order lattice points (p = 2 or 3; 6 or 20 points)
 * through the inverse of the Bernstein collocation matrix, computed once.
 * When the smallest coefficient is not positive the simplex is split into
 * 4 (triangle) or 8 (tetrahedron: four corners and the octahedron cut
 * along one diagonal) and each child is bounded again, which tightens the
 * bound quadratically; a lattice value that is not safely positive (32 eps
 * of the Hadamard bound, as map.c) proves the element inverted there. This
 * is the idea of Gmsh's AnalyseCurvedMesh plugin (Johnen, Remacle and
 * Geuzaine, "Geometrical validity of curvilinear finite elements", 2013),
 * written anew for these two types: every Bernstein coefficient of a child
 * is computed from values, not by de Casteljau subdivision. The depth is
 * bounded (6 on triangles, 4 on tetrahedra: at most 4096 leaves); an
 * element whose smallest coefficient is still not positive there is "not
 * proved positive". The ratio min c / max c (smallest leaf coefficient
 * over the largest coefficient of the whole element) is a lower bound of
 * min det J / max det J, the measure of curvature Gmsh reports. */
#include <float.h>
#include <math.h>
#include <pthread.h>

#include "kernel-impl.h"

#define NB 20 /* most Bernstein coefficients (tet, degree 3) */

typedef struct {
  int d, p, n;        /* dimension, degree, number of coefficients */
  int idx[NB][4];     /* multi-indices (barycentric exponents, sum p) */
  double inv[NB][NB]; /* inverse of A[b][a] = B_a(idx_b / p) */
} basis;

static basis bases[2]; /* [0] triangle degree 2, [1] tetrahedron degree 3 */
/* The reference gradients of tri6 and tet10 at the lattice points of the
 * whole element (depth 0, where every element starts and most end),
 * evaluated once: the same values dtm_map_det evaluates on the spot. */
static double root_dn[2][NB][DTM_K_NODES][3];
static dtm_v4d root_dn4[NB / 4][DTM_K_NODES][3]; /* the tet's, four points lane by lane (dtm_map_det_dn4) */
static pthread_once_t once = PTHREAD_ONCE_INIT;

static double bernstein(int d, int p, const int *a, const double *l) {
  static const double f[4] = {1, 1, 2, 6};
  double v = f[p];
  for (int k = 0; k <= d; k++) v *= pow(l[k], a[k]) / f[a[k]];
  return v;
}

/* Gauss-Jordan inverse of the n x n matrix A (destroyed) into X. */
static void invert(int n, double A[NB][NB], double X[NB][NB]) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) X[i][j] = i == j;
  for (int c = 0; c < n; c++) {
    int r = c;
    for (int i = c + 1; i < n; i++)
      if (fabs(A[i][c]) > fabs(A[r][c])) r = i;
    for (int j = 0; j < n; j++) {
      double t = A[c][j], u = X[c][j];
      A[c][j] = A[r][j], X[c][j] = X[r][j], A[r][j] = t, X[r][j] = u;
    }
    double s = 1 / A[c][c];
    for (int j = 0; j < n; j++) A[c][j] *= s, X[c][j] *= s;
    for (int i = 0; i < n; i++) {
      double m = A[i][c];
      if (i == c || m == 0) continue;
      for (int j = 0; j < n; j++) A[i][j] -= m * A[c][j], X[i][j] -= m * X[c][j];
    }
  }
}

static void basis_init(int d, int p, basis *b) {
  double A[NB][NB];
  b->d = d, b->p = p, b->n = 0;
  for (int i = 0; i <= p; i++)
    for (int j = 0; j <= p - i; j++)
      for (int k = 0; k <= (d == 3 ? p - i - j : 0); k++) {
        int *a = b->idx[b->n++];
        a[1] = i, a[2] = j, a[3] = d == 3 ? k : 0, a[0] = p - i - j - a[3];
      }
  for (int r = 0; r < b->n; r++) {
    double l[4];
    for (int k = 0; k <= d; k++) l[k] = (double)b->idx[r][k] / p;
    for (int c = 0; c < b->n; c++) A[r][c] = bernstein(d, p, b->idx[c], l);
  }
  invert(b->n, A, b->inv);
}

/* root_dn of type at the lattice points of b on the reference simplex V
 * (the points as bound computes them). */
static void root_init(int type, const basis *b, const double V[4][3], double (*dn)[DTM_K_NODES][3]) {
  double N[DTM_K_NODES];
  for (int r = 0; r < b->n; r++) {
    double p[3] = {0, 0, 0};
    for (int k = 0; k <= b->d; k++)
      for (int i = 0; i < 3; i++) p[i] += V[k][i] * b->idx[r][k] / b->p;
    dtm_ref_eval(type, p, N, dn[r]);
  }
}

static const double tri[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
static const double tet[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

static void init_all(void) {
  basis_init(2, 2, &bases[0]);
  basis_init(3, 3, &bases[1]);
  root_init(DTM_TRI6, &bases[0], tri, root_dn[0]);
  root_init(DTM_TET10, &bases[1], tet, root_dn[1]);
  for (int r = 0; r + 4 <= bases[1].n; r += 4)
    for (int a = 0; a < DTM_K_NODES; a++)
      for (int j = 0; j < 3; j++)
        root_dn4[r / 4][a][j] =
            (dtm_v4d){root_dn[1][r][a][j], root_dn[1][r + 1][a][j], root_dn[1][r + 2][a][j], root_dn[1][r + 3][a][j]};
}

typedef struct {
  int type, d, nn;
  const double (*xl)[3];
  const basis *b;
  double top;    /* largest coefficient of the whole element */
  double low;    /* smallest coefficient over the leaves */
  double scaled; /* scaled Jacobian at a lattice point that is not safely positive */
  int max_depth;
} bound_ctx;

/* Bound det J over the sub-simplex with reference vertices V[d + 1]:
 * 1 positive, -1 a lattice value not safely positive, 0 undecided. */
static int bound(bound_ctx *c, const double V[4][3], int depth) {
  const basis *b = c->b;
  double f[NB], lo = INFINITY, hi = -INFINITY, root_had[NB];
  int lanes = !depth && b->d == 3; /* the tet's root lattice: det J at four points at a time, the same bits */
  for (int r = 0; lanes && r < b->n; r += 4)
    dtm_map_det_dn4(c->nn, c->xl, (const dtm_v4d(*)[3])root_dn4[r / 4], f + r, root_had + r);
  for (int r = 0; r < b->n; r++) {
    double had;
    if (lanes)
      had = root_had[r];
    else if (!depth)
      f[r] = dtm_map_det_dn(c->d, c->nn, c->xl, (const double(*)[3])root_dn[b->d == 3][r], &had);
    else {
      double p[3] = {0, 0, 0};
      for (int k = 0; k <= b->d; k++)
        for (int i = 0; i < 3; i++) p[i] += V[k][i] * b->idx[r][k] / b->p;
      f[r] = dtm_map_det(c->type, c->d, c->nn, c->xl, p, &had);
    }
    if (!(f[r] > 32 * DBL_EPSILON * had)) return c->scaled = had > 0 ? f[r] / had : 0, -1;
  }
  for (int a = 0; a < b->n; a++) {
    double s = 0;
    for (int r = 0; r < b->n; r++) s += b->inv[a][r] * f[r];
    lo = fmin(lo, s), hi = fmax(hi, s);
  }
  if (depth == 0) c->top = hi;
  if (lo > 0 || depth == c->max_depth) return c->low = fmin(c->low, lo), lo > 0;
  double M[4][4][3], C[8][4][3];
  for (int i = 0; i <= b->d; i++)
    for (int j = 0; j <= b->d; j++)
      for (int k = 0; k < 3; k++) M[i][j][k] = 0.5 * (V[i][k] + V[j][k]);
  int nc;
  if (b->d == 2) {
    static const int t[4][3][2] = {
        {{0, 0}, {0, 1}, {0, 2}}, {{0, 1}, {1, 1}, {1, 2}}, {{0, 2}, {1, 2}, {2, 2}}, {{0, 1}, {1, 2}, {0, 2}}};
    for (int s = 0; s < 4; s++)
      for (int v = 0; v < 3; v++)
        for (int k = 0; k < 3; k++) C[s][v][k] = M[t[s][v][0]][t[s][v][1]][k];
    nc = 4;
  } else {
    static const int t[8][4][2] = {{{0, 0}, {0, 1}, {0, 2}, {0, 3}}, {{0, 1}, {1, 1}, {1, 2}, {1, 3}},
                                   {{0, 2}, {1, 2}, {2, 2}, {2, 3}}, {{0, 3}, {1, 3}, {2, 3}, {3, 3}},
                                   {{0, 2}, {1, 3}, {0, 1}, {1, 2}}, {{0, 2}, {1, 3}, {1, 2}, {2, 3}},
                                   {{0, 2}, {1, 3}, {2, 3}, {0, 3}}, {{0, 2}, {1, 3}, {0, 3}, {0, 1}}};
    for (int s = 0; s < 8; s++)
      for (int v = 0; v < 4; v++)
        for (int k = 0; k < 3; k++) C[s][v][k] = M[t[s][v][0]][t[s][v][1]][k];
    nc = 8;
  }
  int res = 1;
  for (int s = 0; s < nc; s++) {
    int r = bound(c, (const double(*)[3])C[s], depth + 1);
    if (r < 0) return -1;
    if (r == 0) res = 0;
  }
  return res;
}

int dtm_elem_jacobian_bound(int type, int d, int nn, const double (*xl)[3], double *ratio, double *scaled) {
  if (type != DTM_TRI6 && type != DTM_TET10) return -2;
  pthread_once(&once, init_all);
  bound_ctx c = {type, d, nn, xl, &bases[type == DTM_TET10], NAN, INFINITY, 0, type == DTM_TET10 ? 4 : 6};
  int r = bound(&c, type == DTM_TET10 ? tet : tri, 0);
  *ratio = r < 0 ? c.scaled : c.low / c.top;
  if (scaled) *scaled = c.scaled;
  return r;
}
