/* Scene reader, bad input: every case returns DTM_ERR_INPUT with a message
 * that starts with "PATH:LINE: " (the line of the offending element) and
 * says what is wrong: malformed XML, schema violations, inadmissible
 * material values, duplicate defaults, names and groups, bad or missing
 * source files, bad time and output options. Each case is a copy of one
 * valid scene with some lines replaced, so the expected line is known.
 * Also checks that libxml2 prints nothing on stderr. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "testutil.h"
#include <dirent.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "dtmap/error.h"
#include "dtmap/scene.h"

static char dir[PATH_MAX]; /* temporary directory of the fixtures */

#define NLINES 10
static const char *const base[NLINES] = {
    "<?xml version=\"1.0\"?>",                                                            /* 1 */
    "<dtmap-scene version=\"1\">",                                                        /* 2 */
    "  <geometry file=\"disc.geo\"/>",                                                    /* 3 */
    "  <material name=\"rock\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\"/>",    /* 4 */
    "  <material name=\"steel\" groups=\"platen\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>", /* 5 */
    "  <effects>",                                                                        /* 6 */
    "    <elastic formulation=\"plane-strain\" length=\"eigen\"/>",                       /* 7 */
    "  </effects>",                                                                       /* 8 */
    "  <time safety=\"0.9\"/>",                                                           /* 9 */
    "</dtmap-scene>",                                                                     /* 10 */
};

typedef struct {
  const char *name;    /* fixture file is NAME.xml */
  int line[3];         /* lines (1-based) replaced, 0 = unused */
  const char *text[3]; /* their replacements */
  int expect_line;     /* line the message must name */
  const char *expect;  /* text the message must contain after "PATH:LINE: " */
} error_case;

