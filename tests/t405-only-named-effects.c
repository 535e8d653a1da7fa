/* Only the effects a scene names are created and run:
 * - a scene with only <thermal/> and materials with no elastic properties
 *   runs, creates exactly one effect, and writes "dt thermal" but no
 *   "dt elastic" view;
 * - a scene with only <elastic/> needs no thermal properties;
 * - a named effect whose property is missing fails, naming the material,
 *   the property and the effect. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <gmshc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "dtmap/output.h"
#include "dtmap/gmsh.h"
#include "testutil.h"

extern const dtm_effect_class dtm_effect_thermal, dtm_effect_elastic;

static void write_scene(const char *name, const char *material, const char *effects) {
  char path[600], text[4096];
  snprintf(path, sizeof path, "%s/sq.geo", tu_tmpdir());
  tu_write(path,
           "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 0.1, 0.1};\nPhysical Surface(\"rock\") = {1};\n");
  snprintf(path, sizeof path, "%s/%s.xml", tu_tmpdir(), name);
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n<geometry file=\"sq.geo\"/>\n"
           "<meshing size=\"0.02\" dim=\"2\"/>\n<material name=\"rock\" groups=\"rock\" %s/>\n"
           "<effects>%s</effects>\n</dtmap-scene>\n",
           material, effects);
  tu_write(path, text);
}

static void thermal_only(void **unused) {
  dtm_scene *s = NULL;
  write_scene("thermal", "conductivity=\"3\" heat-capacity=\"790\" rho=\"2700\"", "<thermal/>");
  dtm_analysis *a = tu_analyse("thermal", &s);
  assert_int_equal(a->neffects, 1);
  assert_ptr_equal(a->effects[0].cls, &dtm_effect_thermal);
  char out[600];
  snprintf(out, sizeof out, "%s/thermal.msh", tu_tmpdir());
  dtm_results res = {a, NULL, NULL, 0, 0, 0, 0, {NULL}, {NULL}, NULL, NULL};
  assert_int_equal(dtm_output_write(&res, out), 0);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  int ierr = 0;
  gmshOpen(out, &ierr);
  tu_view v;
  assert_int_equal(tu_view_read("dt thermal", &v), 0);
  tu_view_free(&v);
  assert_int_not_equal(tu_view_read("dt elastic", &v), 0);
  gmshClear(&ierr);
  (void)unused;
}

static void elastic_only(void **unused) {
  dtm_scene *s = NULL;
  write_scene("elastic", "E=\"1e9\" nu=\"0.2\" rho=\"2000\"", "<elastic/>");
  dtm_analysis *a = tu_analyse("elastic", &s);
  assert_int_equal(a->neffects, 1);
  assert_ptr_equal(a->effects[0].cls, &dtm_effect_elastic);
  dtm_analysis_destroy(&a);
  dtm_scene_destroy(&s);
  (void)unused;
}

static void missing_property(void **unused) {
  dtm_scene *s = NULL;
  dtm_analysis *a = NULL;
  char path[600];
  write_scene("missing", "E=\"1e9\" nu=\"0.2\" rho=\"2000\"", "<elastic/><thermal/>");
  snprintf(path, sizeof path, "%s/missing.xml", tu_tmpdir());
  assert_int_equal(dtm_scene_load(path, &s), 0);
  assert_int_equal(dtm_analysis_run(s, &a), DTM_ERR_INPUT);
  const char *msg = dtm_error_message();
  assert_non_null(strstr(msg, "missing.xml:5"));
  assert_non_null(strstr(msg, "'rock'"));
  assert_non_null(strstr(msg, "'conductivity'"));
  assert_non_null(strstr(msg, "'thermal'"));
  dtm_error_clear();
  dtm_scene_destroy(&s);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  if (dtm_gmsh_start(0)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(thermal_only), cmocka_unit_test(elastic_only),
                                     cmocka_unit_test(missing_property)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_gmsh_stop();
  return r;
}
