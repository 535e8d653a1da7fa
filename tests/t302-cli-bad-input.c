/* Bad input through the CLI: each case exits 2, names the place (file:line,
 * or the element tag and physical group), and leaves no output file behind
 * (nor a temporary one). Geometries are small .geo files written here and
 * meshed by the real Gmsh library. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "testutil.h"

/* A 2D square "rock" with a "plate" on top, two physical surfaces. */
static const char square_geo[] = "SetFactory(\"OpenCASCADE\");\n"
                                 "Rectangle(1) = {0, 0, 0, 1, 1};\n"
                                 "Rectangle(2) = {0, 1, 0, 1, 0.2};\n"
                                 "BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }\n"
                                 "Physical Surface(\"rock\") = {1};\n"
                                 "Physical Surface(\"plate\") = {2};\n";

/* A curve loop that crosses itself: meshing it fails. */
static const char bowtie_geo[] =
    "Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {0, 1, 0}; Point(4) = {1, 1, 0};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4};\nPlane Surface(1) = {1};\nPhysical Surface(\"rock\") = {1};\n";

static const char head[] = "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n";

static int setup(void **state) {
  char p[512];
  snprintf(p, sizeof p, "%s/square.geo", tu_tmpdir());
  tu_write(p, square_geo);
  snprintf(p, sizeof p, "%s/bowtie.geo", tu_tmpdir());
  tu_write(p, bowtie_geo);
  (void)state;
  return 0;
}

/* Files in the temporary directory other than the fixtures. */
static int stray_files(void) {
  DIR *d = opendir(tu_tmpdir());
  int n = 0;
  for (struct dirent *e; (e = readdir(d));)
    if (strstr(e->d_name, ".msh") || strstr(e->d_name, ".json") || strstr(e->d_name, ".tmp")) n++;
  closedir(d);
  return n;
}

/* Run scene text (written to NAME.xml) and check exit 2, no output, and
 * that stderr contains every expected fragment. */
static void expect_fail(const char *name, const char *body, const char *const *expect) {
  char scene[512], *log = NULL;
  snprintf(scene, sizeof scene, "%s/%s.xml", tu_tmpdir(), name);
  char *text = malloc(strlen(head) + strlen(body) + 32);
  sprintf(text, "%s%s</dtmap-scene>\n", head, body);
  tu_write(scene, text);
  free(text);
  int code = tu_run(&log, "%s run %s -q -o %s/out.msh --report %s/out.json", tu_cli(), scene, tu_tmpdir(), tu_tmpdir());
  for (int i = 0; expect[i]; i++)
    if (!strstr(log, expect[i])) fprintf(stderr, "[%s] missing '%s' in:\n%s\n", name, expect[i], log);
  assert_int_equal(code, 2);
  for (int i = 0; expect[i]; i++) assert_non_null(strstr(log, expect[i]));
  assert_int_equal(stray_files(), 0);
  free(log);
}

#define MAT_OK "<material name=\"r\" groups=\"rock plate\" E=\"1e9\" nu=\"0.25\" rho=\"2000\"/>\n"
#define GEO "<geometry file=\"square.geo\"/>\n<meshing size=\"0.25\" dim=\"2\"/>\n"
#define FX "<effects><elastic formulation=\"plane-strain\"/></effects>\n"

static void missing_file(void **state) {
  char *log = NULL;
  int code = tu_run(&log, "%s run %s/nope.xml -q -o %s/out.msh", tu_cli(), tu_tmpdir(), tu_tmpdir());
  assert_int_equal(code, 2);
  assert_non_null(strstr(log, "nope.xml"));
  assert_int_equal(stray_files(), 0);
  free(log);
  (void)state;
}

static void malformed_xml(void **state) {
  /* Lines: 1 <?xml?>, 2 <dtmap-scene>, 3-4 geometry and meshing, 5 the
   * material, 6 the unclosed <effects>; libxml2 notices the mismatch at the
   * </dtmap-scene> on line 7 and names line 6 as the opening. */
  expect_fail("malformed", GEO MAT_OK "<effects><elastic formulation=\"plane-strain\"/>\n",
              (const char *const[]){"malformed.xml:7", "effects line 6", NULL});
  (void)state;
}

static void schema_violation(void **state) {
  expect_fail("schema", GEO MAT_OK "<effects><elastic formulation=\"plane\"/></effects>\n",
              (const char *const[]){"schema.xml:6", "'plane'", NULL});
  (void)state;
}

