/* Physical groups to materials: a group without a name is referred to by
 * its number; elements in no group take the default material; the output
 * keeps every analysed element (Mesh.SaveAll) so the views cover them; and
 * an effect's groups may overlap the material groups (a fracture zone that
 * is also part of the rock). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

/* Three squares: one in the named group "rock", one in the unnamed
 * physical group 7, one in no group at all. */
static const char geo[] =
    "SetFactory(\"OpenCASCADE\");\n"
    "Rectangle(1) = {0, 0, 0, 1, 1};\nRectangle(2) = {1, 0, 0, 1, 1};\nRectangle(3) = {2, 0, 0, 1, 1};\n"
    "BooleanFragments{ Surface{1}; Delete; }{ Surface{2, 3}; Delete; }\n"
    "Physical Surface(\"rock\") = {1};\nPhysical Surface(7) = {2};\nPhysical Surface(\"fz\") = {1, 2};\n";

static void run_fx(const char *name, const char *materials, const char *effects, int expect, const char *expect_msg);

static void run(const char *name, const char *materials, int expect, const char *expect_msg) {
  run_fx(name, materials, "<elastic/>", expect, expect_msg);
}

static void run_fx(const char *name, const char *materials, const char *effects, int expect, const char *expect_msg) {
  char path[512], text[2048], *log = NULL;
  snprintf(path, sizeof path, "%s/three.geo", tu_tmpdir());
  tu_write(path, geo);
  snprintf(path, sizeof path, "%s/%s.xml", tu_tmpdir(), name);
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n<geometry file=\"three.geo\"/>\n"
           "<meshing size=\"0.25\" dim=\"2\"/>\n%s<effects>%s</effects>\n</dtmap-scene>\n",
           materials, effects);
  tu_write(path, text);
  int code = tu_run(&log, "%s run %s -q -o %s/%s.msh --report %s/%s.json", tu_cli(), path, tu_tmpdir(), name,
                    tu_tmpdir(), name);
  if (code != expect) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, expect);
  if (expect_msg) assert_non_null(strstr(log, expect_msg));
  free(log);
}

/* The stiff default material (100 E) in the third square sets the smallest
 * step: its wave speed is 10x higher on elements of the same size. */
static void default_and_number(void **unused) {
  run("ok",
      "<material name=\"rock\" groups=\"rock\" E=\"1e10\" nu=\"0.25\" rho=\"2500\"/>\n"
      "<material name=\"seven\" groups=\"7\" E=\"1e10\" nu=\"0.25\" rho=\"2500\"/>\n"
      "<material name=\"stiff\" default=\"true\" E=\"1e12\" nu=\"0.25\" rho=\"2500\"/>\n",
      0, NULL);
  char rep[512];
  snprintf(rep, sizeof rep, "%s/ok.json", tu_tmpdir());
  cJSON *j = tu_json_load(rep);
  assert_non_null(j);
  const cJSON *g = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "dt"), "group");
  assert_string_equal(g->valuestring, "(none)");
  double cx = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "dt"), "centroid"), 0)->valuedouble;
  assert_true(cx > 2.0 && cx < 3.0);
  cJSON_Delete(j);
  (void)unused;
}

static void no_default(void **unused) {
  run("nodefault", "<material name=\"rock\" groups=\"rock 7\" E=\"1e10\" nu=\"0.25\" rho=\"2500\"/>\n", 2,
      "is in no physical group");
  (void)unused;
}

/* The cohesive effect on group "fz" (squares 1 and 2, which get their
 * materials from "rock" and 7): its 1/30 rule must apply there, so it limits
 * the step, and its smallest step lies in squares 1-2 (x < 2). */
static void overlapping_groups(void **unused) {
  run_fx("overlap",
         "<material name=\"rock\" groups=\"rock 7\" E=\"1e10\" nu=\"0.25\" rho=\"2500\" fracture-energy=\"50\" "
         "strength=\"1e7\"/>\n<material name=\"other\" default=\"true\" E=\"1e10\" nu=\"0.25\" rho=\"2500\"/>\n",
         "<elastic/><cohesive groups=\"fz\"/>", 0, NULL);
  char rep[512];
  snprintf(rep, sizeof rep, "%s/overlap.json", tu_tmpdir());
  cJSON *j = tu_json_load(rep);
  const cJSON *mins = cJSON_GetObjectItem(j, "effect_minima");
  const cJSON *coh = cJSON_GetArrayItem(mins, 1);
  double cmin = cJSON_GetObjectItem(coh, "min")->valuedouble;
  double cx = cJSON_GetArrayItem(cJSON_GetObjectItem(coh, "centroid"), 0)->valuedouble;
  assert_true(isfinite(cmin) && cmin > 0);
  assert_true(cx < 2.0); /* in squares 1-2 */
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "dt"), "effect")->valuestring, "cohesive");
  cJSON_Delete(j);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(default_and_number), cmocka_unit_test(no_default),
                                     cmocka_unit_test(overlapping_groups)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
