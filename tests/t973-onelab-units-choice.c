/* dtmap's ONELAB panel on a model with no scene beside it offers the system
 * of units (issue 43, item 1): "dtmap/0Units", SI (0) by default, mm-t-s (1)
 * for a model drawn in mm. Driven by Gmsh's own machinery as t805 does (the
 * test process is the Gmsh session, gmshOnelabRun launches `dtmap -onelab`).
 * The model is a 20 x 20 x 60 mm box (.geo in mm, no box.xml beside it).
 * Checked: by default the fields say m and Pa (SI, as before); with mm-t-s
 * chosen the mesh size says mm and E, rho MPa, t/mm^3, the library's steel
 * is shown converted (210e9 Pa = 210000 MPa, 7850 kg/m^3 = 7.85e-9 t/mm^3,
 * to 1e-15: one division); the scene the panel writes says units="mm-t-s";
 * and its recommended and smallest element steps equal those of `dtmap run`
 * on a scene written by hand in mm-t-s (the same geometry, mesh size 8 mm,
 * steel in MPa, t/mm^3) to 1e-12 relative (the same computation; only the
 * text round trip of the values differs). Fails on the code before: no such
 * parameter, the fields always SI, so the mm box was analysed with E read
 * in Pa. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <gmshc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "onelab.h"
#include "testutil.h"

static char dir[512], geo[600], saved[600], report[600];

static const char *const box_geo = "SetFactory(\"OpenCASCADE\");\n"
                                   "Box(1) = {0, 0, 0, 20, 20, 60};\n"
                                   "Physical Volume(\"block\") = {1};\n";

/* The same model in a scene of its own (elsewhere: not beside the model). */
static const char *const hand_xml = "<dtmap-scene version=\"1\" units=\"mm-t-s\">\n"
                                    "  <geometry file=\"../nobase/box.geo\"/>\n"
                                    "  <meshing size=\"8\" dim=\"3\"/>\n"
                                    "  <material name=\"steel\" default=\"true\" E=\"210000\" nu=\"0.3\" "
                                    "rho=\"7.85e-9\"/>\n"
                                    "  <effects><elastic/></effects>\n"
                                    "  <time safety=\"0.9\"/>\n"
                                    "</dtmap-scene>\n";

static int setup(void **state) {
  (void)state;
  char path[700], *log = NULL;
  snprintf(dir, sizeof dir, "%s/nobase", tu_tmpdir());
  snprintf(geo, sizeof geo, "%s/box.geo", dir);
  snprintf(saved, sizeof saved, "%s/saved.xml", dir);
  snprintf(report, sizeof report, "%s/hand/hand.json", tu_tmpdir());
  int r = tu_run(NULL, "mkdir -p %s %s/hand", dir, tu_tmpdir());
  tu_write(geo, box_geo);
  snprintf(path, sizeof path, "%s/hand/hand.xml", tu_tmpdir());
  tu_write(path, hand_xml);
  if (!r) r = tu_run(&log, "%s run %s -q -o %s/hand/hand_dt.msh --report %s", tu_cli(), path, tu_tmpdir(), report);
  if (r) fprintf(stderr, "%s\n", log ? log : "");
  free(log);
  return r;
}

static int close_to(double a, double b, double rel) { return fabs(a - b) <= rel * fabs(b); }

/* Without a choice: SI, as the panel always was. */
static void test_default_si(void **state) {
  (void)state;
  tu_onelab_session(geo, "t973");
  tu_onelab_run("check");
  assert_true(tu_onelab_get_number("dtmap/0Units") == 0);
  tu_onelab_assert_units("dtmap/3Mesh/0size", "m");
  tu_onelab_assert_units("dtmap/4Materials/block/1E", "Pa");
  tu_gmsh_end();
}

/* mm-t-s chosen: the fields in mm, MPa, t/mm^3, the library converted, and
 * the panel's run is the hand-written mm-t-s scene's. */
static void test_mm(void **state) {
  (void)state;
  tu_onelab_session(geo, "t973");
  tu_onelab_run("check");
  tu_onelab_set_number("dtmap/0Units", 1);
  tu_onelab_run("check");
  tu_onelab_assert_units("dtmap/3Mesh/0size", "mm");
  tu_onelab_assert_units("dtmap/4Materials/block/1E", "MPa");
  tu_onelab_assert_units("dtmap/4Materials/block/3rho", "t/mm^3");
  tu_onelab_set_number("dtmap/4Materials/block/0material", 1); /* the library's first entry: steel */
  tu_onelab_set_number("dtmap/3Mesh/0size", 8);
  tu_onelab_run("check");
  assert_true(close_to(tu_onelab_get_number("dtmap/4Materials/block/1E"), 210000, 1e-15));
  assert_true(close_to(tu_onelab_get_number("dtmap/4Materials/block/3rho"), 7.85e-9, 1e-15));
  double rec, dmin;
  char *text = tu_onelab_compute_saved(saved, &rec, &dmin);
  if (!strstr(text, "units=\"mm-t-s\"")) fprintf(stderr, "the panel's scene:\n%s\n", text);
  assert_non_null(strstr(text, "units=\"mm-t-s\""));
  free(text);
  cJSON *j = tu_json_load(report);
  double r = tu_json_number(j, "dt.recommended"), m = tu_json_number(j, "dt.min");
  cJSON_Delete(j);
  fprintf(stderr, "panel %.17g s (min %.17g s), dtmap run %.17g s (min %.17g s)\n", rec, dmin, r, m);
  assert_true(close_to(rec, r, 1e-12));
  assert_true(close_to(dmin, m, 1e-12));
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_default_si), cmocka_unit_test(test_mm)};
  return cmocka_run_group_tests(tests, setup, NULL);
}
