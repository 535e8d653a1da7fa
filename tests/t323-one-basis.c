/* One basis for every number. On every bundled scene, the report's cost,
 * subcycling and verify all use dt.recommended: cost.basis and
 * subcycling.basis are dt.recommended exactly, cost.steps is
 * ceil(duration / dt.recommended), the ideal speed-up is >= 1 and the
 * subcycled cost never exceeds the plain one; the terminal labels the
 * element-bound minimum as the map's own minimum, next to the recommended
 * step and its basis. `dtmap verify` with no step option verifies exactly
 * `run`'s dt.recommended (and with --posterior exactly run --posterior's);
 * its report has the step, the steps run, the growth and the verdict. */
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

static cJSON *run(const char *geo, const char *extra, char **log) {
  char rep[512];
  snprintf(rep, sizeof rep, "%s/%s_basis.json", tu_tmpdir(), geo);
  int code = tu_run(log, "%s run %s/geometries/%s.xml -o %s/%s_basis.msh --report %s %s", tu_cli(), tu_src(), geo,
                    tu_tmpdir(), geo, rep, extra);
  if (code) fprintf(stderr, "%s\n", *log);
  assert_int_equal(code, 0);
  return tu_json_load(rep);
}

static void scene_basis(const char *geo) {
  char *log = NULL;
  cJSON *j = run(geo, "", &log);
  double rec = tu_json_number(j, "dt.recommended"), d = tu_json_number(j, "cost.duration");
  double plain = tu_json_number(j, "cost.element_steps"), sub = tu_json_number(j, "cost.element_steps_subcycled");
  assert_true(tu_json_number(j, "cost.basis") == rec);
  assert_true(tu_json_number(j, "subcycling.basis") == rec);
  assert_true(tu_json_number(j, "cost.steps") == ceil(d / rec));
  assert_true(tu_json_number(j, "subcycling.speedup") >= 1.0);
  assert_true(sub <= plain);
  assert_true(tu_json_number(j, "mesh.elements") * ceil(d / rec) == plain);
  assert_non_null(strstr(log, "the dt map's own minimum (a bound, not the step)"));
  assert_non_null(strstr(log, "(nodal bound): the step"));
  fprintf(stderr, "%s: speed-up %.3f, element-steps %.4g, subcycled %.4g\n", geo,
          tu_json_number(j, "subcycling.speedup"), plain, sub);
  free(log);
  cJSON_Delete(j);
}

static void bundled(void **unused) {
  static const char *const geos[] = {"box", "brazilian_disc", "notched_beam", "plate_with_hole"};
  for (int i = 0; i < 4; i++) scene_basis(geos[i]);
  (void)unused;
}

static void verify_step(const char *extra) {
  char *log = NULL, vrep[512];
  cJSON *r = run("brazilian_disc", extra, &log);
  free(log);
  snprintf(vrep, sizeof vrep, "%s/disc_verify.json", tu_tmpdir());
  int code = tu_run(&log, "%s verify %s/geometries/brazilian_disc.xml --steps 300 --report %s %s", tu_cli(), tu_src(),
                    vrep, extra);
  if (code) fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
  cJSON *v = tu_json_load(vrep);
  assert_true(tu_json_number(v, "step") == tu_json_number(r, "dt.recommended"));
  assert_true(tu_json_number(v, "factor") == 1.0);
  assert_true(tu_json_number(v, "steps") == 300);
  assert_true(tu_json_number(v, "growth") >= 0);
  assert_string_equal(cJSON_GetObjectItem(v, "verdict")->valuestring, "stable");
  assert_string_equal(cJSON_GetObjectItem(v, "basis")->valuestring,
                      cJSON_GetObjectItem(cJSON_GetObjectItem(r, "dt"), "basis")->valuestring);
  cJSON_Delete(v);
  cJSON_Delete(r);
}

static void verify_default(void **unused) {
  verify_step("");
  verify_step("--posterior");
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(bundled), cmocka_unit_test(verify_default)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
