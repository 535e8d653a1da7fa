/* The discrete dispersion of an element type: Bloch analysis of the
 * periodic patch that tiles space with it (bar: one segment per cell;
 * quad4, hex8: one square or cube; tri3/tri6: a square cut along a
 * diagonal; tet4/tet10: the cube cut into six tetrahedra around its main
 * diagonal), with the element stiffness of isotropic elasticity at full
 * integration and dtmap's lumped mass (dtm_elem_lumped_weights). For a
 * wave vector k the Hermitian matrix M^-1/2 K(k) M^-1/2 is formed over the
 * node classes of one cell and its eigenpairs found by cyclic Jacobi; the
 * P and S branches are the eigenvectors that overlap most with a plane
 * wave polarised along k and across it. Everything is nondimensional: cell
 * size 1, P-wave modulus 1, density 1, so the semi-discrete phase speed
 * over the exact one depends only on the element type, mu / (lam + 2 mu),
 * k h and the direction. Central differences then act mode by mode:
 * sin(omega dt / 2) = omega_h dt / 2 (dtm_dispersion_time). */
#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/cost.h"
#include "dtmap/topology.h"
#include "dispersion-impl.h"
#include "reference.h"

#define PI 3.14159265358979323846

#define MAX_N (DTM_DISP_MAX_CLS * 3) /* unknowns per cell */
#define MAX_R (2 * MAX_N)            /* the real symmetric form: twice that */

typedef dtm_disp_lattice lattice;

/* Vertices of the patch elements, in cell units (Gmsh node order). */
static int patch_vertices(int type, double v[DTM_DISP_MAX_EL][4][3]) {
  static const int perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  memset(v, 0, sizeof(double) * DTM_DISP_MAX_EL * 12);
  switch (type) {
  case DTM_LINE2: v[0][1][0] = 1; return 1;
  case DTM_QUAD4: v[0][1][0] = v[0][2][0] = v[0][2][1] = v[0][3][1] = 1; return 1;
  case DTM_TRI3:
  case DTM_TRI6:
    v[0][1][0] = v[0][2][0] = v[0][2][1] = 1;
    v[1][1][0] = v[1][1][1] = v[1][2][1] = 1;
    return 2;
  case DTM_TET4:
  case DTM_TET10:
    for (int t = 0; t < 6; t++)
      for (int s = 1; s < 4; s++) {
        for (int c = 0; c < 3; c++) v[t][s][c] = v[t][s - 1][c];
        v[t][s][perm[t][s - 1]] = 1;
      }
    return 6;
  default: return 0;
  }
}

