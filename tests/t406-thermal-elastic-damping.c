/* elastic + damping + thermal on the bundled Brazilian disc: per element,
 * "limiting effect" is the index of the smaller of "dt elastic" and
 * "dt thermal", "dt" is that minimum, and damping (a modifier) never limits.
 * The steel is given an artificially high diffusivity so that both effects
 * limit somewhere. Run twice, with and without damping, "dt elastic" must
 * shrink by exactly sqrt(1+xi^2)-xi everywhere (constant xi). */
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

#include "testutil.h"

#define XI 0.2

static void run(const char *name, const char *damping) {
  char scene[600], text[4096], *log = NULL;
  snprintf(scene, sizeof scene, "%s/%s.xml", tu_tmpdir(), name);
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n"
           "<geometry file=\"%s/geometries/brazilian_disc.geo\"/>\n"
           "<meshing size=\"2e-3\" min-size=\"5e-4\" dim=\"2\"/>\n"
           "<material name=\"granite\" groups=\"rock\" E=\"60e9\" nu=\"0.25\" rho=\"2700\" conductivity=\"3\" "
           "heat-capacity=\"790\"/>\n"
           "<material name=\"steel\" groups=\"platen_top platen_bottom\" E=\"210e9\" nu=\"0.3\" rho=\"7850\" "
           "conductivity=\"2e7\" heat-capacity=\"500\"/>\n"
           "<effects><elastic formulation=\"plane-strain\"/>%s<thermal/></effects>\n</dtmap-scene>\n",
           tu_src(), damping);
  tu_write(scene, text);
  int code = tu_run(&log, "%s run %s -q -o %s/%s.msh --report %s/%s.json", tu_cli(), scene, tu_tmpdir(), name,
                    tu_tmpdir(), name);
  if (code) fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
}

static void read_views(const char *name, tu_view *v) {
  static const char *const names[] = {"dt", "limiting effect", "dt elastic", "dt thermal"};
  char out[600];
  int ierr = 0;
  snprintf(out, sizeof out, "%s/%s.msh", tu_tmpdir(), name);
  gmshClear(&ierr);
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  for (int i = 0; i < 4; i++) assert_int_equal(tu_view_read(names[i], &v[i]), 0);
  for (int i = 1; i < 4; i++) assert_int_equal(v[i].n, v[0].n);
}

static void limiting_matches_views(void **unused) {
  tu_view v[4];
  run("damped", "<damping xi=\"0.2\"/>");
  read_views("damped", v);
  size_t by[3] = {0, 0, 0};
  for (size_t i = 0; i < v[0].n; i++) {
    double el = v[2].values[i], th = v[3].values[i];
    int lim = (int)v[1].values[i];
    assert_true(lim == 0 || lim == 2); /* index 1 is damping, a modifier */
    assert_int_equal(lim, el <= th ? 0 : 2);
    assert_true(v[0].values[i] == fmin(el, th)); /* the same doubles, copied */
    by[lim]++;
  }
  assert_true(by[0] > 0 && by[2] > 0); /* both effects limit somewhere */
  char rep[600];
  snprintf(rep, sizeof rep, "%s/damped.json", tu_tmpdir());
  cJSON *j = tu_json_load(rep);
  const cJSON *mins = cJSON_GetObjectItem(j, "effect_minima");
  double min_el = INFINITY, min_th = INFINITY;
  for (size_t i = 0; i < v[0].n; i++) min_el = fmin(min_el, v[2].values[i]), min_th = fmin(min_th, v[3].values[i]);
  assert_true(fabs(cJSON_GetObjectItem(cJSON_GetArrayItem(mins, 0), "min")->valuedouble - min_el) <= 1e-15 * min_el);
  assert_true(fabs(cJSON_GetObjectItem(cJSON_GetArrayItem(mins, 2), "min")->valuedouble - min_th) <= 1e-15 * min_th);
  cJSON_Delete(j);
  for (int i = 0; i < 4; i++) tu_view_free(&v[i]);
  (void)unused;
}

/* Same mesh (same geometry and options, Gmsh is deterministic here), with
 * and without damping: the ratio is the closed-form factor to 1e-13
 * (a few roundings in the damped path). */
static void damping_factor_applied(void **unused) {
  tu_view d[4], u[4];
  run("undamped", "");
  read_views("damped", d);
  read_views("undamped", u);
  const double f = sqrt(1 + XI * XI) - XI;
  for (size_t i = 0; i < d[0].n; i++) {
    assert_int_equal(d[2].tags[i], u[2].tags[i]);
    assert_true(fabs(d[2].values[i] - f * u[2].values[i]) <= 1e-13 * d[2].values[i]);
    assert_true(d[3].values[i] == u[3].values[i]); /* damping leaves diffusion alone */
  }
  for (int i = 0; i < 4; i++) tu_view_free(&d[i]), tu_view_free(&u[i]);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(limiting_matches_views),
                                     cmocka_unit_test(damping_factor_applied)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  tu_gmsh_end();
  return r;
}