static const error_case cases[] = {
    {"unclosed-tag",
     {3},
     {"  <geometry file=\"disc.geo\">"},
     10,
     "malformed XML: Opening and ending tag mismatch: geometry line 3 and dtmap-scene"},
    {"mismatched-tag",
     {7},
     {"    <elastic formulation=\"3d\"></elastc>"},
     7,
     "malformed XML: Opening and ending tag mismatch: elastic line 7 and elastc"},
    {"unbalanced-quote", {4}, {"  <material name=\"rock\" E=\"60e9 nu=\"0.25\"/>"}, 4, "malformed XML: "},
    {"bad-entity", {4}, {"  <material name=\"rock&amp\" E=\"60e9\"/>"}, 4, "malformed XML: "},
    {"unknown-element", {7}, {"    <thermall/>"}, 7, "schema: Element 'thermall': This element is not expected."},
    {"bad-formulation",
     {7},
     {"    <elastic formulation=\"plane\"/>"},
     7,
     "schema: Element 'elastic', attribute 'formulation': [facet 'enumeration'] "
     "The value 'plane' is not an element of the set"},
    {"bad-length", {7}, {"    <elastic length=\"edge\"/>"}, 7, "schema: "},
    {"unknown-attribute",
     {7},
     {"    <elastic formulaton=\"3d\"/>"},
     7,
     "schema: Element 'elastic', attribute 'formulaton': The attribute 'formulaton' is "
     "not allowed."},
    {"bad-version", {2}, {"<dtmap-scene version=\"2\">"}, 2, "schema: "},
    {"no-effects", {6, 7, 8}, {"", "", ""}, 9, "schema: Element 'time': This element is not expected."},
    {"empty-effects", {7}, {""}, 6, "schema: Element 'effects': Missing child element(s)."},
    /* an element out of order: the message states <dtmap-scene>'s order (issue 37) */
    {"time-before-material",
     {4, 9},
     {"  <time safety=\"0.9\"/>", "  <material name=\"rock\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\"/>"},
     4,
     "Element 'time': This element is not expected. Expected is one of ( meshing, material, section ). "
     "(<dtmap-scene> holds, in this order: (geometry | mesh | model), meshing?, (material | section)+, effects"},
    {"effect-without-name", {7}, {"    <effect library=\"x.so\"/>"}, 7, "schema: "},
    {"E-junk",
     {4},
     {"  <material name=\"rock\" E=\"60e9x\"/>"},
     4,
     "schema: Element 'material', attribute 'E': '60e9x' is not a valid value"},
    {"E-nan-lowercase", {4}, {"  <material name=\"rock\" E=\"nan\"/>"}, 4, "schema: "},
    {"nu-half",
     {4},
     {"  <material name=\"rock\" E=\"60e9\" nu=\"0.5\"/>"},
     4,
     "material 'rock': nu = 0.5 is not admissible (need -1 < nu < 0.5)"},
    {"nu-minus-one",
     {4},
     {"  <material name=\"rock\" nu=\"-1\"/>"},
     4,
     "material 'rock': nu = -1 is not admissible (need -1 < nu < 0.5)"},
    {"nu-just-above",
     {4},
     {"  <material name=\"rock\" nu=\"0.50000000000001\"/>"},
     4,
     "material 'rock': nu = 0.50000000000001 is not admissible"},
    {"E-zero",
     {4},
     {"  <material name=\"rock\" E=\"0\"/>"},
     4,
     "material 'rock': E = 0 is not admissible (need E > 0)"},
    {"rho-negative",
     {5},
     {"  <material name=\"steel\" rho=\"-1\"/>"},
     5,
     "material 'steel': rho = -1 is not admissible (need rho > 0)"},
    {"E-NaN",
     {4},
     {"  <material name=\"rock\" E=\"NaN\"/>"},
     4,
     "material 'rock': E = nan is not admissible (need a finite number)"},
    {"E-INF",
     {4},
     {"  <material name=\"rock\" E=\"INF\"/>"},
     4,
     "material 'rock': E = inf is not admissible (need a finite number)"},
    {"xi-negative",
     {4},
     {"  <material name=\"rock\" xi=\"-0.1\"/>"},
     4,
     "material 'rock': xi = -0.1 is not admissible (need xi >= 0)"},
    {"storage-zero",
     {4},
     {"  <material name=\"rock\" storage=\"0\"/>"},
     4,
     "material 'rock': storage = 0 is not admissible (need storage > 0)"},
    {"two-defaults",
     {4, 5},
     {"  <material name=\"rock\" default=\"true\"/>", "  <material name=\"steel\" default=\"1\"/>"},
     5,
     "material 'steel' is a second default material (the first is 'rock' at line 4)"},
    {"duplicate-name",
     {5},
     {"  <material name=\"rock\" groups=\"platen\"/>"},
     5,
     "material 'rock' is defined twice (first at line 4)"},
    {"group-twice",
     {5},
     {"  <material name=\"steel\" groups=\"platen rock\"/>"},
     5,
     "group 'rock' is given to material 'rock' (line 4) and to material 'steel'"},
    {"group-repeated",
     {4},
     {"  <material name=\"rock\" groups=\"a b a\"/>"},
     4,
     "material 'rock' lists group 'a' twice"},
    {"bad-geometry-extension",
     {3},
     {"  <geometry file=\"disc.stl\"/>"},
     3,
     "geometry file 'disc.stl' has an unsupported extension (use .geo, .step, .stp, .iges, .igs or .brep"},
    {"geometry-is-mesh",
     {3},
     {"  <geometry file=\"disc.msh\"/>"},
     3,
     "geometry file 'disc.msh' is a mesh; use <mesh file=\"disc.msh\"/>"},
    {"mesh-not-msh", {3}, {"  <mesh file=\"disc.geo\"/>"}, 3, "mesh file 'disc.geo' is not a Gmsh .msh file"},
    {"missing-geometry",
     {3},
     {"  <geometry file=\"nothere.geo\"/>"},
     3,
     "geometry file 'nothere.geo' not found (looked for '"},
    {"missing-mesh", {3}, {"  <mesh file=\"sub/none.msh\"/>"}, 3, "mesh file 'sub/none.msh' not found"},
    {"geometry-is-directory", {3}, {"  <geometry file=\"adir.geo\"/>"}, 3, "is a directory"},
    {"safety-above-one", {9}, {"  <time safety=\"1.5\"/>"}, 9, "schema: "},
    {"target-inf",
     {9},
     {"  <time target=\"INF\"/>"},
     9,
     "<time> target=\"INF\" is not admissible (need a finite number > 0)"},
    {"safety-nan", {9}, {"  <time safety=\"NaN\"/>"}, 9, "schema: "},
    {"min-size-above-size",
     {3},
     {"  <geometry file=\"disc.geo\"/><meshing size=\"1e-3\" min-size=\"1e-2\"/>"},
     3,
     "<meshing> min-size=0.01 is larger than size=0.001"},
    {"order-three", {3}, {"  <geometry file=\"disc.geo\"/><meshing order=\"3\"/>"}, 3, "schema: "},
    {"output-not-msh", {9}, {"  <output mesh=\"out.vtk\"/>"}, 9, "<output> mesh=\"out.vtk\" must be a Gmsh .msh file"},
};

static void write_file(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

static const char *line_text(const error_case *c, int line) {
  for (int k = 0; k < 3; k++)
    if (c->line[k] == line) return c->text[k];
  return base[line - 1];
}

static void write_case(const error_case *c, const char *path) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  for (int l = 1; l <= NLINES; l++) fprintf(f, "%s\n", line_text(c, l));
  fclose(f);
}