/* Hexahedron: eight corners of the unit cube in Gmsh order. */
static void hex_cell(double *x) {
  static const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                 {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  memcpy(x, c, sizeof c);
}

/* Which two vertices each second-order node of type sits between, from
 * the type's regular element (mid-edge nodes only; -1 when not found). */
static int midside_pairs(int type, int nv, int nn, int pair[10][2]) {
  double r[DTM_K_NODES * 3];
  if (dtm_elem_regular(type, 1.0, r)) return -1;
  for (int m = nv; m < nn; m++) {
    pair[m][0] = -1;
    for (int a = 0; a < nv; a++)
      for (int b = a + 1; b < nv; b++) {
        double e = 0;
        for (int c = 0; c < 3; c++) e += fabs(0.5 * (r[3 * a + c] + r[3 * b + c]) - r[3 * m + c]);
        if (e < 1e-12) pair[m][0] = a, pair[m][1] = b;
      }
    if (pair[m][0] < 0) return -1;
  }
  return 0;
}

/* Nodes of element e of the patch in cell units into x[nn][3]. */
static int element_nodes(int type, int d, int nn, double v[DTM_DISP_MAX_EL][4][3], int e, double *x) {
  if (type == DTM_HEX8) return hex_cell(x), 0;
  int nv = d + 1 + (type == DTM_QUAD4);
  for (int a = 0; a < nv; a++)
    for (int c = 0; c < 3; c++) x[3 * a + c] = v[e][a][c];
  if (nn == nv) return 0;
  int pair[10][2];
  if (midside_pairs(type, nv, nn, pair)) return -1;
  for (int m = nv; m < nn; m++)
    for (int c = 0; c < 3; c++) x[3 * m + c] = 0.5 * (x[3 * pair[m][0] + c] + x[3 * pair[m][1] + c]);
  return 0;
}

/* Class of the node at p (cell units): its position reduced into the cell. */
static int node_class(lattice *L, const double *p, int shift[3]) {
  double q[3];
  for (int c = 0; c < 3; c++) shift[c] = (int)floor(p[c] + 1e-9), q[c] = p[c] - shift[c];
  for (int k = 0; k < L->ncls; k++)
    if (fabs(q[0] - L->pos[k][0]) + fabs(q[1] - L->pos[k][1]) + fabs(q[2] - L->pos[k][2]) < 1e-9) return k;
  if (L->ncls == DTM_DISP_MAX_CLS) return -1;
  memcpy(L->pos[L->ncls], q, sizeof q);
  L->mass[L->ncls] = 0;
  return L->ncls++;
}

/* Element stiffness of one element at full integration for (lam, mu):
 * K[a i][b j] = int lam dNa_i dNb_j + mu (dNa_k dNb_k delta_ij + dNa_j dNb_i). */
void dtm_disp_stiffness(int type, int d, int nn, const double *x, double lam, double mu, double *K) {
  dtm_qrule q;
  dtm_ref_rule(type, &q);
  int n = nn * d;
  memset(K, 0, sizeof(double) * (size_t)n * (size_t)n);
  for (int g = 0; g < q.n; g++) {
    double N[DTM_K_NODES], dN[DTM_K_NODES][3], J[3][3] = {{0}}, Ji[3][3], G[DTM_K_NODES][3] = {{0}};
    dtm_ref_eval(type, q.p[g], N, dN);
    for (int i = 0; i < d; i++)
      for (int j = 0; j < d; j++)
        for (int a = 0; a < nn; a++) J[i][j] += x[3 * a + i] * dN[a][j];
    double dj = dtm_mat_det(d, J);
    dtm_mat_inverse(d, J, dj, Ji);
    for (int a = 0; a < nn; a++)
      for (int i = 0; i < d; i++)
        for (int j = 0; j < d; j++) G[a][i] += dN[a][j] * Ji[j][i];
    double w = q.w[g] * fabs(dj);
    for (int a = 0; a < nn; a++)
      for (int b = 0; b < nn; b++) {
        double gg = 0;
        for (int k = 0; k < d; k++) gg += G[a][k] * G[b][k];
        for (int i = 0; i < d; i++)
          for (int j = 0; j < d; j++)
            K[(a * d + i) * n + b * d + j] +=
                w * (lam * G[a][i] * G[b][j] + mu * G[a][j] * G[b][i] + (i == j) * mu * gg);
      }
  }
}

/* The cell of the lattice: the identity (the unit square or cube cut as
 * above), or for DTM_LATTICE_REGULAR simplices the same cut compressed
 * along the main diagonal, x -> (I - a d d^T) x, until its elements are
 * as regular as a tiling allows (equilateral triangles in 2D, a = 1 -
 * 1/sqrt 3; in 3D a = 1/2 gives six congruent tetrahedra with edges in the
 * ratio sqrt 3 / 2 : 1, the body-centred cubic tiling), scaled back to a
 * cell of volume 1. */
static void lattice_cell(int type, int shape, int d, double cell[3][3]) {
  double a = 0;
  if (shape == DTM_LATTICE_REGULAR && d > 1 && dtm_elem_is_simplex(dtm_elem_parent(type)))
    a = d == 2 ? 1 - 1 / sqrt(3.0) : 0.5;
  double sc = pow(1 - a, -1.0 / d);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) cell[i][j] = i < d && j < d ? sc * ((i == j) - a / d) : (i == j);
}

