/* The scene's meshing choices, with real Gmsh meshing:
 * - <meshing algorithm="hxt" threads="2"> meshes with HXT on two threads
 *   and the report says mesh.reproducible = false;
 * - without them dtmap keeps what the geometry file sets (Mesh.Algorithm3D
 *   = 10 in the .geo) on one thread; HXT is never reported reproducible
 *   (its result follows the process's thread count);
 * - Gmsh's default Delaunay on one thread is: the same scene gives the same
 *   element tags twice;
 * - a later scene does not inherit an earlier scene's choice;
 * - a mesh read from a .msh is reported as read and reproducible;
 * - an unknown algorithm is a schema error naming the line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/analysis.h"
#include "dtmap/gmsh.h"
#include "dtmap/output.h"
#include "testutil.h"

/* The steel cube scene name with extra <meshing> attributes. */
static void write_scene(const char *name, const char *source, const char *extra) {
  char meshing[256];
  snprintf(meshing, sizeof meshing, "size=\"0.15\" dim=\"3\"%s", extra);
  tu_steel_scene(name, source, meshing, "");
}

static void check(const char *name, int algorithm, int threads, int reproducible) {
  dtm_scene *s = NULL;
  dtm_analysis *a = tu_analyse(name, &s);
  const dtm_mesher_info *mi = dtm_analysis_mesher(a);
  assert_int_equal(mi->algorithm, algorithm);
  assert_int_equal(mi->threads, threads);
  assert_int_equal(mi->reproducible, reproducible);
  char rep[600];
  snprintf(rep, sizeof rep, "%s/%s.json", tu_tmpdir(), name);
  dtm_results res = {a, NULL, NULL, 0, 0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  assert_int_equal(dtm_report_write(&res, rep), 0);
  cJSON *j = tu_json_load(rep);
  const cJSON *mesh = cJSON_GetObjectItemCaseSensitive(j, "mesh");
  assert_true(cJSON_IsBool(cJSON_GetObjectItemCaseSensitive(mesh, "reproducible")));
  assert_int_equal(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(mesh, "reproducible")), reproducible);
  assert_string_equal(cJSON_GetObjectItemCaseSensitive(mesh, "algorithm")->valuestring,
                      dtm_scene_algorithm_name(algorithm));
  cJSON_Delete(j);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
}

static void scene_choice(void **unused) {
  write_scene("hxt2", "<geometry file=\"cube.geo\"/>", " algorithm=\"hxt\" threads=\"2\"");
  check("hxt2", 10, 2, 0);
  (void)unused;
}

/* Element tags of a run of scene name (caller frees), count in *n. */
static size_t *tags_of(const char *name, size_t *n) {
  dtm_scene *s = NULL;
  dtm_analysis *a = tu_analyse(name, &s);
  *n = dtm_analysis_nelements(a);
  size_t *t = malloc(*n * sizeof *t);
  for (size_t i = 0; i < *n; i++) t[i] = dtm_analysis_tag(a, i);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  return t;
}

static void geometry_choice(void **unused) {
  write_scene("geo_hxt", "<geometry file=\"cube_hxt.geo\"/>", "");
  check("geo_hxt", 10, 1, 0);
  write_scene("plain", "<geometry file=\"cube.geo\"/>", "");
  check("plain", 1, 1, 1); /* neither the .geo's nor the earlier scene's choice carries over */
  size_t n1, n2, *t1 = tags_of("plain", &n1), *t2 = tags_of("plain", &n2);
  assert_int_equal(n1, n2);
  assert_memory_equal(t1, t2, n1 * sizeof *t1); /* Delaunay on one thread: the same numbering */
  free(t1), free(t2);
  (void)unused;
}

static void read_mesh(void **unused) {
  char geo[600], msh[600];
  int ierr = 0;
  snprintf(geo, sizeof geo, "%s/cube.geo", tu_tmpdir());
  snprintf(msh, sizeof msh, "%s/cube.msh", tu_tmpdir());
  gmshClear(&ierr);
  gmshOpen(geo, &ierr);
  gmshOptionSetNumber("Mesh.MeshSizeMax", 0.15, &ierr);
  gmshModelMeshGenerate(3, &ierr);
  gmshWrite(msh, &ierr);
  assert_int_equal(ierr, 0);
  write_scene("read", "<mesh file=\"cube.msh\"/>", "");
  check("read", 0, 0, 1);
  (void)unused;
}

static void bad_algorithm(void **unused) {
  char path[600];
  dtm_scene *s = NULL;
  write_scene("bad", "<geometry file=\"cube.geo\"/>", " algorithm=\"fastest\"");
  snprintf(path, sizeof path, "%s/bad.xml", tu_tmpdir());
  assert_int_equal(dtm_scene_load(path, &s), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "bad.xml:4"));
  dtm_error_clear();
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_cube_geo("cube.geo", "");
  tu_cube_geo("cube_hxt.geo", "Mesh.Algorithm3D = 10;\n");
  if (dtm_gmsh_start(0)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(scene_choice), cmocka_unit_test(geometry_choice),
                                     cmocka_unit_test(read_mesh), cmocka_unit_test(bad_algorithm)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_gmsh_stop();
  return r;
}
