/* The effect registry and external effects:
 * - every built-in effect is registered once, with the current API version;
 * - an unknown name fails listing the known ones;
 * - the example effect built as a .so loads through its entry symbol and
 *   runs in a real scene; a version mismatch and a missing symbol are clear
 *   errors (exit 2 through the CLI). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/effect_set.h"
#include "dtmap/registry.h"
#include "testutil.h"

static void builtins(void **unused) {
  static const char *const names[] = {"elastic", "damping", "thermal", "hydraulic", "cohesive"};
  assert_int_equal(dtm_registry_count(), 5);
  for (int i = 0; i < 5; i++) {
    const dtm_effect_class *c = NULL;
    assert_int_equal(dtm_registry_find(names[i], &c), 0);
    assert_ptr_equal(c, dtm_registry_get(i));
    assert_int_equal(c->api_version, DTM_EFFECT_API_VERSION);
    assert_true((c->role & DTM_ROLE_LIMITS) ? c->element_dt != NULL : c->wave_factor != NULL);
  }
  (void)unused;
}

static void unknown_lists_known(void **unused) {
  const dtm_effect_class *c = NULL;
  assert_int_equal(dtm_registry_find("plastic", &c), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "'plastic'"));
  assert_non_null(strstr(dtm_error_message(), "elastic, damping, thermal, hydraulic, cohesive"));
  dtm_error_clear();
  (void)unused;
}

static char libdir[1024];

static void lib_path(char *buf, size_t n, const char *name) {
  snprintf(buf, n, "%s/libdtmap_example_%s.so", libdir, name);
}

static void load_direct(void **unused) {
  char p[1200];
  const dtm_effect_class *c = NULL;
  void *h = NULL;
  lib_path(p, sizeof p, "courant");
  assert_int_equal(dtm_registry_load(p, "courant", &c, &h), 0);
  assert_string_equal(c->name, "courant");
  dtm_effect *e = calloc(1, sizeof *e);
  e->cls = c, e->handle = h;
  dtm_effects_destroy(&e, 1); /* closes the library */
  lib_path(p, sizeof p, "badversion");
  assert_int_equal(dtm_registry_load(p, "courant", &c, &h), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "API version mismatch"));
  dtm_error_clear();
  lib_path(p, sizeof p, "noentry");
  assert_int_equal(dtm_registry_load(p, "courant", &c, &h), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "dtm_effect_entry"));
  dtm_error_clear();
  (void)unused;
}

/* A 1 m square meshed at 0.25 m; elastic and the courant example side by
 * side. The example's dt is min-edge / speed, so with a very fast
 * signal speed it limits everywhere and dt.min = (shortest edge) / speed. */
static void run_scene(const char *lib, int expect_code, const char *expect_msg) {
  char geo[600], scene[600], text[4096], out[700], rep[700], p[1200], *log = NULL;
  snprintf(geo, sizeof geo, "%s/sq.geo", tu_tmpdir());
  tu_write(geo, "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {0, 0, 0, 1, 1};\nPhysical Surface(\"rock\") = {1};\n");
  lib_path(p, sizeof p, lib);
  snprintf(scene, sizeof scene, "%s/ext-%s.xml", tu_tmpdir(), lib);
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n<geometry file=\"sq.geo\"/>\n"
           "<meshing size=\"0.25\" dim=\"2\"/>\n"
           "<material name=\"r\" groups=\"rock\" E=\"1e9\" nu=\"0.25\" rho=\"2000\"/>\n"
           "<effects><elastic/><effect name=\"courant\" library=\"%s\" speed=\"1e6\"/></effects>\n</dtmap-scene>\n",
           p);
  tu_write(scene, text);
  snprintf(out, sizeof out, "%s/ext-%s.msh", tu_tmpdir(), lib);
  snprintf(rep, sizeof rep, "%s/ext-%s.json", tu_tmpdir(), lib);
  int code = tu_run(&log, "%s run %s -q -o %s --report %s", tu_cli(), scene, out, rep);
  if (code != expect_code) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, expect_code);
  if (expect_msg) assert_non_null(strstr(log, expect_msg));
  if (expect_code == 0) {
    cJSON *j = tu_json_load(rep);
    assert_non_null(j);
    const cJSON *eff = cJSON_GetObjectItem(j, "effects");
    assert_int_equal(cJSON_GetArraySize(eff), 2);
    assert_string_equal(cJSON_GetArrayItem(eff, 1)->valuestring, "courant");
    assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "dt"), "effect")->valuestring, "courant");
    double dt = tu_json_number(j, "dt.min"); /* shortest edge of a 0.25 m mesh at 1e6 m/s */
    assert_true(dt > 0.05e-6 && dt <= 0.25e-6 * 1.5);
    cJSON_Delete(j);
  } else {
    assert_false(tu_exists(out));
  }
  free(log);
}

static void run_external(void **unused) {
  run_scene("courant", 0, NULL);
  run_scene("badversion", 2, "API version mismatch");
  run_scene("noentry", 2, "no symbol 'dtm_effect_entry'");
  /* limits the step but has no element_dt: refused, not called (no crash) */
  run_scene("nostep", 2, "effect 'courant' declares DTM_ROLE_LIMITS but has no element_dt");
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  snprintf(libdir, sizeof libdir, "%s", DTM_TEST_LIBDIR); /* where CMake builds the examples */
  const struct CMUnitTest tests[] = {cmocka_unit_test(builtins), cmocka_unit_test(unknown_lists_known),
                                     cmocka_unit_test(load_direct), cmocka_unit_test(run_external)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
