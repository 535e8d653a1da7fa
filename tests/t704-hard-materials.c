/* Hard cases, materials: two unit cubes side by side, fragmented by
 * OpenCASCADE so the mesh is conforming across the shared face and meshed
 * by Gmsh, in physical groups "soft" (E = 1 GPa) and "stiff" (E = 100 GPa,
 * same density: wave speeds 10x apart); and a unit cube of nearly
 * incompressible material (nu = 0.4999: lambda/mu = 5000). Each case must
 * pass the corpus check of hardcase.h: Lanczos converged, element and nodal
 * bounds at or below the global estimate, verify bounded at the
 * recommended step and unbounded at 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <stdio.h>

#include "hardcase.h"
#include "testutil.h"

#define SIZE 0.2

static void mesh_3d(double size) {
  int ierr = 0;
  gmshOptionSetNumber("Mesh.MeshSizeMin", size, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", size, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  assert_int_equal(ierr, 0);
}

static void group(int dim, int tag, const char *name) {
  int ierr = 0;
  gmshModelAddPhysicalGroup(dim, &tag, 1, tag, &ierr);
  gmshModelSetPhysicalName(dim, tag, name, &ierr);
  assert_int_equal(ierr, 0);
}

static void report_census(const char *name) {
  char census[256];
  size_t n = hc_model_census(3, census, sizeof census);
  printf("%s: %zu elements (%s)\n", name, n, census);
  assert_true(n > 100 && n < 5000);
}

static void two_cubes(const char *name) {
  int ierr = 0, *out = NULL, **map = NULL;
  size_t nout = 0, *nmap = NULL, nnmap = 0;
  gmshClear(&ierr);
  gmshModelAdd(name, &ierr);
  int a = gmshModelOccAddBox(0, 0, 0, 1, 1, 1, -1, &ierr), b = gmshModelOccAddBox(1, 0, 0, 1, 1, 1, -1, &ierr);
  int obj[2] = {3, a}, tool[2] = {3, b};
  gmshModelOccFragment(obj, 2, tool, 2, &out, &nout, &map, &nmap, &nnmap, -1, 1, 1, &ierr);
  assert_int_equal(nout, 4); /* two volumes: the boxes only touch */
  gmshModelOccSynchronize(&ierr);
  mesh_3d(SIZE);
  /* fragment keeps the object's tag for the object's piece */
  group(3, map[0][1], "soft");
  group(3, map[1][1], "stiff");
  for (size_t i = 0; i < nnmap; i++) gmshFree(map[i]);
  gmshFree(map), gmshFree(nmap), gmshFree(out);
  report_census(name);
  hc_model_write(name, 1.0);
}

static void contrast(void **unused) {
  hc_result r;
  two_cubes("contrast-100");
  hc_scene_write("contrast-100",
                 "  <material name=\"soft\" groups=\"soft\" E=\"1e9\" nu=\"0.25\" rho=\"2000\"/>\n"
                 "  <material name=\"stiff\" groups=\"stiff\" E=\"100e9\" nu=\"0.25\" rho=\"2000\"/>",
                 "<elastic formulation=\"3d\"/>");
  hc_check("contrast-100", &r);
  (void)unused;
}

static void incompressible(void **unused) {
  int ierr = 0;
  hc_result r;
  gmshClear(&ierr);
  gmshModelAdd("nu-0.4999", &ierr);
  int v = gmshModelOccAddBox(0, 0, 0, 1, 1, 1, -1, &ierr);
  gmshModelOccSynchronize(&ierr);
  mesh_3d(SIZE);
  group(3, v, "rubber");
  report_census("nu-0.4999");
  hc_model_write("nu-0.4999", 1.0);
  hc_scene_write("nu-0.4999", "  <material name=\"rubber\" groups=\"rubber\" E=\"1e7\" nu=\"0.4999\" rho=\"1100\"/>",
                 "<elastic formulation=\"3d\"/>");
  hc_check("nu-0.4999", &r);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(contrast), cmocka_unit_test(incompressible)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