int dtm_disp_lattice_begin(lattice *L, int type, const double cell[3][3]) {
  memset(L, 0, sizeof *L);
  L->type = type;
  if (dtm_elem_info(type, &L->d, &L->nn) || L->nn > DTM_DISP_MAX_NN || L->nn * L->d > DTM_DISP_ELDOF)
    return DTM_ERR(DTM_ERR_INPUT, "no dispersion model for %s elements", dtm_elem_name(type));
  memcpy(L->cell, cell, sizeof L->cell);
  return DTM_OK;
}

int dtm_disp_lattice_add(lattice *L, const double *f) {
  int e = L->nel;
  if (e == DTM_DISP_MAX_EL) return DTM_ERR(DTM_ERR_INPUT, "a cell of more than %d elements", DTM_DISP_MAX_EL);
  for (int a = 0; a < L->nn; a++) {
    int c = L->cls[e][a] = node_class(L, f + 3 * a, L->shift[e][a]);
    if (c < 0) return DTM_ERR(DTM_ERR_INPUT, "a cell of more than %d node classes", DTM_DISP_MAX_CLS);
    for (int i = 0; i < 3; i++) {
      L->x[e][3 * a + i] = 0;
      for (int j = 0; j < 3; j++) L->x[e][3 * a + i] += L->cell[i][j] * f[3 * a + j];
    }
  }
  double w[DTM_K_NODES], meas = fabs(dtm_elem_measure(L->type, L->x[e]));
  dtm_elem_lumped_weights(L->type, L->x[e], w);
  for (int a = 0; a < L->nn; a++) L->mass[L->cls[e][a]] += w[a] * meas;
  dtm_disp_stiffness(L->type, L->d, L->nn, L->x[e], 1, 0, L->klam[e]);
  dtm_disp_stiffness(L->type, L->d, L->nn, L->x[e], 0, 1, L->kmu[e]);
  L->nel++;
  return DTM_OK;
}

/* The patch of type on lattice shape: elements, node classes, masses, stiffness parts. */
static int lattice_build(int type, int shape, lattice *L) {
  double v[DTM_DISP_MAX_EL][4][3], cell[3][3], f[3 * DTM_DISP_MAX_NN];
  int d, nn, nel = type == DTM_HEX8 ? 1 : patch_vertices(type, v);
  if (!nel || dtm_elem_info(type, &d, &nn) || nn > 10)
    return DTM_ERR(DTM_ERR_INPUT, "no dispersion model for %s elements (bar, tri3, tri6, quad4, tet4, tet10, hex8)",
                   dtm_elem_name(type));
  if (shape != DTM_LATTICE_CUBE && shape != DTM_LATTICE_REGULAR)
    return DTM_ERR(DTM_ERR_INPUT, "dispersion: no lattice %d", shape);
  lattice_cell(type, shape, d, cell);
  DTM_CHECK(dtm_disp_lattice_begin(L, type, cell));
  for (int e = 0; e < nel; e++) {
    if (element_nodes(type, d, nn, v, e, f))
      return DTM_ERR(DTM_ERR_INTERNAL, "%s: no mid-edge layout", dtm_elem_name(type));
    DTM_CHECK(dtm_disp_lattice_add(L, f));
  }
  return DTM_OK;
}

