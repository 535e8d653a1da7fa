/* Hard cases, 1000:1 grading: a bar of 60 elements whose lengths grow
 * geometrically from 1 mm to 1 m (elastic bar, and thermal only: the
 * diffusion steps then span six decades); and a 2 m square meshed by Gmsh
 * with a Threshold field on the distance to one corner, sizes from 0.4 mm
 * there to about 0.5 m far from it, checked to span at least 1000:1 (plane
 * strain + thermal, with a diffusivity of 10 m^2/s so that diffusion limits
 * on the small elements and waves on the large ones). Each case must pass
 * the corpus check of hardcase.h: Lanczos converged, element and nodal
 * bounds at or below the global estimate, verify bounded at the
 * recommended step and unbounded at 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "hardcase.h"
#include "testutil.h"

#define NBAR 60
#define GRANITE(k)                                                                                                     \
  "  <material name=\"granite\" groups=\"solid\" E=\"60e9\" nu=\"0.25\" rho=\"2700\" conductivity=\"" k "\" "          \
  "heat-capacity=\"790\"/>"

static void graded_bar(const char *name) {
  double x[NBAR + 1], r = pow(1000.0, 1.0 / (NBAR - 1));
  x[0] = 0;
  for (int i = 0; i < NBAR; i++) x[i + 1] = x[i] + 1e-3 * pow(r, i);
  assert_true(fabs((x[NBAR] - x[NBAR - 1]) / (x[1] - x[0]) - 1000) < 1e-9);
  hc_mesh m;
  hc_mesh_init(&m, 1, HC_LINE2, 2, "solid");
  hc_bar(&m, x, NBAR);
  hc_mesh_write(&m, name);
  hc_mesh_free(&m);
}

static void bar_elastic(void **unused) {
  hc_result r;
  graded_bar("grading-bar-elastic");
  hc_scene_write("grading-bar-elastic", GRANITE("3"), "<elastic formulation=\"bar\"/>");
  hc_check("grading-bar-elastic", &r);
  (void)unused;
}

static void bar_thermal(void **unused) {
  hc_result r;
  graded_bar("grading-bar-thermal");
  hc_scene_write("grading-bar-thermal", GRANITE("3"), "<thermal/>");
  hc_check("grading-bar-thermal", &r);
  (void)unused;
}

/* Mean edge length of each triangle of the current model: smallest and
 * largest. */
static void size_range(double *lo, double *hi) {
  size_t *tags = NULL, nt = 0, *nodes = NULL, nn = 0, *ntag = NULL, nnt = 0, nc = 0, np = 0;
  double *xyz = NULL, *par = NULL;
  int ierr = 0;
  gmshModelMeshGetNodes(&ntag, &nnt, &xyz, &nc, &par, &np, -1, -1, 0, 0, &ierr);
  gmshModelMeshGetElementsByType(2, &tags, &nt, &nodes, &nn, -1, 0, 1, &ierr);
  *lo = INFINITY, *hi = 0;
  for (size_t e = 0; e < nt; e++) {
    double s = 0;
    for (int k = 0; k < 3; k++) {
      const double *a = xyz + 3 * (nodes[3 * e + (size_t)k] - 1);
      const double *b = xyz + 3 * (nodes[3 * e + (size_t)(k + 1) % 3] - 1);
      s += hypot(a[0] - b[0], a[1] - b[1]) / 3;
    }
    *lo = fmin(*lo, s), *hi = fmax(*hi, s);
  }
  for (size_t i = 0; i < nnt; i++) assert_int_equal(ntag[i], i + 1); /* dense tags, as DESIGN.md says */
  gmshFree(tags), gmshFree(nodes), gmshFree(ntag), gmshFree(xyz), gmshFree(par);
}

static void graded_square(const char *name) {
  int ierr = 0, surf = 1, corner = 1;
  gmshClear(&ierr);
  gmshModelAdd(name, &ierr);
  gmshModelOccAddRectangle(0, 0, 0, 2, 2, surf, 0, &ierr);
  gmshModelOccSynchronize(&ierr);
  int *pts = NULL;
  size_t npts = 0;
  gmshModelGetEntitiesInBoundingBox(-1e-6, -1e-6, -1e-6, 1e-6, 1e-6, 1e-6, &pts, &npts, 0, &ierr);
  assert_int_equal(npts, 2);
  corner = pts[1];
  gmshFree(pts);
  int d = gmshModelMeshFieldAdd("Distance", -1, &ierr), t = gmshModelMeshFieldAdd("Threshold", -1, &ierr);
  double pl[1] = {corner};
  gmshModelMeshFieldSetNumbers(d, "PointsList", pl, 1, &ierr);
  gmshModelMeshFieldSetNumber(t, "InField", d, &ierr);
  gmshModelMeshFieldSetNumber(t, "SizeMin", 4e-4, &ierr);
  gmshModelMeshFieldSetNumber(t, "SizeMax", 1.0, &ierr);
  gmshModelMeshFieldSetNumber(t, "DistMin", 0, &ierr);
  gmshModelMeshFieldSetNumber(t, "DistMax", 4.0, &ierr);
  gmshModelMeshFieldSetAsBackgroundMesh(t, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeExtendFromBoundary", 0, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeFromPoints", 0, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeFromCurvature", 0, &ierr);
  gmshModelMeshGenerate(2, &ierr);
  assert_int_equal(ierr, 0);
  gmshModelAddPhysicalGroup(2, &surf, 1, 1, &ierr);
  gmshModelSetPhysicalName(2, 1, "solid", &ierr);
  double lo, hi;
  size_range(&lo, &hi);
  printf("%s: element sizes %.3g to %.3g m (%.0f:1)\n", name, lo, hi, hi / lo);
  assert_true(hi / lo >= 1000);
  hc_model_write(name, 1.0);
}

static void square_thermal_elastic(void **unused) {
  hc_result r;
  graded_square("grading-square");
  hc_scene_write("grading-square", GRANITE("2.133e7"), "<elastic formulation=\"plane-strain\"/><thermal/>");
  hc_check("grading-square", &r);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(bar_elastic), cmocka_unit_test(bar_thermal),
                                     cmocka_unit_test(square_thermal_elastic)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
