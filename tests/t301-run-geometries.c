/* Real Gmsh runs of `dtmap run` on every bundled geometry: the output .msh
 * re-opens in Gmsh with the contract views under their exact names, value
 * counts match the element and node counts, and the report agrees with the
 * views (dt.element holds the smallest dt; dt.recommended = safety x dt.min). */
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

static const char *const scenes[] = {"brazilian_disc", "notched_beam", "box", "plate_with_hole"};

/* Elements of dimension dim in the opened model. */
static size_t count_elements(int dim) {
  int *types = NULL, ierr = 0;
  size_t nt = 0, **et = NULL, *etn = NULL, etnn = 0, **nt_ = NULL, *ntn = NULL, ntnn = 0, total = 0;
  gmshModelMeshGetElements(&types, &nt, &et, &etn, &etnn, &nt_, &ntn, &ntnn, dim, -1, &ierr);
  for (size_t i = 0; i < nt; i++) total += etn[i], gmshFree(et[i]), gmshFree(nt_[i]);
  gmshFree(types), gmshFree(et), gmshFree(etn), gmshFree(nt_), gmshFree(ntn);
  return total;
}

static void check_views(const cJSON *rep, size_t nel, size_t nnodes) {
  static const char *const names[] = {"dt", "characteristic length", "limiting effect", "dt elastic"};
  for (int i = 0; i < 4; i++) {
    tu_view v;
    assert_int_equal(tu_view_read(names[i], &v), 0);
    assert_string_equal(v.type, "ElementData");
    assert_int_equal(v.n, nel);
    for (size_t k = 0; k < v.n; k++) assert_true(isfinite(v.values[k]) && v.values[k] >= 0);
    tu_view_free(&v);
  }
  tu_view s;
  assert_int_equal(tu_view_read("size suggestion", &s), 0);
  assert_string_equal(s.type, "NodeData");
  assert_int_equal(s.n, nnodes);
  for (size_t k = 0; k < s.n; k++) assert_true(s.values[k] > 0);
  tu_view_free(&s);
  (void)rep;
}

/* The report's dt.element is the element with the smallest "dt" value;
 * dt.nodal is the smallest "nodal dt" and is never below dt.min (it is a
 * bound on the same spectrum, tighter by construction); dt.recommended =
 * safety x dt.nodal, the best guaranteed-safe estimate without --posterior.
 * Tolerance 1e-14 relative: cJSON prints doubles with 17 significant
 * digits, so only the last bit can differ. */
static void check_report_against_dt(const cJSON *rep) {
  tu_view v;
  assert_int_equal(tu_view_read("dt", &v), 0);
  size_t imin = 0;
  for (size_t k = 1; k < v.n; k++)
    if (v.values[k] < v.values[imin]) imin = k;
  double dtmin = tu_json_number(rep, "dt.min"), safety = tu_json_number(rep, "dt.safety");
  assert_int_equal((size_t)tu_json_number(rep, "dt.element"), v.tags[imin]);
  assert_true(fabs(dtmin - v.values[imin]) <= 1e-14 * dtmin);
  assert_true(safety > 0 && safety <= 1);
  tu_view_free(&v);
  tu_view nd;
  assert_int_equal(tu_view_read("nodal dt", &nd), 0);
  assert_string_equal(nd.type, "NodeData");
  double nmin = INFINITY;
  for (size_t k = 0; k < nd.n; k++) nmin = fmin(nmin, nd.values[k]);
  tu_view_free(&nd);
  double nodal = tu_json_number(rep, "dt.nodal");
  assert_true(fabs(nodal - nmin) <= 1e-14 * nodal);
  assert_true(nodal >= dtmin);
  assert_true(fabs(tu_json_number(rep, "dt.recommended") - safety * nodal) <= 1e-14 * nodal);
}

static void run_scene(void **state) {
  const char *name = *state;
  char out[512], rep[512], opt[600];
  snprintf(out, sizeof out, "%s/%s.msh", tu_tmpdir(), name);
  snprintf(rep, sizeof rep, "%s/%s.json", tu_tmpdir(), name);
  snprintf(opt, sizeof opt, "%s.opt", out);
  char *log = NULL;
  int code = tu_run(&log, "%s run %s/geometries/%s.xml -q -o %s --report %s", tu_cli(), tu_src(), name, out, rep);
  if (code) fprintf(stderr, "%s\n", log);
  free(log);
  assert_int_equal(code, 0);
  assert_true(tu_exists(opt));
  cJSON *j = tu_json_load(rep);
  assert_non_null(j);
  size_t nel = (size_t)tu_json_number(j, "mesh.elements"), nn = (size_t)tu_json_number(j, "mesh.nodes");
  int dim = (int)tu_json_number(j, "mesh.dim"), ierr = 0;
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  assert_int_equal(count_elements(dim), nel);
  check_views(j, nel, nn);
  check_report_against_dt(j);
  gmshClear(&ierr);
  cJSON_Delete(j);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  tu_gmsh_begin();
  struct CMUnitTest tests[4];
  for (int i = 0; i < 4; i++) tests[i] = (struct CMUnitTest){scenes[i], run_scene, NULL, NULL, (void *)scenes[i]};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  tu_gmsh_end();
  return r;
}
