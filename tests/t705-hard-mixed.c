/* Hard cases, mixed element types, all meshed by Gmsh: two unit cubes
 * fragmented by OpenCASCADE, one a transfinite recombined block of hexes,
 * the other unstructured, which Gmsh fills with tets and, on the shared
 * quad face, pyramids (3D, steel); a unit square of quads glued to a unit
 * square of triangles (plane stress, aluminium); and that 2D mesh extruded
 * by 4 recombined layers into hexes and prisms (3D, aluminium). Each case
 * must pass the corpus check of hardcase.h: Lanczos converged, element and
 * nodal bounds at or below the global estimate, verify bounded at the
 * recommended step and unbounded at 1.05 x the estimate's unsafe side. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hardcase.h"
#include "testutil.h"

#define STEEL "  <material name=\"steel\" groups=\"solid\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>"
#define ALU "  <material name=\"alu\" groups=\"solid\" E=\"70e9\" nu=\"0.33\" rho=\"2700\"/>"

/* Transfinite (n nodes per curve) and recombined: every curve, face and,
 * for dim 3, the volume of entity (dim, tag). */
static void structured(int dim, int tag, int n) {
  int ierr = 0, dt[2] = {dim, tag}, *faces = NULL, *curves = NULL;
  size_t nf = 0, nc = 0;
  if (dim == 3)
    gmshModelGetBoundary(dt, 2, &faces, &nf, 0, 0, 0, &ierr);
  else
    faces = dt, nf = 2;
  gmshModelGetBoundary(faces, nf, &curves, &nc, 0, 0, 0, &ierr);
  for (size_t i = 0; i < nc; i += 2) gmshModelMeshSetTransfiniteCurve(abs(curves[i + 1]), n, "Progression", 1, &ierr);
  for (size_t i = 0; i < nf; i += 2) {
    gmshModelMeshSetTransfiniteSurface(faces[i + 1], "Left", NULL, 0, &ierr);
    gmshModelMeshSetRecombine(2, faces[i + 1], &ierr);
  }
  if (dim == 3) gmshModelMeshSetTransfiniteVolume(tag, NULL, 0, &ierr);
  assert_int_equal(ierr, 0);
  gmshFree(curves);
  if (dim == 3) gmshFree(faces);
}

/* Fragment two unit boxes (dim 3) or squares (dim 2) along x; the tags of
 * the two pieces. */
static void two_pieces(const char *name, int dim, int *first, int *second) {
  int ierr = 0, *out = NULL, **map = NULL;
  size_t nout = 0, *nmap = NULL, nnmap = 0;
  gmshClear(&ierr);
  gmshModelAdd(name, &ierr);
  int a = dim == 3 ? gmshModelOccAddBox(0, 0, 0, 1, 1, 1, -1, &ierr)
                   : gmshModelOccAddRectangle(0, 0, 0, 1, 1, -1, 0, &ierr);
  int b = dim == 3 ? gmshModelOccAddBox(1, 0, 0, 1, 1, 1, -1, &ierr)
                   : gmshModelOccAddRectangle(1, 0, 0, 1, 1, -1, 0, &ierr);
  int obj[2] = {dim, a}, tool[2] = {dim, b};
  gmshModelOccFragment(obj, 2, tool, 2, &out, &nout, &map, &nmap, &nnmap, -1, 1, 1, &ierr);
  assert_int_equal(nout, 4);
  gmshModelOccSynchronize(&ierr);
  *first = map[0][1], *second = map[1][1];
  for (size_t i = 0; i < nnmap; i++) gmshFree(map[i]);
  gmshFree(map), gmshFree(nmap), gmshFree(out);
}

static void mesh_and_write(const char *name, int dim, const int *tags, int ntags, double size, const char *want) {
  int ierr = 0;
  char census[256];
  gmshOptionSetNumber("Mesh.MeshSizeMin", size, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", size, &ierr);
  gmshModelMeshGenerate(dim, &ierr);
  assert_int_equal(ierr, 0);
  gmshModelAddPhysicalGroup(dim, (int *)tags, (size_t)ntags, 1, &ierr);
  gmshModelSetPhysicalName(dim, 1, "solid", &ierr);
  size_t n = hc_model_census(dim, census, sizeof census);
  printf("%s: %zu elements (%s)\n", name, n, census);
  for (const char *w = want; *w; w += strlen(w) + 1) assert_non_null(strstr(census, w));
  hc_model_write(name, 1.0);
}

static void hex_pyramid_tet(void **unused) {
  int hex, tet;
  hc_result r;
  two_pieces("mixed-hex-pyr-tet", 3, &hex, &tet);
  structured(3, hex, 7);
  int tags[2] = {hex, tet};
  mesh_and_write("mixed-hex-pyr-tet", 3, tags, 2, 0.2, "Hexahedron 8\0Pyramid 5\0Tetrahedron 4\0");
  hc_scene_write("mixed-hex-pyr-tet", STEEL, "<elastic formulation=\"3d\"/>");
  hc_check("mixed-hex-pyr-tet", &r);
  (void)unused;
}

static void quad_triangle(void **unused) {
  int quad, tri;
  hc_result r;
  two_pieces("mixed-quad-tri", 2, &quad, &tri);
  structured(2, quad, 11);
  int tags[2] = {quad, tri};
  mesh_and_write("mixed-quad-tri", 2, tags, 2, 0.1, "Quadrilateral 4\0Triangle 3\0");
  hc_scene_write("mixed-quad-tri", ALU, "<elastic formulation=\"plane-stress\"/>");
  hc_check("mixed-quad-tri", &r);
  (void)unused;
}

static void hex_prism(void **unused) {
  int quad, tri, ierr = 0, *out = NULL, layers[1] = {4};
  size_t nout = 0;
  hc_result r;
  two_pieces("mixed-hex-prism", 2, &quad, &tri);
  structured(2, quad, 9);
  int base[4] = {2, quad, 2, tri}, vols[2], nv = 0;
  gmshModelOccExtrude(base, 4, 0, 0, 0.5, &out, &nout, layers, 1, NULL, 0, 1, &ierr);
  gmshModelOccSynchronize(&ierr);
  for (size_t i = 0; i < nout; i += 2)
    if (out[i] == 3) vols[nv++] = out[i + 1];
  gmshFree(out);
  assert_int_equal(nv, 2);
  mesh_and_write("mixed-hex-prism", 3, vols, 2, 0.125, "Hexahedron 8\0Prism 6\0");
  hc_scene_write("mixed-hex-prism", ALU, "<elastic formulation=\"3d\"/>");
  hc_check("mixed-hex-prism", &r);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(hex_pyramid_tet), cmocka_unit_test(quad_triangle),
                                     cmocka_unit_test(hex_prism)};
  int r = cmocka_run_group_tests(tests, hc_group_setup, NULL);
  tu_gmsh_end();
  return r;
}
