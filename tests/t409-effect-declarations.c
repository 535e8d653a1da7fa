/* Effects that describe themselves: every built-in class passes the
 * registration check and its declared ranges agree across effects; an
 * incomplete class is refused with "declares Y but has no Z"; a scene's
 * effect attributes are validated against the declarations (a misspelt
 * attribute, a value out of range or not among the choices, a missing
 * required one) at the scene's file:line, for the generic <effect name=...>
 * form too; a material property no effect declares is an error at the
 * material's line; the schema (generated from the declarations) keeps the
 * cohesive stiffness and the plugin in agreement; `dtmap effects` lists
 * each effect's attributes and properties. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/error.h"
#include "dtmap/registry.h"
#include "dtmap/scene.h"
#include "testutil.h"

static int step(void *s, const dtm_batch *b, double *dt, double *len) {
  (void)s, (void)b, (void)dt, (void)len;
  return DTM_OK;
}

static int factor(void *s, const dtm_material *m, double omega, double *f) {
  (void)s, (void)m, (void)omega;
  return *f = 1.0, DTM_OK;
}

static void expect_refused(const dtm_effect_class *c, const char *want) {
  dtm_error_clear();
  assert_int_equal(dtm_registry_check(c), DTM_ERR_INPUT);
  if (!strstr(dtm_error_message(), want)) fprintf(stderr, "got '%s'\n", dtm_error_message());
  assert_non_null(strstr(dtm_error_message(), want));
  dtm_error_clear();
}

static void registration(void **unused) {
  assert_int_equal(dtm_registry_check_all(), DTM_OK);
  for (int i = 0; i < dtm_registry_count(); i++) assert_int_equal(dtm_registry_check(dtm_registry_get(i)), DTM_OK);
  dtm_effect_class c = {.api_version = DTM_EFFECT_API_VERSION,
                        .name = "x",
                        .summary = "",
                        .role = DTM_ROLE_LIMITS,
                        .scheme = DTM_SCHEME_CENTRAL_DIFFERENCE,
                        .exponent = 1.0};
  expect_refused(&c, "effect 'x' declares DTM_ROLE_LIMITS but has no element_dt");
  c.element_dt = step, c.scheme = DTM_SCHEME_NONE;
  expect_refused(&c, "declares DTM_ROLE_LIMITS but has no time integration scheme");
  c.role = DTM_ROLE_MODIFIES_WAVES, c.element_dt = NULL;
  expect_refused(&c, "declares DTM_ROLE_MODIFIES_WAVES but has no wave_factor");
  c.wave_factor = factor, c.accuracy = (int (*)(void *, const dtm_batch *, double *, double *))step;
  expect_refused(&c, "declares accuracy() but has no indicator");
  static const dtm_param empty[] = {{"n", DTM_PARAM_NUMBER, NULL, 2, 1, 0, NULL, 0, "", ""},
                                    {NULL, 0, NULL, 0, 0, 0, NULL, 0, NULL, NULL}};
  c.accuracy = NULL, c.params = empty;
  expect_refused(&c, "declares parameter 'n' with an empty range");
  (void)unused;
}

/* Load a scene whose <effects> and first material are given, from memory,
 * next to a geometry file that exists. */
static int load(const char *material, const char *effects, dtm_scene **s) {
  char name[600], geo[600], text[4096];
  snprintf(geo, sizeof geo, "%s/sq.geo", tu_tmpdir());
  tu_write(geo, "// a geometry file must exist\n");
  snprintf(name, sizeof name, "%s/mem.xml", tu_tmpdir());
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n"                                       /* 1 */
           "  <geometry file=\"sq.geo\"/>\n"                                     /* 2 */
           "  <material name=\"rock\" E=\"1e9\" nu=\"0.25\" rho=\"2000\" %s/>\n" /* 3 */
           "  <effects>\n"                                                       /* 4 */
           "    %s\n"                                                            /* 5 */
           "  </effects>\n"                                                      /* 6 */
           "</dtmap-scene>\n",
           material, effects);
  dtm_error_clear();
  return dtm_scene_load_memory(text, strlen(text), name, s);
}

