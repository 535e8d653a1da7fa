/* The dispersion of a mesh's own element shapes, for tri3, quad4 and hex8
 * (types whose nodes are all vertices). An unstructured mesh is not the
 * regular lattice of its element type: its elements are of every shape
 * and orientation, and a wave crossing them sees their mean; a structured
 * mesh of rectangles or boxes is a lattice with one node class, whose
 * Bloch matrix is exactly the sum below. Tetrahedra are left to the
 * lattice (src/cost/dispersion.c): on an unstructured tetrahedral mesh the
 * plane wave is far from a mode and the sum is too stiff for the S wave
 * (docs/accuracy.md).
 * A plane wave u = p exp(i k.x) on the nodes of one element gives the
 * element's dynamic matrix D_e(k) = sum_ab K_ab cos(k.(x_b - x_a)) (the
 * real part: the element together with its point reflection, which for a
 * triangle tile the plane exactly, so that for tri3 this is the Bloch
 * matrix of the element's own lattice). Its Rayleigh quotient over the
 * element's mass (any lumping: the wave has the same amplitude at every
 * node) is the element's share of the wave's frequency, and over a region
 * the wave's squared frequency is the Rayleigh quotient of the summed D_e
 * over the summed mass: exact on a lattice with one node class, the
 * energy-weighted mean of the local ones otherwise.
 * dtm_dispersion_table_shapes builds the lattice's table (src/cost/
 * dispersion.c) from a sample of the mesh's elements, each scaled to the
 * lattice spacing of its measure, so that an element of the mesh still
 * costs one interpolation; dtm_dispersion_element and
 * dtm_dispersion_branches give the exact sum for one wave (the prediction
 * that verify --accuracy checks). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dispersion-impl.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"
#include "dtmap/topology.h"

#define PI 3.14159265358979323846
#define MAX_NN 8 /* nodes of the types modelled (hex8) */

int dtm_dispersion_has_shapes(int type) { return type == DTM_TRI3 || type == DTM_QUAD4 || type == DTM_HEX8; }

int dtm_dispersion_cell_elements(int type) {
  int d = 0, nn = 0;
  if (dtm_elem_info(type, &d, &nn) || !dtm_elem_is_simplex(dtm_elem_parent(type))) return 1;
  return d == 2 ? 2 : d == 3 ? 6 : 1;
}

/* D[d][d] (stride 3) += sum_ab K_ab cos(k.(x_b - x_a)), K[nn d][nn d]. */
static void add_dynamic(int d, int nn, const double *K, const double *x, const double *k, double *D) {
  double c[MAX_NN], s[MAX_NN];
  int n = nn * d;
  for (int a = 0; a < nn; a++) {
    double ph = 0;
    for (int i = 0; i < d; i++) ph += k[i] * x[3 * a + i];
    c[a] = cos(ph), s[a] = sin(ph);
  }
  for (int a = 0; a < nn; a++)
    for (int b = 0; b < nn; b++) {
      double w = c[a] * c[b] + s[a] * s[b];
      const double *Kab = K + (size_t)(a * d) * (size_t)n + b * d;
      for (int i = 0; i < d; i++)
        for (int j = 0; j < d; j++) D[3 * i + j] += w * Kab[i * n + j];
    }
}

/* Whether type's nodes are all corners (at most MAX_NN): its plane-wave sums are defined. */
static int corners_only(int type, int *d, int *nn) {
  return !dtm_elem_info(type, d, nn) && dtm_elem_parent(type) == type && *nn <= MAX_NN && *d >= 2;
}

int dtm_dispersion_element(int type, const double *x, double lam, double mu, const double k[3], double D[9]) {
  int d, nn;
  if (!corners_only(type, &d, &nn))
    return DTM_ERR(DTM_ERR_INPUT, "no plane-wave dispersion for %s elements (first-order types)", dtm_elem_name(type));
  double K[MAX_NN * 3 * MAX_NN * 3];
  dtm_disp_stiffness(type, d, nn, x, lam, mu, K);
  memset(D, 0, 9 * sizeof *D);
  add_dynamic(d, nn, K, x, k, D);
  return DTM_OK;
}

