/* The kill switches (src/gmsh/budget.c, msh_scan.c): inputs too big for
 * the machine are refused with their figures before anything is allocated.
 *  - The header scan reads the node and element counts Gmsh itself finds,
 *    in MSH 1, 2 and 4, ASCII and binary (files written by the gmsh
 *    program from one geometry, counts compared with Gmsh's API).
 *  - A .msh whose headers promise more than its size can hold is refused
 *    as truncated or corrupt.
 *  - Under a data-size limit of 64 MB (ulimit -d), a mesh of 384000 tets
 *    (estimated 300 B per element and 150 B per node, about 126 MB) is
 *    refused, naming the counts and the limit; not under ASan, whose
 *    shadow memory needs more than such a limit allows.
 *  - Sparse node tags (a .msh keeps its writer's tags): up to 10^6 for four
 *    nodes, they are looked up by bisection and the run succeeds, its
 *    report naming the element by its own tag; up to 10^15, the views
 *    (which Gmsh indexes by tag: 8 B a tag number in each of 8 views, 64 PB)
 *    cannot be written, and the run is refused before any work on them.
 *  - <meshing size=1e-4> on the 0.1 m cube of geometries/box.geo: at least
 *    4 x 0.001 / 1e-12 = 4e9 tetrahedra, refused naming the scene line and
 *    the volume OpenCASCADE gives; on a built-in-kernel square the measure
 *    comes from the bounding box (1 m^2). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "gmsh-impl.h"
#include "testutil.h"

#if defined(__SANITIZE_ADDRESS__)
#define UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define UNDER_ASAN 1
#endif
#endif

static const char square_geo[] = "Point(1) = {0, 0, 0, 0.2}; Point(2) = {1, 0, 0, 0.2};\n"
                                 "Point(3) = {1, 1, 0, 0.2}; Point(4) = {0, 1, 0, 0.2};\n"
                                 "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
                                 "Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\n"
                                 "Physical Surface(\"rock\") = {1};\n";

/* Gmsh's own counts of the nodes and elements of a .msh. */
static void gmsh_counts(const char *path, size_t *nodes, size_t *elements) {
  int ierr = 0, *types = NULL;
  size_t *tags = NULL, nt = 0, n = 0, nc = 0, np = 0, **et = NULL, *net = NULL, ne = 0, **nt2 = NULL, *nnt = NULL,
         nn = 0;
  double *xyz = NULL, *par = NULL;
  tu_gmsh_begin();
  gmshOpen(path, &ierr);
  assert_int_equal(ierr, 0);
  gmshModelMeshGetNodes(&tags, &n, &xyz, &nc, &par, &np, -1, -1, 0, 0, &ierr);
  *nodes = n;
  gmshModelMeshGetElements(&types, &nt, &et, &net, &ne, &nt2, &nnt, &nn, -1, -1, &ierr);
  *elements = 0;
  for (size_t i = 0; i < nt; i++) *elements += net[i], gmshFree(et[i]), gmshFree(nt2[i]);
  gmshFree(tags), gmshFree(xyz), gmshFree(par), gmshFree(types), gmshFree(et), gmshFree(net), gmshFree(nt2),
      gmshFree(nnt);
  tu_gmsh_end();
}

static void test_scan_formats(void **state) {
  (void)state;
  static const char *const formats[][2] = {
      {"msh1", ""}, {"msh22", ""}, {"msh22", "-bin"}, {"msh41", ""}, {"msh41", "-bin"}};
  char geo[600], msh[600], *log = NULL;
  snprintf(geo, sizeof geo, "%s/square.geo", tu_tmpdir());
  tu_write(geo, square_geo);
  for (size_t i = 0; i < sizeof formats / sizeof *formats; i++) {
    snprintf(msh, sizeof msh, "%s/square-%zu.msh", tu_tmpdir(), i);
    assert_int_equal(tu_run(&log, "gmsh %s -2 -format %s %s -o %s", geo, formats[i][0], formats[i][1], msh), 0);
    free(log);
    size_t nodes, elements;
    gmsh_counts(msh, &nodes, &elements);
    dtm_msh_head h;
    assert_int_equal(dtm_msh_scan(msh, &h), 0);
    assert_true(h.have_nodes && h.have_elements);
    assert_int_equal(h.nodes, nodes);
    assert_int_equal(h.elements, elements);
    assert_int_equal(h.binary, formats[i][1][0] != '\0');
    assert_int_equal(dtm_gmsh_check_msh(msh), DTM_OK);
  }
  assert_int_equal(dtm_msh_scan("/nonexistent.msh", &(dtm_msh_head){0}), -1);
}

static void test_lying_header(void **state) {
  (void)state;
  char msh[600];
  snprintf(msh, sizeof msh, "%s/lies.msh", tu_tmpdir());
  tu_write(msh, "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n1 0 0\n0 1 0\n"
                "$EndNodes\n$Elements\n1 5000000000 1 5000000000\n2 1 2 5000000000\n1 1 2 3\n$EndElements\n");
  dtm_error_clear();
  assert_int_equal(dtm_gmsh_check_msh(msh), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "lies.msh: its headers announce 3 nodes and 5000000000 elements"));
  assert_non_null(strstr(dtm_error_message(), "truncated or corrupt"));
  dtm_error_clear();
}

