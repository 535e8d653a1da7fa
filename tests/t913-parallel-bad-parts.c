/* Bad part files for the distributed run: a part that is missing, one from
 * another mesh, one from another partitioning of the same mesh, a whole
 * mesh where a part is expected, a run on the wrong number of ranks, and
 * outputs that would overwrite the parts. Each is exit 2 with a message
 * naming the file (or the scene line and the rank count), and leaves
 * nothing in the output directory and the inputs unchanged. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "parts.h"

#define NP 4

static char dir[512];

static const char scene[] = "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n"
                            "  <mesh file=\"case/box_parts.msh\" partitions=\"4\"/>\n"
                            "  <material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                            "  <effects><elastic/></effects>\n</dtmap-scene>\n";

static int setup(void **state) {
  (void)state;
  char path[1024];
  snprintf(dir, sizeof dir, "%s", tu_tmpdir());
  tu_gmsh_begin();
  tu_mesh_and_split("box.geo", 3, 1.2e-2, dir, "box", NP);   /* box.msh, box_parts_1..4.msh */
  tu_mesh_and_split("box.geo", 3, 1.5e-2, dir, "other", NP); /* another mesh of the same box */
  tu_mesh_and_split("box.geo", 3, 1.2e-2, dir, "three", 3);  /* the first mesh, split in 3 */
  snprintf(path, sizeof path, "%s/scene.xml", dir);
  tu_write(path, scene);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  tu_gmsh_end();
  return 0;
}

/* A fresh case/ with the four good parts, and an empty out/. */
static void fresh_case(void) {
  char *out = NULL;
  int rc = tu_run(&out, "cd %s && rm -rf case out && mkdir case out && cp box_parts_?.msh case/", dir);
  free(out);
  assert_int_equal(rc, 0);
}

static int empty_dir(const char *path) {
  DIR *d = opendir(path);
  struct dirent *e;
  int n = 0;
  while (d && (e = readdir(d))) n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
  if (d) closedir(d);
  return d && n == 0;
}

/* Run on np ranks: exit 2, stderr holding each of the needles, out/ empty. */
static void expect_refused(int np, const char *opts, const char *needle1, const char *needle2) {
  char *out = NULL, path[1024];
  int rc = tu_mpirun(&out, np, "sh -c 'cd %s && %s run scene.xml %s --report out/r.json -q'", dir, tu_cli(), opts);
  if (rc != 2 || !strstr(out, needle1) || (needle2 && !strstr(out, needle2))) fprintf(stderr, "exit %d:\n%s", rc, out);
  assert_int_equal(rc, 2);
  assert_non_null(strstr(out, needle1));
  if (needle2) assert_non_null(strstr(out, needle2));
  free(out);
  snprintf(path, sizeof path, "%s/out", dir);
  assert_true(empty_dir(path));
}

/* A fresh case where the shell command cmd (run in the temporary
 * directory) spoils one part: refused naming file, with reason. */
static void spoiled(const char *cmd, const char *file, const char *reason) {
  char *out = NULL;
  fresh_case();
  tu_run(&out, "cd %s && %s", dir, cmd);
  free(out);
  expect_refused(NP, "-o out/r.msh", file, reason);
}

static void missing_part(void **state) {
  (void)state;
  spoiled("rm case/box_parts_3.msh", "case/box_parts_3.msh", "not found");
}

static void part_of_another_mesh(void **state) {
  (void)state;
  spoiled("cp other_parts_2.msh case/box_parts_2.msh", "box_parts_2.msh", "different meshes");
}

static void part_of_another_split(void **state) {
  (void)state;
  spoiled("cp three_parts_3.msh case/box_parts_3.msh", "box_parts_3.msh", "overlap");
}

static void wrong_partition_number(void **state) {
  (void)state;
  spoiled("cp box_parts_1.msh case/box_parts_4.msh", "case/box_parts_4.msh", "not partition 4");
}

static void whole_mesh_as_part(void **state) {
  (void)state;
  spoiled("cp box.msh case/box_parts_2.msh", "case/box_parts_2.msh", "not a part file");
}

static void wrong_rank_count(void **state) {
  (void)state;
  fresh_case();
  expect_refused(2, "-o out/r.msh", "scene.xml:3", "mpirun -n 4");
}

/* -o naming the parts themselves: refused, and the parts are untouched. */
static void output_over_parts(void **state) {
  (void)state;
  fresh_case();
  char *out = NULL, path[1024];
  struct stat before, after;
  snprintf(path, sizeof path, "%s/case/box_parts_1.msh", dir);
  assert_int_equal(stat(path, &before), 0);
  expect_refused(NP, "-o case/box_parts.msh", "refusing to overwrite an input", NULL);
  assert_int_equal(stat(path, &after), 0);
  assert_true(before.st_size == after.st_size && before.st_mtime == after.st_mtime && before.st_ino == after.st_ino);
  int rc = tu_run(&out, "ls -a %s/case | grep -c dtmap", dir); /* no temporaries left beside them */
  free(out);
  assert_int_not_equal(rc, 0);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(missing_part),          cmocka_unit_test(part_of_another_mesh),
      cmocka_unit_test(part_of_another_split), cmocka_unit_test(wrong_partition_number),
      cmocka_unit_test(whole_mesh_as_part),    cmocka_unit_test(wrong_rank_count),
      cmocka_unit_test(output_over_parts),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