/* Load path, expect DTM_ERR_INPUT and a message "PREFIX<expect>...". */
static void expect_error(const char *path, const char *prefix, const char *expect) {
  dtm_scene *s = (dtm_scene *)&s; /* must be reset to NULL */
  dtm_error_clear();
  int rc = dtm_scene_load(path, &s);
  const char *msg = dtm_error_message();
  if (getenv("DTM_TEST_VERBOSE")) fprintf(stderr, "%s\n", msg);
  if (rc != DTM_ERR_INPUT || strncmp(msg, prefix, strlen(prefix)) || !strstr(msg + strlen(prefix), expect))
    fprintf(stderr, "rc %d\n  got    '%s'\n  wanted '%s%s'\n", rc, msg, prefix, expect);
  assert_int_equal(rc, DTM_ERR_INPUT);
  assert_null(s);
  assert_int_equal(strncmp(msg, prefix, strlen(prefix)), 0);
  assert_non_null(strstr(msg + strlen(prefix), expect));
}

static void run_case(const error_case *c) {
  char path[PATH_MAX * 2], prefix[PATH_MAX * 2 + 32];
  snprintf(path, sizeof path, "%s/%s.xml", dir, c->name);
  snprintf(prefix, sizeof prefix, "%s:%d: ", path, c->expect_line);
  write_case(c, path);
  expect_error(path, prefix, c->expect);
}

static void test_cases(void **state) {
  (void)state;
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) run_case(&cases[i]);
}

/* The base scene itself is valid, so each case fails for its own reason. */
static void test_base_is_valid(void **state) {
  (void)state;
  char path[PATH_MAX * 2];
  error_case none = {"valid", {0}, {0}, 0, ""};
  dtm_scene *s = NULL;
  snprintf(path, sizeof path, "%s/valid.xml", dir);
  write_case(&none, path);
  dtm_error_clear();
  assert_int_equal(dtm_scene_load(path, &s), DTM_OK);
  dtm_scene_destroy(&s);
}

static void test_missing_file(void **state) {
  (void)state;
  char path[PATH_MAX * 2], want[PATH_MAX * 3];
  snprintf(path, sizeof path, "%s/nofile.xml", dir);
  snprintf(want, sizeof want, "%s: cannot read scene file: No such file or directory", path);
  expect_error(path, want, "");
  assert_string_equal(dtm_error_message(), want);
}

static void test_directory_as_scene(void **state) {
  (void)state;
  char want[PATH_MAX * 2];
  snprintf(want, sizeof want, "%s: cannot read scene file: Is a directory", dir);
  expect_error(dir, want, "");
}

static void test_empty_file(void **state) {
  (void)state;
  char path[PATH_MAX * 2], prefix[PATH_MAX * 2 + 32];
  snprintf(path, sizeof path, "%s/empty.xml", dir);
  write_file(path, "");
  snprintf(prefix, sizeof prefix, "%s:1: ", path);
  expect_error(path, prefix, "malformed XML: Document is empty");
}

/* libxml2 must not print anything itself: all goes into the message. */
static void test_stderr_silent(void **state) {
  (void)state;
  char path[PATH_MAX * 2], log[PATH_MAX * 2];
  snprintf(path, sizeof path, "%s/broken.xml", dir);
  snprintf(log, sizeof log, "%s/stderr.log", dir);
  write_file(path, "<dtmap-scene version=\"1\">\n<geometry file=\"a.geo\">\n</dtmap-scene>\n");
  fflush(stderr);
  int saved = dup(2), fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0600);
  dup2(fd, 2);
  dtm_scene *s = NULL;
  dtm_error_clear();
  int rc = dtm_scene_load(path, &s);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  close(fd);
  struct stat st;
  assert_int_equal(stat(log, &st), 0);
  assert_int_equal(st.st_size, 0);
  assert_int_equal(rc, DTM_ERR_INPUT);
}

static int setup(void **state) {
  char path[PATH_MAX * 2];
  (void)state;
  strcpy(dir, "/tmp/dtm-t202-XXXXXX");
  if (!mkdtemp(dir)) return -1;
  snprintf(path, sizeof path, "%s/disc.geo", dir);
  write_file(path, "// dummy\n");
  snprintf(path, sizeof path, "%s/adir.geo", dir);
  return mkdir(path, 0700);
}

static int teardown(void **state) {
  (void)state;
  tu_remove_tree(dir);
  return 0;
}

int main(int argc, char **argv) {
  (void)argc;
  (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_base_is_valid), cmocka_unit_test(test_cases),
      cmocka_unit_test(test_missing_file),  cmocka_unit_test(test_directory_as_scene),
      cmocka_unit_test(test_empty_file),    cmocka_unit_test(test_stderr_silent),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
