/* Hard cases, damping, on a unit cube meshed by Gmsh (steel): critical
 * damping at the top frequency (<damping xi="1"/>, factor sqrt(2) - 1);
 * and Rayleigh damping with a large stiffness term, beta = 2 xi_e /
 * omega_e with xi_e = 15 at the element-bound frequency omega_e =
 * 2 / dt.min of an undamped run (plus alpha = 1000/s), which puts xi at
 * the global top frequency between 3 and 10 (checked from the Ritz value).
 * The damped brackets already carry the factor sqrt(1+xi^2) - xi, and
 * verify applies the damping force to the lagged velocity. Each case must
 * pass the corpus check of hardcase.h: Lanczos converged, element and nodal
 * bounds at or below the global estimate, verify bounded at the
 * recommended step and unbounded at 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <math.h>
#include <stdio.h>

#include "hardcase.h"
#include "testutil.h"

#define STEEL "  <material name=\"steel\" groups=\"solid\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>"
#define XI_E 15.0
#define ALPHA 1000.0

static void cube(const char *name) {
  int ierr = 0;
  gmshClear(&ierr);
  gmshModelAdd(name, &ierr);
  int v = gmshModelOccAddBox(0, 0, 0, 1, 1, 1, -1, &ierr);
  gmshModelOccSynchronize(&ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMin", 0.2, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", 0.2, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  assert_int_equal(ierr, 0);
  gmshModelAddPhysicalGroup(3, &v, 1, 1, &ierr);
  gmshModelSetPhysicalName(3, 1, "solid", &ierr);
  hc_model_write(name, 1.0);
}

static void critical(void **unused) {
  hc_result r;
  cube("damping-xi-1");
  hc_scene_write("damping-xi-1", STEEL, "<elastic formulation=\"3d\"/><damping xi=\"1\"/>");
  hc_check("damping-xi-1", &r);
  (void)unused;
}

static void rayleigh(void **unused) {
  const char *name = "rayleigh-beta";
  char effects[256];
  hc_result r;
  cube(name);
  hc_scene_write(name, STEEL, "<elastic formulation=\"3d\"/>");
  double dt_min = hc_run_number(name, 0, "dt.min"), beta = 2 * XI_E / (2 / dt_min);
  snprintf(effects, sizeof effects, "<elastic formulation=\"3d\"/><damping alpha=\"%.17g\" beta=\"%.17g\"/>", ALPHA,
           beta);
  hc_scene_write(name, STEEL, effects);
  hc_check(name, &r);
  double omega = sqrt(r.theta), xi = ALPHA / (2 * omega) + beta * omega / 2;
  printf("%s: beta = %.4g s, xi at the top frequency %.3f\n", name, beta, xi);
  assert_true(xi >= 3 && xi <= 10);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(critical), cmocka_unit_test(rayleigh)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
