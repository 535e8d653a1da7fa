/* Material properties (src/material/material.c) and the property catalogue
 * of the built-in effects (src/registry/catalogue.c): every declared name
 * is found again and its first declaration is the one the others agree
 * with, the admissibility rules hold at and around their bounds, and
 * dtm_property_check / dtm_material_require produce messages naming the
 * scene file, line, material, property and effect. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/material.h"
#include "dtmap/registry.h"
#include "fixtures.h"

static dtm_material rock(void) {
  dtm_material m;
  tu_material(&m, "rock", NULL);
  m.file = "scene.xml";
  m.line = 7;
  return m;
}

static const dtm_property *prop(const char *name) { return dtm_registry_property(name, NULL); }

static void test_names(void **state) {
  (void)state;
  int n;
  const dtm_property *const *all = dtm_registry_properties(&n);
  assert_true(n >= 13);
  for (int p = 0; p < n; p++) {
    assert_non_null(all[p]->name);
    assert_ptr_equal(prop(all[p]->name), all[p]);
  }
  assert_string_equal(prop("heat-capacity")->name, "heat-capacity");
  assert_string_equal(prop("E")->name, "E");
  assert_null(prop("e"));
  assert_null(prop("Nu"));
  assert_null(prop(NULL));
  assert_int_equal(dtm_registry_check_all(), DTM_OK);
}

static void check_value(const char *name, double v, int want) {
  dtm_material m = rock();
  dtm_error_clear();
  int rc = dtm_property_check(name ? prop(name) : NULL, &m, v);
  if (rc != want) print_error("%s = %g: rc %d, wanted %d\n", name ? name : "(none)", v, rc, want);
  assert_int_equal(rc, want);
}

static void test_bounds(void **state) {
  (void)state;
  const int in = DTM_OK, out = DTM_ERR_INPUT;
  check_value("nu", 0.4999999, in);
  check_value("nu", 0.5, out);
  check_value("nu", -0.999, in);
  check_value("nu", -1, out);
  check_value("nu", 0, in);
  check_value("E", 1e-300, in);
  check_value("E", 0, out);
  check_value("rho", -1, out);
  check_value("storage", 1e-12, in);
  check_value("xi", 0, in);
  check_value("xi", -1e-9, out);
  check_value("beta", 0, in);
  check_value("alpha", INFINITY, out);
  check_value("E", NAN, out);
  check_value(NULL, 1, DTM_ERR_INTERNAL);
  dtm_error_clear();
}

static void test_check_message(void **state) {
  (void)state;
  dtm_material m = rock();
  dtm_error_clear();
  assert_int_equal(dtm_property_check(prop("nu"), &m, 0.5), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "scene.xml:7: material 'rock': nu = 0.5 is not "
                                           "admissible (need -1 < nu < 0.5)");
  /* the next double above 0.5 must not print as 0.5 */
  dtm_error_clear();
  assert_int_equal(dtm_property_check(prop("nu"), &m, 0.5000000000000001), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "nu = 0.5000000000000001 is"));
  dtm_error_clear();
  assert_int_equal(dtm_property_check(prop("E"), NULL, 0), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "E = 0 is not admissible (need E > 0)");
  dtm_error_clear();
}

static void test_require(void **state) {
  (void)state;
  static const dtm_property thermal[] = {{"rho", "kg/m^3", 0, HUGE_VAL, DTM_OPEN_LO, 1, "density"},
                                         {"conductivity", "W/(m K)", 0, HUGE_VAL, DTM_OPEN_LO, 1, "k"},
                                         {"heat-capacity", "J/(kg K)", 0, HUGE_VAL, DTM_OPEN_LO, 1, "c"},
                                         {"xi", "", 0, HUGE_VAL, 0, 0, "optional"},
                                         {NULL, NULL, 0, 0, 0, 0, NULL}};
  dtm_material m;
  tu_material(&m, "rock", "rho", 2700.0, "heat-capacity", 790.0, NULL);
  m.file = "scene.xml", m.line = 7;
  dtm_error_clear();
  assert_int_equal(dtm_material_require(&m, thermal, "thermal"), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "scene.xml:7: material 'rock' has no "
                                           "'conductivity', needed by effect 'thermal'");
  m = rock();
  dtm_error_clear();
  assert_int_equal(dtm_material_require(&m, thermal, "thermal"), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "scene.xml:7: material 'rock' has no 'rho', 'conductivity', "
                                           "'heat-capacity', needed by effect 'thermal'");
  tu_material(&m, "rock", "rho", 2700.0, "heat-capacity", 790.0, "conductivity", 3.0, NULL);
  dtm_error_clear();
  assert_int_equal(dtm_material_require(&m, thermal, "thermal"), DTM_OK);
  assert_int_equal(dtm_material_require(&m, NULL, "none"), DTM_OK);
  assert_int_equal(dtm_error_code(), DTM_OK);
}

int main(int argc, char **argv) {
  (void)argc;
  (void)argv;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_names),
      cmocka_unit_test(test_bounds),
      cmocka_unit_test(test_check_message),
      cmocka_unit_test(test_require),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
