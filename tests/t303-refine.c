/* `dtmap refine` on two bundled geometries: the target is met within the
 * round budget (round 0 plus at most 3 remeshes), the kept mesh carries
 * all the views, and the report lists the rounds and which one is kept. For the box, whose scene
 * mesh is uniform, the refined mesh is compared with the ideal uniform mesh
 * at the target: N_ideal = N_0 (R_0 / target)^3 (dt scales linearly with the
 * size, the count with its cube), and the refined count must be at most
 * 1.3 N_ideal (the goal). */
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

static cJSON *refine(const char *geo, const char *target, int *code) {
  char out[512], rep[512], *log = NULL;
  snprintf(out, sizeof out, "%s/%s_refined.msh", tu_tmpdir(), geo);
  snprintf(rep, sizeof rep, "%s/%s_refined.json", tu_tmpdir(), geo);
  *code = tu_run(&log, "%s refine %s/geometries/%s.xml --target %s --max-iter 3 -o %s --report %s", tu_cli(), tu_src(),
                 geo, target, out, rep);
  if (*code) fprintf(stderr, "%s\n", log);
  free(log);
  return tu_json_load(rep);
}

static void check_met(const cJSON *j, double target) {
  const cJSON *rounds = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "rounds");
  assert_non_null(rounds);
  int n = cJSON_GetArraySize(rounds), best = (int)tu_json_number(j, "refine.best");
  assert_true(n >= 1 && n <= 4);
  assert_true(best >= 0 && best < n);
  assert_true(tu_json_number(j, "dt.recommended") >= target);
  const cJSON *kept = cJSON_GetArrayItem(rounds, best);
  assert_true(cJSON_GetObjectItem(kept, "recommended")->valuedouble == tu_json_number(j, "dt.recommended"));
}

static void views_present(const char *geo) {
  static const char *const names[] = {"dt", "characteristic length", "limiting effect", "size suggestion", "nodal dt"};
  char out[512];
  int ierr = 0;
  snprintf(out, sizeof out, "%s/%s_refined.msh", tu_tmpdir(), geo);
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  for (int i = 0; i < 5; i++) {
    tu_view v;
    assert_int_equal(tu_view_read(names[i], &v), 0);
    tu_view_free(&v);
  }
  gmshClear(&ierr);
}

static void box(void **unused) {
  int code;
  const double target = 4e-7;
  cJSON *j = refine("box", "4e-7", &code);
  assert_int_equal(code, 0);
  check_met(j, target);
  const cJSON *r0 = cJSON_GetArrayItem(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "refine"), "rounds"), 0);
  double n0 = cJSON_GetObjectItem(r0, "elements")->valuedouble,
         rec0 = cJSON_GetObjectItem(r0, "recommended")->valuedouble;
  double ideal = n0 * pow(rec0 / target, 3), n = tu_json_number(j, "mesh.elements");
  fprintf(stderr, "box: %g elements, ideal uniform %g, ratio %.2f\n", n, ideal, n / ideal);
  assert_true(n <= 1.3 * ideal);
  views_present("box");
  cJSON_Delete(j);
  (void)unused;
}

static void plate(void **unused) {
  int code;
  cJSON *j = refine("plate_with_hole", "3e-7", &code);
  assert_int_equal(code, 0);
  check_met(j, 3e-7);
  views_present("plate_with_hole");
  cJSON_Delete(j);
  (void)unused;
}

/* An unreachable target (the elements would have to be larger than the
 * plate) ends with exit 1 and says so. */
static void unreachable(void **unused) {
  int code;
  cJSON *j = refine("plate_with_hole", "1e-3", &code);
  assert_int_equal(code, 1);
  cJSON_Delete(j);
  (void)unused;
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  const struct CMUnitTest tests[] = {cmocka_unit_test(box), cmocka_unit_test(plate), cmocka_unit_test(unreachable)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  tu_gmsh_end();
  return r;
}
