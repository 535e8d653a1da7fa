/* The measured dispersion of Gmsh's unstructured tetrahedral meshes. On
 * such a mesh a plane wave is not a mode, and no sum over elements predicts
 * what it does (docs/accuracy.md): the phase speed is measured instead, by
 * simulation on periodic cubes meshed by Gmsh's Delaunay and HXT
 * (bench/tet_dispersion.py, which writes measured.inc). The table holds the
 * semi-discrete error over (k s)^2 at the table's points k s = pi (j + 1) /
 * DTM_DISP_KH, s the mean edge, for tet4 and tet10, P and S, along three
 * classes of direction (axes, face diagonals, body diagonals: Gmsh's meshes
 * carry a trace of the box's axes, the S wave lags more along them) and
 * three Poisson's ratios (interpolated linearly in lam / mu, clamped to
 * the measured 0.15-0.45); central differences are added exactly mode by
 * mode (dtm_dispersion_time), as for every model.
 * The table is a mean over each mesh's elements (the abscissa is the root
 * mean square of the mean edges, weighted by volume); the measures evaluate
 * each element at its own mean edge and average the errors over the
 * volumes around its corners (src/cost/accuracy.c), which is that mean to
 * first order and what a wave crossing the elements sees. */
#include <math.h>
#include <string.h>

#include "dispersion-impl.h"
#include "dtmap/cost.h"
#include "dtmap/kernel.h"

#include "measured.inc"

#define NCLASS 3

/* The classes' directions: an axis, a face diagonal, a body diagonal. */
static const double class_dir[NCLASS][3] = {{1, 0, 0},
                                            {0.70710678118654752, 0.70710678118654752, 0},
                                            {0.57735026918962576, 0.57735026918962576, 0.57735026918962576}};

int dtm_dispersion_has_measured(int type) { return type == DTM_TET4 || type == DTM_TET10; }

/* lam / mu of Poisson's ratio nu: the errors are close to linear in it
 * (the S wave of linear tetrahedra stiffens as the material nears
 * incompressibility; docs/accuracy.md). */
static double lam_mu(double nu) { return 2 * nu / (1 - 2 * nu); }

/* The two measured ratios around q = lam / mu and the weight of the
 * second, clamped to the measured range. */
static void bracket(double q, int *i, double *w) {
  int k = 0;
  while (k + 2 < DTM_MEASURED_NU && q > lam_mu(measured_nu[k + 1])) k++;
  double a = lam_mu(measured_nu[k]), b = lam_mu(measured_nu[k + 1]);
  *i = k, *w = fmin(fmax((q - a) / (b - a), 0), 1);
}

int dtm_dispersion_table_measured(int type, double r, dtm_dispersion *t) {
  if (!dtm_dispersion_has_measured(type))
    return DTM_ERR(DTM_ERR_INPUT, "no measured dispersion for %s elements (tet4, tet10)", dtm_elem_name(type));
  if (!(r > 0 && r < 0.75)) return DTM_ERR(DTM_ERR_INPUT, "dispersion: mu/M = %g", r);
  int o = type == DTM_TET10, i;
  double w;
  bracket(1 / r - 2, &i, &w);
  memset(t, 0, sizeof *t);
  t->type = type, t->r = r, t->shape = DTM_LATTICE_MEASURED, t->ndir = NCLASS, t->per_cell = 0;
  memcpy(t->dir, class_dir, sizeof class_dir);
  for (int m = 0; m < 2; m++)
    for (int c = 0; c < NCLASS; c++)
      for (int j = 0; j < DTM_DISP_KH; j++)
        t->g[m][c][j] = (1 - w) * measured_g[o][i][m][c][j] + w * measured_g[o][i + 1][m][c][j];
  return DTM_OK;
}

int dtm_disp_measured_class(const double n[3]) {
  double a[3] = {fabs(n[0]), fabs(n[1]), fabs(n[2])}, best = -1;
  int cls = 0;
  for (int i = 0; i < 2; i++) /* sort descending */
    for (int j = 0; j + 1 < 3 - i; j++)
      if (a[j] < a[j + 1]) {
        double s = a[j];
        a[j] = a[j + 1], a[j + 1] = s;
      }
  for (int c = 0; c < NCLASS; c++) {
    double dot = a[0] * class_dir[c][0] + a[1] * class_dir[c][1] + a[2] * class_dir[c][2];
    if (dot > best) best = dot, cls = c;
  }
  return cls;
}
