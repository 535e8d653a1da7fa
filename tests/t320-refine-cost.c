/* `dtmap refine` never makes the run more expensive. On the bundled plate,
 * disc and notched beam, with a target 1.3 x the recommended step `run`
 * reports: the target is met within 3 rounds, or (where a thin or sharp
 * feature limits the step) the report names its causes and refine exits
 * 1; either way the element-steps of the kept mesh
 * (cost.element_steps, for the scene's duration) are at most the input's
 * (refine.rounds[0].element_steps), and the report's cost is that of the
 * kept round. Also: refine's default outputs never overwrite what `run`
 * wrote for the same scene, and the target comes from the scene's
 * <time target> when --target is absent. Last, where an accuracy bound
 * forces smaller elements (the plate with f-max 3e5 Hz: h <= C_S/(10 f) =
 * 1.04 mm, below its 5 mm bulk), refine says which bound and how many
 * elements it asks for, warns that the target is forbidden, exits 1 and
 * keeps a mesh no dearer than the input. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "testutil.h"

static double recommended(const char *geo) {
  char rep[512], *log = NULL;
  snprintf(rep, sizeof rep, "%s/%s_run.json", tu_tmpdir(), geo);
  int code = tu_run(&log, "%s run %s/geometries/%s.xml -o %s/%s_run.msh --report %s -q", tu_cli(), tu_src(), geo,
                    tu_tmpdir(), geo, rep);
  if (code) fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
  cJSON *j = tu_json_load(rep);
  double r = tu_json_number(j, "dt.recommended");
  cJSON_Delete(j);
  return r;
}

static void refine_cheaper(const char *geo) {
  char out[512], rep[512], *log = NULL;
  double target = 1.3 * recommended(geo);
  snprintf(out, sizeof out, "%s/%s_refined.msh", tu_tmpdir(), geo);
  snprintf(rep, sizeof rep, "%s/%s_refined.json", tu_tmpdir(), geo);
  int code = tu_run(&log, "%s refine %s/geometries/%s.xml --target %.17g --max-iter 3 -o %s --report %s", tu_cli(),
                    tu_src(), geo, target, out, rep);
  fprintf(stderr, "%s\n", log);
  free(log);
  cJSON *j = tu_json_load(rep);
  assert_non_null(j);
  const cJSON *rounds = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "rounds");
  int n = cJSON_GetArraySize(rounds), best = (int)tu_json_number(j, "refine.best");
  double input = cJSON_GetObjectItem(cJSON_GetArrayItem(rounds, 0), "element_steps")->valuedouble;
  double kept = tu_json_number(j, "cost.element_steps");
  assert_true(n >= 1 && n <= 4);
  assert_true(kept == cJSON_GetObjectItem(cJSON_GetArrayItem(rounds, best), "element_steps")->valuedouble);
  assert_true(kept <= input);
  if (code == 0) {
    assert_true(tu_json_number(j, "dt.recommended") >= target);
  } else {
    assert_int_equal(code, 1);
    assert_true(cJSON_GetArraySize(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "causes")) > 0);
  }
  fprintf(stderr, "%s: target %.4e, exit %d, %d round(s), element-steps %.4g -> %.4g\n", geo, target, code, n - 1,
          input, kept);
  cJSON_Delete(j);
}

static void plate(void **unused) {
  refine_cheaper("plate_with_hole");
  (void)unused;
}

static void disc(void **unused) {
  refine_cheaper("brazilian_disc");
  (void)unused;
}

static void beam(void **unused) {
  refine_cheaper("notched_beam");
  (void)unused;
}

/* A scene with <output mesh report> and a <time target>: run writes its
 * files, refine without -o, --report or --target writes X_refined.* beside
 * them for the scene's target and leaves run's files as they were. */
