/* Hard case, tiny scale: a sphere 1 um across (meshed by Gmsh at unit scale,
 * written with Mesh.ScalingFactor = 1e-6, so elements are about 0.15 um and
 * steps about 1e-11 s), silicon with elastic waves and heat diffusion, whose
 * steps are of the same order there. The written nodes are checked to lie
 * in the 1 um sphere. The case must pass the corpus check of hardcase.h:
 * Lanczos converged, element and nodal bounds at or below the global
 * estimate, verify bounded at the recommended step and unbounded at 1.05 x
 * the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <math.h>
#include <stdio.h>

#include "hardcase.h"
#include "testutil.h"

#define NAME "tiny-1um"
#define PI 3.14159265358979323846

/* Largest distance of a node of the current model from the origin. */
static double radius(void) {
  size_t *tags = NULL, n = 0, nc = 0, np = 0;
  double *xyz = NULL, *par = NULL, r = 0;
  int ierr = 0;
  gmshModelMeshGetNodes(&tags, &n, &xyz, &nc, &par, &np, -1, -1, 0, 0, &ierr);
  assert_true(ierr == 0 && n > 0);
  for (size_t i = 0; i < n; i++) {
    const double *p = xyz + 3 * i;
    r = fmax(r, sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]));
  }
  gmshFree(tags), gmshFree(xyz), gmshFree(par);
  return r;
}

static void tiny_sphere(void) {
  int ierr = 0;
  char census[256], path[600];
  gmshClear(&ierr);
  gmshModelAdd(NAME, &ierr);
  int v = gmshModelOccAddSphere(0, 0, 0, 0.5, -1, -PI / 2, PI / 2, 2 * PI, &ierr);
  gmshModelOccSynchronize(&ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMin", 0.15, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", 0.15, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  assert_int_equal(ierr, 0);
  gmshModelAddPhysicalGroup(3, &v, 1, 1, &ierr);
  gmshModelSetPhysicalName(3, 1, "solid", &ierr);
  printf("%s: %zu elements (%s)\n", NAME, hc_model_census(3, census, sizeof census), census);
  hc_model_write(NAME, 1e-6);
  snprintf(path, sizeof path, "%s/%s.msh", tu_tmpdir(), NAME);
  gmshClear(&ierr);
  gmshOpen(path, &ierr);
  assert_int_equal(ierr, 0);
  double r = radius();
  assert_true(r > 0.49e-6 && r < 0.5e-6 * (1 + 1e-9));
}

static void tiny(void **unused) {
  hc_result r;
  tiny_sphere();
  hc_scene_write(NAME,
                 "  <material name=\"silicon\" groups=\"solid\" E=\"130e9\" nu=\"0.28\" rho=\"2330\" "
                 "conductivity=\"150\" heat-capacity=\"700\"/>",
                 "<elastic formulation=\"3d\"/><thermal/>");
  hc_check(NAME, &r);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(tiny)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