static void bad_values_single(void **state) {
  static const char *const mats[] = {"E=\"1e9\" nu=\"0.5\" rho=\"2000\"", "E=\"1e9\" nu=\"-1\" rho=\"2000\"",
                                     "E=\"0\" nu=\"0.3\" rho=\"2000\"",   "E=\"1e9\" nu=\"0.3\" rho=\"-5\"",
                                     "E=\"nan\" nu=\"0.3\" rho=\"2000\"", "E=\"1e9\" nu=\"NaN\" rho=\"2000\""};
  static const char *const what[] = {"nu", "nu", "E", "rho", "'E'", "nu"};
  /* "nan" is not an xs:double, so the schema rejects it before the material
   * check, and its message names the attribute but not the material. */
  static const char *const who[] = {"granite", "granite", "granite", "granite", "xs:double", "granite"};
  for (int i = 0; i < 6; i++) {
    char body[1024], name[32], where[64];
    snprintf(body, sizeof body, GEO "<material name=\"granite\" groups=\"rock plate\" %s/>\n" FX, mats[i]);
    snprintf(name, sizeof name, "value%d", i);
    snprintf(where, sizeof where, "%s.xml:5", name);
    expect_fail(name, body, (const char *const[]){where, what[i], who[i], NULL});
  }
  (void)state;
}

static void unknown_effect(void **state) {
  expect_fail("unknown", GEO MAT_OK "<effects>\n<effect name=\"plasticity\"/>\n</effects>\n",
              (const char *const[]){"unknown.xml:7", "'plasticity'", "known effects: elastic", NULL});
  (void)state;
}

static void damping_only(void **state) {
  expect_fail("damponly", GEO MAT_OK "<effects>\n<damping xi=\"0.1\"/>\n</effects>\n",
              (const char *const[]){"damponly.xml:6", "no effect that limits", NULL});
  (void)state;
}

static void group_without_material(void **state) {
  expect_fail("nogroup", GEO "<material name=\"r\" groups=\"rock\" E=\"1e9\" nu=\"0.25\" rho=\"2000\"/>\n" FX,
              (const char *const[]){"physical group 'plate'", "element ", "no default material", NULL});
  (void)state;
}

static void material_names_missing_group(void **state) {
  expect_fail("badgroup",
              GEO "<material name=\"r\" groups=\"rock plate platen\" E=\"1e9\" nu=\"0.25\" rho=\"2000\"/>\n" FX,
              (const char *const[]){"badgroup.xml:5", "'platen' does not exist", "'rock'", "'plate'", NULL});
  (void)state;
}

static void meshing_fails(void **state) {
  expect_fail("bowtie",
              "<geometry file=\"bowtie.geo\"/>\n<meshing size=\"0.25\" dim=\"2\"/>\n"
              "<material name=\"r\" groups=\"rock\" E=\"1e9\" nu=\"0.25\" rho=\"2000\"/>\n" FX,
              (const char *const[]){"bowtie.geo", NULL});
  (void)state;
}

static void missing_geometry(void **state) {
  expect_fail("nogeo", "<geometry file=\"absent.geo\"/>\n" MAT_OK FX,
              (const char *const[]){"nogeo.xml:3", "absent.geo", NULL});
  (void)state;
}

static long file_size(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return -1;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fclose(f);
  return n;
}

/* A scene that reads a .msh: writing the output over that .msh (or over the
 * scene) is refused with exit 2, and the input is left as it was. */
static void input_not_overwritten(void **state) {
  char msh[512], scene[512], text[1024], *log = NULL;
  snprintf(msh, sizeof msh, "%s/in.msh", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/frommesh.xml", tu_tmpdir());
  int code = tu_run(&log, "gmsh %s/square.geo -2 -clmax 0.25 -o %s", tu_tmpdir(), msh);
  free(log);
  assert_int_equal(code, 0);
  long before = file_size(msh);
  snprintf(text, sizeof text, "%s<mesh file=\"in.msh\"/>\n%s%s</dtmap-scene>\n", head, MAT_OK, FX);
  tu_write(scene, text);
  code = tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, msh);
  assert_int_equal(code, 2);
  assert_non_null(strstr(log, "refusing to overwrite"));
  free(log);
  assert_int_equal(file_size(msh), before);
  code = tu_run(&log, "%s run %s -q -o %s/fine.msh", tu_cli(), scene, tu_tmpdir()); /* and it does run */
  free(log);
  assert_int_equal(code, 0);
  char fine[600];
  snprintf(fine, sizeof fine, "%s/fine.msh", tu_tmpdir());
  unlink(fine);
  snprintf(fine, sizeof fine, "%s/fine.msh.opt", tu_tmpdir());
  unlink(fine);
  unlink(msh);
  (void)state;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(missing_file),
      cmocka_unit_test(malformed_xml),
      cmocka_unit_test(schema_violation),
      cmocka_unit_test(bad_values_single),
      cmocka_unit_test(unknown_effect),
      cmocka_unit_test(group_without_material),
      cmocka_unit_test(damping_only),
      cmocka_unit_test(input_not_overwritten),
      cmocka_unit_test(material_names_missing_group),
      cmocka_unit_test(meshing_fails),
      cmocka_unit_test(missing_geometry),
  };
  return cmocka_run_group_tests(tests, setup, NULL);
}