/* H = M^-1/2 K(k) M^-1/2 over the classes' unknowns, k = kh n (cell units). */
static void bloch_matrix(const lattice *L, double lam, double mu, double kh, const double *n, double complex *H) {
  int d = L->d, N = L->ncls * d, ne = L->nn * d;
  memset(H, 0, sizeof(double complex) * (size_t)N * (size_t)N);
  for (int e = 0; e < L->nel; e++)
    for (int a = 0; a < L->nn; a++)
      for (int b = 0; b < L->nn; b++) {
        double ph = 0;
        for (int c = 0; c < d; c++)
          for (int j = 0; j < d; j++) ph += kh * n[c] * L->cell[c][j] * (L->shift[e][b][j] - L->shift[e][a][j]);
        double complex z = cexp(I * ph);
        int ca = L->cls[e][a], cb = L->cls[e][b];
        for (int i = 0; i < d; i++)
          for (int j = 0; j < d; j++) {
            int r = (a * d + i) * ne + b * d + j;
            H[(ca * d + i) * N + cb * d + j] += (lam * L->klam[e][r] + mu * L->kmu[e][r]) * z;
          }
      }
  for (int r = 0; r < N; r++)
    for (int c = 0; c < N; c++) H[r * N + c] /= sqrt(L->mass[r / d] * L->mass[c / d]);
}

/* One Jacobi rotation zeroing A[p][q] of the symmetric A[n][n]; V collects them. */
static void rotate(int n, double *A, double *V, int p, int q) {
  double t, th = (A[q * n + q] - A[p * n + p]) / (2 * A[p * n + q]);
  t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
  double c = 1 / sqrt(t * t + 1), s = t * c;
  for (int k = 0; k < n; k++) {
    double akp = A[k * n + p], akq = A[k * n + q];
    A[k * n + p] = c * akp - s * akq, A[k * n + q] = s * akp + c * akq;
  }
  for (int k = 0; k < n; k++) {
    double apk = A[p * n + k], aqk = A[q * n + k];
    A[p * n + k] = c * apk - s * aqk, A[q * n + k] = s * apk + c * aqk;
  }
  for (int k = 0; k < n; k++) {
    double vkp = V[k * n + p], vkq = V[k * n + q];
    V[k * n + p] = c * vkp - s * vkq, V[k * n + q] = s * vkp + c * vkq;
  }
}

/* Eigenvalues (diagonal of A) and eigenvectors (columns of V) of the
 * symmetric A[n][n], by cyclic Jacobi to round-off. */
void dtm_disp_jacobi(int n, double *A, double *V) {
  for (int i = 0; i < n * n; i++) V[i] = (i / n == i % n);
  for (int sweep = 0; sweep < 60; sweep++) {
    double off = 0, diag = 0;
    for (int i = 0; i < n; i++)
      for (int j = 0; j < n; j++) *(i == j ? &diag : &off) += A[i * n + j] * A[i * n + j];
    if (off <= 1e-30 * diag) return;
    for (int p = 0; p < n; p++)
      for (int q = p + 1; q < n; q++)
        if (A[p * n + q] != 0) rotate(n, A, V, p, q);
  }
}

/* Overlap of real eigenvector column m of V (the Hermitian vector
 * x + i y stacked [x; y]) with the plane wave polarised along pol:
 * |<e, v>|^2 / (|e|^2 |v|^2), e_c = sqrt(m_c) pol exp(i k . pos_c). */
static double overlap(const lattice *L, const double *V, int R, int m, double kh, const double *n, const double *pol) {
  int d = L->d, N = R / 2;
  double complex dot = 0;
  double ee = 0, vv = 0;
  for (int c = 0; c < L->ncls; c++) {
    double ph = 0;
    for (int i = 0; i < d; i++)
      for (int j = 0; j < d; j++) ph += kh * n[i] * L->cell[i][j] * L->pos[c][j];
    double complex ph_c = cexp(I * ph) * sqrt(L->mass[c]);
    for (int i = 0; i < d; i++) {
      double complex v = V[(c * d + i) * R + m] + I * V[(N + c * d + i) * R + m];
      dot += conj(ph_c * pol[i]) * v;
      ee += L->mass[c] * pol[i] * pol[i], vv += creal(v * conj(v));
    }
  }
  return creal(dot * conj(dot)) / (ee * vv);
}