static void expect_scene_error(const char *material, const char *effects, int line, const char *want) {
  dtm_scene *s = NULL;
  char where[700];
  snprintf(where, sizeof where, "%s/mem.xml:%d: ", tu_tmpdir(), line);
  int r = load(material, effects, &s);
  if (r != DTM_ERR_INPUT || !strstr(dtm_error_message(), where) || !strstr(dtm_error_message(), want))
    fprintf(stderr, "%s %s: rc %d, got '%s'\n", material, effects, r, dtm_error_message());
  assert_int_equal(r, DTM_ERR_INPUT);
  assert_null(s);
  assert_non_null(strstr(dtm_error_message(), where));
  assert_non_null(strstr(dtm_error_message(), want));
  dtm_error_clear();
}

static void attributes(void **unused) {
  dtm_scene *s = NULL;
  assert_int_equal(load("", "<effect name=\"elastic\" length=\"min-edge\"/><damping xi=\"0.1\"/>", &s), DTM_OK);
  dtm_scene_destroy(&s);
  expect_scene_error("", "<effect name=\"elastic\" lenght=\"min-edge\"/>", 5,
                     "effect 'elastic': unknown attribute 'lenght' (elastic takes: formulation, length, integration)");
  expect_scene_error("", "<effect name=\"elastic\" length=\"edge\"/>", 5,
                     "length=\"edge\" is not one of: eigen, safe, min-edge, min-altitude, inradius, volume-area");
  expect_scene_error("", "<effect name=\"damping\" xi=\"-1\"/>", 5, "xi = -1 is not admissible (need xi >= 0)");
  expect_scene_error("", "<effect name=\"damping\" xi=\"abc\"/>", 5, "xi=\"abc\" is not a number");
  expect_scene_error("", "<effect name=\"cohesive\"/>", 5, "effect 'cohesive' needs groups=");
  expect_scene_error("", "<effect name=\"plastic\"/>", 5, "unknown effect 'plastic'; known effects: elastic");
  /* the element form is checked by the generated schema */
  expect_scene_error("", "<elastic lenght=\"min-edge\"/>", 5, "schema: ");
  /* stiffness must be > 0 (absent: the 1/30 rule); schema and plugin agree */
  expect_scene_error("", "<cohesive groups=\"rock\" stiffness=\"0\"/>", 5, "schema: ");
  expect_scene_error("", "<effect name=\"cohesive\" groups=\"rock\" stiffness=\"0\"/>", 5,
                     "stiffness = 0 is not admissible (need stiffness > 0)");
  (void)unused;
}

static void properties(void **unused) {
  expect_scene_error("condutivity=\"3\"", "<elastic/>", 3,
                     "material 'rock': no effect declares the property 'condutivity' (known: E, nu, rho");
  expect_scene_error("storage=\"0\"", "<elastic/>", 3, "storage = 0 is not admissible (need storage > 0)");
  dtm_scene *s = NULL; /* a property only an external effect could declare waits until it is loaded */
  assert_int_equal(load("speedup=\"2\"", "<effect name=\"x\" library=\"libx.so\"/>", &s), DTM_OK);
  assert_float_equal(dtm_material_value(&s->materials[0].m, "speedup"), 2.0, 0);
  assert_int_equal(dtm_scene_check_properties(s, NULL, 0), DTM_OK);
  dtm_scene_destroy(&s);
  (void)unused;
}

static void listing(void **unused) {
  char *out = NULL;
  assert_int_equal(tu_run(&out, "%s effects", tu_cli()), 0);
  static const char *const want[] = {"elastic:",          "length",       "eigen|safe|min-edge",
                                     "heat-capacity",     "J/(kg K)",     "cohesive zone resolution",
                                     "elements-per-zone", "forward Euler"};
  for (size_t i = 0; i < sizeof want / sizeof *want; i++) {
    if (!strstr(out, want[i])) fprintf(stderr, "missing '%s' in:\n%s\n", want[i], out);
    assert_non_null(strstr(out, want[i]));
  }
  free(out);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(registration), cmocka_unit_test(attributes),
                                     cmocka_unit_test(properties), cmocka_unit_test(listing)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