static void defaults(void **unused) {
  char scene[512], dt[512], js[512], rdt[512], rjs[512], *log = NULL, text[2048];
  snprintf(scene, sizeof scene, "%s/plate.xml", tu_tmpdir());
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n  <geometry file=\"%s/geometries/plate_with_hole.geo\"/>\n"
           "  <meshing size=\"5e-3\" min-size=\"1e-3\" dim=\"2\"/>\n"
           "  <material name=\"aluminium\" groups=\"plate\" E=\"70e9\" nu=\"0.33\" rho=\"2700\"/>\n"
           "  <effects>\n    <elastic formulation=\"plane-stress\"/>\n  </effects>\n"
           "  <time target=\"1e-7\" duration=\"1e-4\"/>\n"
           "  <output mesh=\"plate_dt.msh\" report=\"plate_dt.json\"/>\n</dtmap-scene>\n",
           tu_src());
  tu_write(scene, text);
  snprintf(dt, sizeof dt, "%s/plate_dt.msh", tu_tmpdir());
  snprintf(js, sizeof js, "%s/plate_dt.json", tu_tmpdir());
  snprintf(rdt, sizeof rdt, "%s/plate_dt_refined.msh", tu_tmpdir());
  snprintf(rjs, sizeof rjs, "%s/plate_dt_refined.json", tu_tmpdir());
  assert_int_equal(tu_run(&log, "%s run %s -q", tu_cli(), scene), 0);
  free(log);
  size_t n0, n1, m0, m1;
  char *before = tu_slurp(dt, &n0), *jbefore = tu_slurp(js, &m0);
  int code = tu_run(&log, "%s refine %s -q", tu_cli(), scene);
  free(log);
  assert_true(code == 0 || code == 1);
  assert_true(tu_exists(rdt) && tu_exists(rjs));
  char *after = tu_slurp(dt, &n1), *jafter = tu_slurp(js, &m1);
  assert_true(n0 == n1 && !memcmp(before, after, n0));
  assert_true(m0 == m1 && !memcmp(jbefore, jafter, m0));
  cJSON *j = tu_json_load(rjs);
  assert_true(tu_json_number(j, "refine.target") == 1e-7);
  cJSON_Delete(j);
  free(before), free(after), free(jbefore), free(jafter);
  (void)unused;
}

static int has_warning(const cJSON *j, const char *text) {
  const cJSON *w;
  cJSON_ArrayForEach(w, cJSON_GetObjectItem(j, "warnings")) if (strstr(w->valuestring, text)) return 1;
  return 0;
}

static void forced(void **unused) {
  char scene[512], rep[512], text[2048], *log = NULL;
  snprintf(scene, sizeof scene, "%s/plate_fmax.xml", tu_tmpdir());
  snprintf(rep, sizeof rep, "%s/plate_fmax.json", tu_tmpdir());
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n  <geometry file=\"%s/geometries/plate_with_hole.geo\"/>\n"
           "  <meshing size=\"5e-3\" min-size=\"1e-3\" dim=\"2\"/>\n"
           "  <material name=\"aluminium\" groups=\"plate\" E=\"70e9\" nu=\"0.33\" rho=\"2700\"/>\n"
           "  <effects>\n    <elastic formulation=\"plane-stress\"/>\n  </effects>\n"
           "  <time duration=\"1e-4\" f-max=\"3e5\"/>\n</dtmap-scene>\n",
           tu_src());
  tu_write(scene, text);
  int code = tu_run(&log, "%s refine %s --target 1.07e-7 --max-iter 2 -o %s/pf.msh --report %s", tu_cli(), scene,
                    tu_tmpdir(), rep);
  assert_non_null(strstr(log, "accuracy: the bound 'elements per wavelength' asks for about"));
  free(log);
  assert_int_equal(code, 1);
  cJSON *j = tu_json_load(rep);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "accuracy_bound")->valuestring,
                      "elements per wavelength");
  assert_true(tu_json_number(j, "refine.accuracy_elements") > 0);
  assert_true(has_warning(j, "forbidden by the accuracy bound 'elements per wavelength'"));
  const cJSON *rounds = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "rounds");
  assert_true(tu_json_number(j, "cost.element_steps") <=
              cJSON_GetObjectItem(cJSON_GetArrayItem(rounds, 0), "element_steps")->valuedouble);
  cJSON_Delete(j);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(plate), cmocka_unit_test(disc), cmocka_unit_test(beam),
                                     cmocka_unit_test(defaults), cmocka_unit_test(forced)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