/* sqrt of the eigenvalue whose vector overlaps most with polarisation pol. */
static double branch(const lattice *L, const double *A, const double *V, int R, double kh, const double *n,
                     const double *pol) {
  double best = -1, lam = NAN;
  for (int m = 0; m < R; m++) {
    double o = overlap(L, V, R, m, kh, n, pol);
    if (o > best) best = o, lam = A[m * R + m];
  }
  return sqrt(fmax(lam, 0));
}

/* Unit vectors across n: one in 2D, two in 3D (*np of them). */
static void transverse(int d, const double *n, double t[2][3], int *np) {
  memset(t, 0, sizeof(double) * 6);
  *np = d - 1;
  if (d == 2) {
    t[0][0] = -n[1], t[0][1] = n[0];
    return;
  }
  double a[3] = {fabs(n[0]) < 0.9 ? 1 : 0, fabs(n[0]) < 0.9 ? 0 : 1, 0};
  double dot = a[0] * n[0] + a[1] * n[1] + a[2] * n[2], len = 0;
  for (int c = 0; c < 3; c++) t[0][c] = a[c] - dot * n[c], len += t[0][c] * t[0][c];
  for (int c = 0; c < 3; c++) t[0][c] /= sqrt(len);
  t[1][0] = n[1] * t[0][2] - n[2] * t[0][1];
  t[1][1] = n[2] * t[0][0] - n[0] * t[0][2];
  t[1][2] = n[0] * t[0][1] - n[1] * t[0][0];
}

/* The eigenpairs of the Bloch matrix at kh n in its real symmetric form
 * A[R x R] (diagonalised) and V; returns R. */
static int bloch_eigen(const lattice *L, double r, double kh, const double *n, double *A, double *V) {
  int N = L->ncls * L->d, R = 2 * N;
  double complex H[MAX_N * MAX_N];
  bloch_matrix(L, 1 - 2 * r, r, kh, n, H);
  for (int i = 0; i < N; i++)
    for (int j = 0; j < N; j++) {
      double re = creal(H[i * N + j]), im = cimag(H[i * N + j]);
      A[i * R + j] = A[(N + i) * R + N + j] = re;
      A[(N + i) * R + j] = im, A[i * R + N + j] = -im;
    }
  dtm_disp_jacobi(R, A, V);
  return R;
}

/* The index of the largest of v[R] not yet taken (taken[m] set when chosen). */
static int take_largest(const double *v, int R, char *taken) {
  int best = -1;
  for (int m = 0; m < R; m++)
    if (!taken[m] && (best < 0 || v[m] > v[best])) best = m;
  taken[best] = 1;
  return best;
}

/* The worse error of the transverse branches: the d - 1 eigenpairs (each
 * twice in the real form) that overlap most with the plane across n, once
 * the P branch's pair is set aside (so that two transverse branches whose
 * eigenvectors lie between the fixed transverse vectors are both found). */
static double shear_worst(const lattice *L, const double *A, const double *V, int R, double kh, const double *n,
                          double r) {
  double t[2][3], along[MAX_R] = {0}, across[MAX_R] = {0}, worst = 0;
  char taken[MAX_R] = {0};
  int np;
  transverse(L->d, n, t, &np);
  for (int m = 0; m < R; m++) {
    along[m] = overlap(L, V, R, m, kh, n, n), across[m] = 0;
    for (int p = 0; p < np; p++) across[m] += overlap(L, V, R, m, kh, n, t[p]);
  }
  take_largest(along, R, taken), take_largest(along, R, taken);
  for (int k = 0; k < 2 * np; k++) {
    int m = take_largest(across, R, taken);
    double e = sqrt(fmax(A[m * R + m], 0)) / (sqrt(r) * kh) - 1;
    if (k == 0 || fabs(e) > fabs(worst)) worst = e;
  }
  return worst;
}