void dtm_dispersion_branches(int d, const double D[9], const double v[3], double w[3]) {
  double A[9], V[9];
  for (int i = 0; i < d; i++)
    for (int j = 0; j < d; j++) A[i * d + j] = D[3 * i + j];
  dtm_disp_jacobi(d, A, V);
  int best = 0;
  double o = -1;
  for (int m = 0; m < d; m++) {
    double dot = 0;
    for (int i = 0; i < d; i++) dot += V[i * d + m] * v[i];
    if (fabs(dot) > o) o = fabs(dot), best = m;
  }
  w[0] = A[best * d + best];
  for (int m = 0, j = 1; m < d; m++)
    if (m != best) w[j++] = A[m * d + m];
}

/* Element e of the sample scaled to its lattice spacing (cell units) into
 * y; 0 when it has no measure. */
static int scaled(int type, int d, int nn, const double *x, double *y) {
  double meas = fabs(dtm_elem_measure(type, x));
  if (!(meas > 0) || !isfinite(meas)) return 0;
  double h = pow(dtm_dispersion_cell_elements(type) * meas, 1.0 / d);
  for (int a = 0; a < nn; a++)
    for (int c = 0; c < 3; c++) y[3 * a + c] = (x[3 * a + c] - x[c]) / h;
  return 1;
}

/* The table's errors from the summed matrices S[dir][kh][9] over mass m. */
static void table_errors(dtm_dispersion *t, int d, const double *S, double m) {
  for (int i = 0; i < t->ndir; i++)
    for (int j = 0; j < DTM_DISP_KH; j++) {
      double kh = PI * (j + 1) / DTM_DISP_KH, D[9], w[3];
      for (int c = 0; c < 9; c++) D[c] = S[((size_t)i * DTM_DISP_KH + j) * 9 + c] / m;
      dtm_dispersion_branches(d, D, t->dir[i], w);
      t->g[0][i][j] = (sqrt(fmax(w[0], 0)) / kh - 1) / (kh * kh);
      double worst = 0;
      for (int b = 1; b < d && t->r > 0; b++) {
        double e = sqrt(fmax(w[b], 0)) / (sqrt(t->r) * kh) - 1;
        if (b == 1 || fabs(e) > fabs(worst)) worst = e;
      }
      t->g[1][i][j] = worst / (kh * kh);
    }
}

int dtm_disp_table_weighted(int type, double r, const double *x, const double *w, size_t n, dtm_dispersion *t) {
  int d, nn;
  if (!corners_only(type, &d, &nn))
    return DTM_ERR(DTM_ERR_INPUT, "no plane-wave dispersion for %s elements (first-order types)", dtm_elem_name(type));
  if (!(r >= 0 && r < 0.75) || !n) return DTM_ERR(DTM_ERR_INPUT, "dispersion: mu/M = %g, %zu elements", r, n);
  memset(t, 0, sizeof *t);
  t->type = type, t->r = r, t->shape = DTM_LATTICE_OWN, t->ndir = dtm_disp_directions(d, t->dir);
  t->per_cell = dtm_dispersion_cell_elements(type);
  double *S = calloc((size_t)t->ndir * DTM_DISP_KH * 9, sizeof *S), m = 0;
  if (!S) return DTM_ERR(DTM_ERR_INTERNAL, "out of memory");
  for (size_t e = 0; e < n; e++) {
    double y[3 * MAX_NN], K[MAX_NN * 3 * MAX_NN * 3], we = w ? w[e] : 1;
    if (!scaled(type, d, nn, x + (size_t)e * nn * 3, y)) continue;
    dtm_disp_stiffness(type, d, nn, y, we * (1 - 2 * r), we * r, K);
    m += we * fabs(dtm_elem_measure(type, y)), t->samples++;
    for (int i = 0; i < t->ndir; i++)
      for (int j = 0; j < DTM_DISP_KH; j++) {
        double kh = PI * (j + 1) / DTM_DISP_KH, k[3] = {kh * t->dir[i][0], kh * t->dir[i][1], kh * t->dir[i][2]};
        add_dynamic(d, nn, K, y, k, S + ((size_t)i * DTM_DISP_KH + j) * 9);
      }
  }
  if (t->samples) table_errors(t, d, S, m);
  free(S);
  return t->samples ? DTM_OK : DTM_ERR(DTM_ERR_INPUT, "dispersion: no %s element with a measure", dtm_elem_name(type));
}

int dtm_dispersion_table_shapes(int type, double r, const double *x, size_t n, dtm_dispersion *t) {
  if (!dtm_dispersion_has_shapes(type))
    return DTM_ERR(DTM_ERR_INPUT, "no own-shape dispersion for %s elements (tri3, quad4, hex8)", dtm_elem_name(type));
  return dtm_disp_table_weighted(type, r, x, NULL, n, t);
}