/* 6 n^3 tets of a structured unit cube, MSH 2. */
static void write_cube(const char *path, int n) {
  FILE *f = fopen(path, "w");
  int n1 = n + 1;
  assert_non_null(f);
  fprintf(f, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n", n1 * n1 * n1);
  for (int k = 0, id = 1; k < n1; k++)
    for (int j = 0; j < n1; j++)
      for (int i = 0; i < n1; i++) fprintf(f, "%d %d %d %d\n", id++, i, j, k);
  fprintf(f, "$EndNodes\n$Elements\n%d\n", 6 * n * n * n);
  for (int e = 1; e <= 6 * n * n * n; e++) fprintf(f, "%d 4 2 1 1 1 2 %d %d\n", e, n1 + 1, n1 * n1 + 1);
  fprintf(f, "$EndElements\n");
  fclose(f);
}

static void test_memory_limit(void **state) {
  (void)state;
#ifdef UNDER_ASAN
  skip();
#endif
  char msh[600], scene[600], *log = NULL;
  snprintf(msh, sizeof msh, "%s/cube.msh", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/cube.xml", tu_tmpdir());
  write_cube(msh, 40);
  tu_write(scene, "<dtmap-scene version=\"1\">\n  <mesh file=\"cube.msh\"/>\n"
                  "  <material name=\"m\" default=\"true\" E=\"1e9\" nu=\"0.3\" rho=\"1000\"/>\n"
                  "  <effects><elastic/></effects>\n</dtmap-scene>\n");
  int code = tu_run(&log, "ulimit -d 65536 && %s run %s -q -o %s/cube_out.msh", tu_cli(), scene, tu_tmpdir());
  if (code != 2 || !strstr(log, "126 MB")) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 2);
  assert_non_null(strstr(log, "cube.msh: the mesh has 384000 elements and 68921 nodes, which need about 126 MB"));
  assert_non_null(strstr(log, "this machine allows 67.1 MB"));
  free(log);
}

/* A one-tet mesh whose node tags are base + 1 ... base + 4. */
static int run_sparse(size_t base, char **log) {
  char msh[600], scene[600], text[1024];
  snprintf(msh, sizeof msh, "%s/sparse.msh", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/sparse.xml", tu_tmpdir());
  snprintf(text, sizeof text,
           "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n%zu 0 0 0\n%zu 1 0 0\n%zu 0 1 0\n%zu 0 0 1\n"
           "$EndNodes\n$Elements\n1\n999 4 2 1 1 %zu %zu %zu %zu\n$EndElements\n",
           base + 1, base + 2, base + 3, base + 4, base + 1, base + 2, base + 3, base + 4);
  tu_write(msh, text);
  tu_write(scene, "<dtmap-scene version=\"1\">\n  <mesh file=\"sparse.msh\"/>\n"
                  "  <material name=\"m\" default=\"true\" E=\"1e9\" nu=\"0.3\" rho=\"1000\"/>\n"
                  "  <effects><elastic/></effects>\n</dtmap-scene>\n");
  return tu_run(log, "%s run %s -q -o %s/sparse_out.msh --report %s/sparse.json", tu_cli(), scene, tu_tmpdir(),
                tu_tmpdir());
}

static void test_sparse_tags(void **state) {
  (void)state;
  char rep[600], *log = NULL;
  int code = run_sparse(1000000, &log);
  if (code) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 0);
  free(log);
  snprintf(rep, sizeof rep, "%s/sparse.json", tu_tmpdir());
  struct cJSON *r = tu_json_load(rep);
  assert_non_null(r);
  assert_true(tu_json_number(r, "dt.element") == 999);
  cJSON_Delete(r);
  code = run_sparse(1000000000000000, &log);
  assert_int_equal(code, 2);
  /* Gmsh reads MSH 2 node tags as int: 10^15 wraps, to a tag no smaller */
  assert_non_null(strstr(log, "sparse.msh: node tags go up to "));
  assert_non_null(strstr(log, " for 4 nodes (renumber them densely)"));
  free(log);
}

static void run_meshing(const char *geometry, const char *meshing, const char *const *expect) {
  char scene[600], *log = NULL;
  snprintf(scene, sizeof scene, "%s/fine.xml", tu_tmpdir());
  char text[2048];
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n  <geometry file=\"%s\"/>\n  %s\n"
           "  <material name=\"m\" default=\"true\" E=\"1e9\" nu=\"0.3\" rho=\"1000\"/>\n"
           "  <effects><elastic/></effects>\n</dtmap-scene>\n",
           geometry, meshing);
  tu_write(scene, text);
  int code = tu_run(&log, "%s run %s -q -o %s/fine_out.msh", tu_cli(), scene, tu_tmpdir());
  assert_int_equal(code, 2);
  for (int i = 0; expect[i]; i++) {
    if (!strstr(log, expect[i])) fprintf(stderr, "missing '%s' in %s\n", expect[i], log);
    assert_non_null(strstr(log, expect[i]));
  }
  free(log);
}

static void test_meshing_too_fine(void **state) {
  (void)state;
  char box[600], sq[600];
  snprintf(box, sizeof box, "%s/geometries/box.geo", tu_src());
  run_meshing(box, "<meshing size=\"1e-4\" dim=\"3\"/>",
              (const char *const[]){"fine.xml:3: <meshing size=\"0.0001\">", "measure 0.001 m^3 in dimension 3",
                                    "gives at least 4e+09 elements", "this machine allows", NULL});
  snprintf(sq, sizeof sq, "%s/square.geo", tu_tmpdir());
  tu_write(sq, square_geo);
  run_meshing(sq, "<meshing size=\"1e-8\"/>",
              (const char *const[]){"fine.xml:3:", "measure 1 m^2 in dimension 2", "gives at least 2e+16", NULL});
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_scan_formats), cmocka_unit_test(test_lying_header),     cmocka_unit_test(test_memory_limit),
      cmocka_unit_test(test_sparse_tags),  cmocka_unit_test(test_meshing_too_fine),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