static int space_errors(const lattice *L, double r, double kh, const double *n, double err[2]) {
  double A[MAX_R * MAX_R], V[MAX_R * MAX_R];
  int R = bloch_eigen(L, r, kh, n, A, V);
  err[0] = branch(L, A, V, R, kh, n, n) / kh - 1;
  err[1] = r > 0 ? shear_worst(L, A, V, R, kh, n, r) : 0;
  return DTM_OK;
}

int dtm_disp_lattice_polarised(const lattice *L, double r, double kh, const double n[3], const double pol[3], int mode,
                               double *err) {
  if (!(r >= 0 && r < 0.75) || !(kh > 0) || (mode == 1 && !(r > 0)) || (mode != 0 && mode != 1))
    return DTM_ERR(DTM_ERR_INPUT, "dispersion: mu/M = %g, k h = %g, branch %d", r, kh, mode);
  double A[MAX_R * MAX_R], V[MAX_R * MAX_R];
  int R = bloch_eigen(L, r, kh, n, A, V);
  *err = branch(L, A, V, R, kh, n, pol) / ((mode ? sqrt(r) : 1) * kh) - 1;
  return DTM_OK;
}

/* The patch of type on lattice shape, allocated (*out owned by the caller). */
static int lattice_new(int type, int shape, lattice **out) {
  lattice *L = malloc(sizeof *L);
  if (!L) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  int rc = lattice_build(type, shape, L);
  if (rc) return free(L), rc;
  *out = L;
  return DTM_OK;
}

int dtm_dispersion_polarised(int type, int shape, double r, double kh, const double n[3], const double pol[3], int mode,
                             double *err) {
  lattice *L;
  DTM_CHECK(lattice_new(type, shape, &L));
  int rc = dtm_disp_lattice_polarised(L, r, kh, n, pol, mode, err);
  free(L);
  return rc;
}

const char *dtm_dispersion_model_name(int shape) {
  static const char *const names[] = {"cube lattice", "regular lattice", "own shapes", "structured lattice",
                                      "measured"};
  return shape >= 0 && shape <= DTM_LATTICE_MEASURED ? names[shape] : "none";
}

int dtm_dispersion_has_model(int type) {
  return type == DTM_LINE2 || type == DTM_TRI3 || type == DTM_TRI6 || type == DTM_QUAD4 || type == DTM_TET4 ||
         type == DTM_TET10 || type == DTM_HEX8;
}

int dtm_dispersion_space(int type, int shape, double r, double kh, const double n[3], double err[2]) {
  lattice *L;
  if (!(r >= 0 && r < 0.75) || !(kh > 0)) return DTM_ERR(DTM_ERR_INPUT, "dispersion: mu/M = %g, k h = %g", r, kh);
  DTM_CHECK(lattice_new(type, shape, &L));
  int rc = space_errors(L, r, kh, n, err);
  free(L);
  return rc;
}

double dtm_dispersion_time(double space, double x) {
  if (!(x <= 1)) return NAN;
  if (x < 1e-8) return space;
  return (1 + space) * asin(x) / x - 1;
}

/* The directions of a table: 2D 24 angles over half a turn (the axes and
 * diagonals among them), 3D the axes, the face and body diagonals and 35
 * more spread over the half sphere (k and -k disperse alike). */
