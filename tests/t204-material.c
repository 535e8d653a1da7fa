/* Material properties (src/material.c): attribute names round-trip through
 * dtm_prop_find, the admissibility rules hold at and around their bounds,
 * and dtm_prop_check / dtm_material_require produce messages naming the
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

static dtm_material rock(void) {
  dtm_material m = {.name = "rock", .file = "scene.xml", .line = 7};
  return m;
}

static void test_names(void **state) {
  (void)state;
  for (int p = 0; p < DTM_PROP_COUNT; p++) {
    assert_non_null(dtm_prop_name(p));
    assert_int_equal(dtm_prop_find(dtm_prop_name(p)), p);
  }
  assert_string_equal(dtm_prop_name(DTM_PROP_HEAT_CAPACITY), "heat-capacity");
  assert_string_equal(dtm_prop_name(DTM_PROP_E), "E");
  assert_null(dtm_prop_name(-1));
  assert_null(dtm_prop_name(DTM_PROP_COUNT));
  assert_int_equal(dtm_prop_find("e"), -1);
  assert_int_equal(dtm_prop_find("Nu"), -1);
  assert_int_equal(dtm_prop_find(NULL), -1);
}

static void check_value(int p, double v, int want) {
  dtm_material m = rock();
  dtm_error_clear();
  int rc = dtm_prop_check(&m, p, v);
  if (rc != want) print_error("%s = %g: rc %d, wanted %d\n", dtm_prop_name(p), v, rc, want);
  assert_int_equal(rc, want);
}

static void test_bounds(void **state) {
  (void)state;
  const int in = DTM_OK, out = DTM_ERR_INPUT;
  check_value(DTM_PROP_NU, 0.4999999, in);
  check_value(DTM_PROP_NU, 0.5, out);
  check_value(DTM_PROP_NU, -0.999, in);
  check_value(DTM_PROP_NU, -1, out);
  check_value(DTM_PROP_NU, 0, in);
  check_value(DTM_PROP_E, 1e-300, in);
  check_value(DTM_PROP_E, 0, out);
  check_value(DTM_PROP_RHO, -1, out);
  check_value(DTM_PROP_STORAGE, 1e-12, in);
  check_value(DTM_PROP_XI, 0, in);
  check_value(DTM_PROP_XI, -1e-9, out);
  check_value(DTM_PROP_BETA, 0, in);
  check_value(DTM_PROP_ALPHA, INFINITY, out);
  check_value(DTM_PROP_E, NAN, out);
  check_value(DTM_PROP_COUNT, 1, DTM_ERR_INTERNAL);
}

static void test_check_message(void **state) {
  (void)state;
  dtm_material m = rock();
  dtm_error_clear();
  assert_int_equal(dtm_prop_check(&m, DTM_PROP_NU, 0.5), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "scene.xml:7: material 'rock': nu = 0.5 is not "
                                           "admissible (need -1 < nu < 0.5)");
  /* the next double above 0.5 must not print as 0.5 */
  dtm_error_clear();
  assert_int_equal(dtm_prop_check(&m, DTM_PROP_NU, 0.5000000000000001), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "nu = 0.5000000000000001 is"));
  dtm_error_clear();
  assert_int_equal(dtm_prop_check(NULL, DTM_PROP_E, 0), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "E = 0 is not admissible (need E > 0)");
  dtm_error_clear();
}

static void test_require(void **state) {
  (void)state;
  dtm_material m = rock();
  const unsigned thermal =
      DTM_PROP_BIT(DTM_PROP_CONDUCTIVITY) | DTM_PROP_BIT(DTM_PROP_HEAT_CAPACITY) | DTM_PROP_BIT(DTM_PROP_RHO);
  m.have = DTM_PROP_BIT(DTM_PROP_RHO) | DTM_PROP_BIT(DTM_PROP_HEAT_CAPACITY);
  dtm_error_clear();
  assert_int_equal(dtm_material_require(&m, thermal, "thermal"), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "scene.xml:7: material 'rock' has no "
                                           "'conductivity', needed by effect 'thermal'");
  m.have = 0;
  dtm_error_clear();
  assert_int_equal(dtm_material_require(&m, thermal, "thermal"), DTM_ERR_INPUT);
  assert_string_equal(dtm_error_message(), "scene.xml:7: material 'rock' has no 'rho', 'conductivity', "
                                           "'heat-capacity', needed by effect 'thermal'");
  m.have = thermal;
  dtm_error_clear();
  assert_int_equal(dtm_material_require(&m, thermal, "thermal"), DTM_OK);
  assert_int_equal(dtm_material_require(&m, 0, "none"), DTM_OK);
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
