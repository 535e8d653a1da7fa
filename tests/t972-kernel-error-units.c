/* The library's own error messages about figures it holds in SI (a
 * kernel's modulus, density, diffusivity) print them in the units of the
 * scene loaded (issue 43, item 1: one unit rule for every figure). After a
 * scene in mm-t-s is loaded, E = -2.1e11 Pa is said as -210000 MPa, rho =
 * -7850 kg/m^3 as -7.85e-09 t/mm^3 and a diffusivity of -1e-6 m^2/s as
 * -1 mm^2/s (the SI value over one mm-t-s unit: exact decimal conversions,
 * compared as text at %.6g); after a scene in SI, the same errors say Pa
 * and kg/m^3 again. Fails on the code before: the kernels printed "Pa",
 * "kg/m^3" and "m^2/s" whatever the scene's units. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/kernel.h"
#include "dtmap/scene.h"
#include "testutil.h"

static const char *const geo = "SetFactory(\"OpenCASCADE\");\nBox(1) = {0, 0, 0, 20, 20, 60};\n"
                               "Physical Volume(\"block\") = {1};\n";

/* Load a scene of the box in system units (its numbers in that system). */
static void load(const char *units, const char *E, const char *rho) {
  char path[600], text[1024];
  snprintf(path, sizeof path, "%s/box.geo", tu_tmpdir());
  tu_write(path, geo);
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\" units=\"%s\">\n  <geometry file=\"box.geo\"/>\n"
           "  <material name=\"steel\" default=\"true\" E=\"%s\" nu=\"0.3\" rho=\"%s\"/>\n"
           "  <effects><elastic/></effects>\n</dtmap-scene>\n",
           units, E, rho);
  snprintf(path, sizeof path, "%s/box_%s.xml", tu_tmpdir(), units);
  tu_write(path, text);
  dtm_scene *s = NULL;
  int r = dtm_scene_load(path, &s);
  if (r) fprintf(stderr, "%s\n", dtm_error_message());
  assert_int_equal(r, DTM_OK);
  dtm_scene_destroy(&s);
  dtm_error_clear();
}

/* The last error's message holds want. */
static void says(int r, const char *want) {
  assert_int_equal(r, DTM_ERR_INPUT);
  const char *msg = dtm_error_message();
  if (!strstr(msg, want)) fprintf(stderr, "message: %s\nexpected: %s\n", msg, want);
  assert_non_null(strstr(msg, want));
  dtm_error_clear(); /* the next error is its own */
}

static const double tet[12] = {0, 0, 0, 1e-3, 0, 0, 0, 1e-3, 0, 0, 0, 1e-3}; /* m */

/* The three errors in the unit system loaded with E and rho, each naming
 * its value as want[i] says. */
static void three_errors(const char *units, const char *e, const char *rho, const char *const want[3]) {
  dtm_elastic_moduli m;
  double lambda;
  load(units, e, rho);
  says(dtm_elastic_moduli_init(DTM_FORM_3D, -2.1e11, 0.3, 7850, &m), want[0]);
  says(dtm_elastic_moduli_init(DTM_FORM_3D, 2.1e11, 0.3, -7850, &m), want[1]);
  says(dtm_kernel_diffusion_lambda(DTM_TET4, -1e-6, tet, &lambda), want[2]);
}

static void test_mm(void **state) {
  (void)state;
  static const char *const want[3] = {"(got -210000 MPa)", "(got -7.85e-09 t/mm^3)", "(got -1 mm^2/s)"};
  three_errors("mm-t-s", "210000", "7.85e-9", want);
}

static void test_si(void **state) {
  (void)state;
  static const char *const want[3] = {"(got -2.1e+11 Pa)", "(got -7850 kg/m^3)", "(got -1e-06 m^2/s)"};
  three_errors("SI", "210e9", "7850", want);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_mm), cmocka_unit_test(test_si)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
