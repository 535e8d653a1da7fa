/* Partitioned meshes in the scene: <mesh file=... partitions="P"> and the
 * names of the parts (Gmsh's "_k" before .msh, or "{part}"), the errors of
 * a bad partition count or a {part} without partitions, and, without
 * mpirun, a clear refusal saying how to run it (exit 2) in both builds: a
 * dtmap without MPI says to build it with DTM_MPI, one with MPI says how
 * many ranks the scene needs. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/scene.h"
#include "testutil.h"

static const char head[] = "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n";
static const char tail[] = "<material name=\"m\" default=\"true\" E=\"1e9\" nu=\"0.3\" rho=\"1000\"/>\n"
                           "<effects><elastic/></effects>\n</dtmap-scene>\n";

static int load(const char *source, dtm_scene **s) {
  char text[2048];
  snprintf(text, sizeof text, "%s%s\n%s", head, source, tail);
  dtm_error_clear();
  return dtm_scene_load_memory(text, strlen(text), "/work/p/scene.xml", s);
}

static void part_names(void **state) {
  (void)state;
  char buf[64];
  assert_int_equal(dtm_scene_part_path("/w/model.msh", 3, buf, sizeof buf), DTM_OK);
  assert_string_equal(buf, "/w/model_3.msh"); /* as Gmsh names a split model.msh */
  assert_int_equal(dtm_scene_part_path("/w/m.MSH", 12, buf, sizeof buf), DTM_OK);
  assert_string_equal(buf, "/w/m_12.MSH");
  assert_int_equal(dtm_scene_part_path("/w/p{part}/m_{part}.msh", 7, buf, sizeof buf), DTM_OK);
  assert_string_equal(buf, "/w/p7/m_{part}.msh"); /* the first {part} only */
  assert_int_equal(dtm_scene_part_path("/w/x", 2, buf, sizeof buf), DTM_OK);
  assert_string_equal(buf, "/w/x_2");
  assert_int_equal(dtm_scene_part_path("/a/rather/long/name.msh", 1, buf, 8), DTM_ERR_INPUT);
}

/* The part files are each rank's to find: the scene loads without them. */
static void partitions_read(void **state) {
  (void)state;
  dtm_scene *s = NULL;
  assert_int_equal(load("<mesh file=\"parts/model.msh\" partitions=\"4\"/>", &s), DTM_OK);
  assert_int_equal(s->partitions, 4);
  assert_string_equal(s->mesh, "/work/p/parts/model.msh");
  dtm_scene_destroy(&s);
}

static void partitions_errors(void **state) {
  (void)state;
  dtm_scene *s = NULL;
  assert_int_equal(load("<mesh file=\"m_{part}.msh\"/>", &s), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "scene.xml:3"));
  assert_non_null(strstr(dtm_error_message(), "partitions"));
  assert_int_equal(load("<mesh file=\"m.msh\" partitions=\"0\"/>", &s), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "partitions"));
  assert_int_equal(load("<geometry file=\"m.geo\" partitions=\"2\"/>", &s), DTM_ERR_INPUT);
  assert_null(s);
}

/* Without mpirun: exit 2 naming the scene and how to run it. */
static void cli_without_mpirun(void **state) {
  (void)state;
  char path[1024], text[2048], *out = NULL;
  snprintf(path, sizeof path, "%s/parts.xml", tu_tmpdir());
  snprintf(text, sizeof text, "%s<mesh file=\"model.msh\" partitions=\"4\"/>\n%s", head, tail);
  tu_write(path, text);
  int rc = tu_run(&out, "cd %s && %s run parts.xml -o o.msh", tu_tmpdir(), tu_cli());
  if (rc != 2) fprintf(stderr, "%s", out);
  assert_int_equal(rc, 2);
  assert_non_null(strstr(out, "parts.xml:3"));
  assert_non_null(strstr(out, "mpirun -n 4"));
  free(out);
  snprintf(path, sizeof path, "%s/o_1.msh", tu_tmpdir());
  assert_false(tu_exists(path));
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(part_names),
      cmocka_unit_test(partitions_read),
      cmocka_unit_test(partitions_errors),
      cmocka_unit_test(cli_without_mpirun),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
