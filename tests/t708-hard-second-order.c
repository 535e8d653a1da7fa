/* Hard cases, second order, meshed by Gmsh and elevated with
 * gmshModelMeshSetOrder(2) before writing: a disc 1 m across in tri6
 * (curved edges on the circle; plane strain, granite), and a unit cube in
 * tet10 (steel). Each case must pass the corpus check of hardcase.h:
 * Lanczos converged, element and nodal bounds at or below the global
 * estimate, verify bounded at the recommended step and unbounded at
 * 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <stdio.h>
#include <string.h>

#include "hardcase.h"
#include "testutil.h"

static void second_order(const char *name, int dim, int tag, double size, const char *want) {
  int ierr = 0;
  char census[256];
  gmshModelOccSynchronize(&ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMin", size, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", size, &ierr);
  gmshModelMeshGenerate(dim, &ierr);
  gmshModelMeshSetOrder(2, &ierr);
  assert_int_equal(ierr, 0);
  gmshModelAddPhysicalGroup(dim, &tag, 1, 1, &ierr);
  gmshModelSetPhysicalName(dim, 1, "solid", &ierr);
  size_t n = hc_model_census(dim, census, sizeof census);
  printf("%s: %zu elements (%s)\n", name, n, census);
  assert_non_null(strstr(census, want));
  hc_model_write(name, 1.0);
}

static void tri6(void **unused) {
  int ierr = 0;
  hc_result r;
  gmshClear(&ierr);
  gmshModelAdd("order2-tri6", &ierr);
  int s = gmshModelOccAddDisk(0, 0, 0, 0.5, 0.5, -1, &ierr);
  second_order("order2-tri6", 2, s, 0.08, "Triangle 6");
  hc_scene_write("order2-tri6", "  <material name=\"granite\" groups=\"solid\" E=\"60e9\" nu=\"0.25\" rho=\"2700\"/>",
                 "<elastic formulation=\"plane-strain\"/>");
  hc_check("order2-tri6", &r);
  (void)unused;
}

static void tet10(void **unused) {
  int ierr = 0;
  hc_result r;
  gmshClear(&ierr);
  gmshModelAdd("order2-tet10", &ierr);
  int v = gmshModelOccAddBox(0, 0, 0, 1, 1, 1, -1, &ierr);
  second_order("order2-tet10", 3, v, 0.25, "Tetrahedron 10");
  hc_scene_write("order2-tet10", "  <material name=\"steel\" groups=\"solid\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>",
                 "<elastic formulation=\"3d\"/>");
  hc_check("order2-tet10", &r);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(tri6), cmocka_unit_test(tet10)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