int dtm_disp_directions(int d, double n[DTM_DISP_DIRS][3]) {
  memset(n, 0, sizeof(double) * 3 * DTM_DISP_DIRS);
  if (d == 1) {
    n[0][0] = 1;
    return 1;
  }
  if (d == 2) {
    for (int i = 0; i < 24; i++) n[i][0] = cos(PI * i / 24), n[i][1] = sin(PI * i / 24);
    return 24;
  }
  static const double fixed[13][3] = {{1, 0, 0}, {0, 1, 0},  {0, 0, 1}, {1, 1, 0},  {1, -1, 0}, {1, 0, 1}, {1, 0, -1},
                                      {0, 1, 1}, {0, 1, -1}, {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {-1, 1, 1}};
  int m = 0;
  for (; m < 13; m++) {
    double l = sqrt(fixed[m][0] * fixed[m][0] + fixed[m][1] * fixed[m][1] + fixed[m][2] * fixed[m][2]);
    for (int c = 0; c < 3; c++) n[m][c] = fixed[m][c] / l;
  }
  for (int i = 0; i < DTM_DISP_DIRS - 13; i++, m++) {
    double z = (i + 0.5) / (DTM_DISP_DIRS - 13), s = sqrt(1 - z * z), phi = i * PI * (3 - sqrt(5.0));
    n[m][0] = s * cos(phi), n[m][1] = s * sin(phi), n[m][2] = z;
  }
  return m;
}

int dtm_disp_lattice_table(const lattice *L, double r, dtm_dispersion *t) {
  t->type = L->type, t->r = r, t->samples = 0, t->per_cell = L->nel;
  t->ndir = dtm_disp_directions(L->d, t->dir);
  for (int j = 0; j < DTM_DISP_KH; j++) {
    double kh = PI * (j + 1) / DTM_DISP_KH, err[2];
    for (int i = 0; i < t->ndir; i++) {
      DTM_CHECK(space_errors(L, r, kh, t->dir[i], err));
      t->g[0][i][j] = err[0] / (kh * kh), t->g[1][i][j] = err[1] / (kh * kh);
    }
  }
  return DTM_OK;
}

int dtm_dispersion_table(int type, int shape, double r, dtm_dispersion *t) {
  lattice *L;
  DTM_CHECK(lattice_new(type, shape, &L));
  int rc = dtm_disp_lattice_table(L, r, t);
  t->shape = shape, t->per_cell = dtm_dispersion_cell_elements(type);
  free(L);
  return rc;
}

/* err / (k h)^2 of branch mode in direction i at kh, linear between the
 * table's points (constant below the first). */
static double g_at(const dtm_dispersion *t, int mode, int i, double kh) {
  double u = kh / PI * DTM_DISP_KH - 1;
  if (u <= 0) return t->g[mode][i][0];
  int j = (int)u;
  if (j >= DTM_DISP_KH - 1) return t->g[mode][i][DTM_DISP_KH - 1];
  double f = u - j;
  return (1 - f) * t->g[mode][i][j] + f * t->g[mode][i][j + 1];
}

double dtm_dispersion_at(const dtm_dispersion *t, int mode, int dir, double kh) {
  if (!(kh <= PI) || dir < 0 || dir >= t->ndir) return NAN;
  return g_at(t, mode, dir, kh) * kh * kh;
}

int dtm_disp_lattice_space(const lattice *L, double r, double kh, const double n[3], double err[2]) {
  if (!(r >= 0 && r < 0.75) || !(kh > 0)) return DTM_ERR(DTM_ERR_INPUT, "dispersion: mu/M = %g, k h = %g", r, kh);
  return space_errors(L, r, kh, n, err);
}

double dtm_dispersion_worst_dir(const dtm_dispersion *t, int mode, double kh, double x, int *dir) {
  if (dir) *dir = 0;
  if (!(kh <= PI)) return NAN;
  double worst = 0;
  for (int i = 0; i < t->ndir; i++) {
    double s = g_at(t, mode, i, kh) * kh * kh;
    double e = dtm_dispersion_time(s, x * (1 + s));
    if (isnan(e)) return NAN;
    if (fabs(e) > fabs(worst)) {
      worst = e;
      if (dir) *dir = i;
    }
  }
  return worst;
}

double dtm_dispersion_worst(const dtm_dispersion *t, int mode, double kh, double x) {
  return dtm_dispersion_worst_dir(t, mode, kh, x, NULL);
}
