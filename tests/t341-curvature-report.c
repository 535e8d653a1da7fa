/* The curvature of second-order elements end to end: a disc of radius 1
 * meshed by Gmsh at order 2 (its boundary triangles are curved, the
 * interior ones straight-sided) run through the CLI. The report's
 * "curvature" block counts every tri6 as second order, some but not all
 * as curved, gives a worst jacobian ratio in (0, 1) and names its element,
 * and says the steps are for the converged integration; the output mesh
 * has the view "curvature" with one value per element, 1 (to 1e-12: a
 * constant det J) on the straight-sided ones and below 1 on the others,
 * as many below 1 as the report counts curved. The scene's
 * integration="full" makes the report say so. */
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

static void write_inputs(const char *extra) {
  char path[512], text[1024];
  snprintf(path, sizeof path, "%s/disc.geo", tu_tmpdir());
  tu_write(path, "SetFactory(\"OpenCASCADE\");\nDisk(1) = {0, 0, 0, 1};\nPhysical Surface(\"disc\") = {1};\n");
  snprintf(path, sizeof path, "%s/disc.xml", tu_tmpdir());
  snprintf(text, sizeof text,
           "<dtmap-scene version=\"1\">\n  <geometry file=\"disc.geo\"/>\n"
           "  <meshing size=\"0.35\" order=\"2\" dim=\"2\"/>\n"
           "  <material name=\"steel\" groups=\"disc\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
           "  <effects><elastic%s/></effects>\n</dtmap-scene>\n",
           extra);
  tu_write(path, text);
}

static cJSON *run(const char *extra, char *out, char *rep) {
  char scene[512], *log = NULL;
  write_inputs(extra);
  snprintf(scene, sizeof scene, "%s/disc.xml", tu_tmpdir());
  snprintf(out, 512, "%s/disc-out.msh", tu_tmpdir());
  snprintf(rep, 512, "%s/disc.json", tu_tmpdir());
  int code = tu_run(&log, "%s run %s -q -o %s --report %s", tu_cli(), scene, out, rep);
  if (code) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 0);
  free(log);
  cJSON *r = tu_json_load(rep);
  assert_non_null(r);
  return r;
}

static void test_converged(void **state) {
  (void)state;
  char out[512], rep[512];
  cJSON *r = run("", out, rep);
  double nel = tu_json_number(r, "mesh.elements"), curved = tu_json_number(r, "curvature.curved");
  double worst = tu_json_number(r, "curvature.worst_jacobian_ratio");
  assert_true(tu_json_number(r, "curvature.second_order") == nel);
  assert_true(curved > 0 && curved < nel);
  assert_true(worst > 0 && worst < 1);
  assert_true(tu_json_number(r, "curvature.worst.element") > 0);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(r, "curvature"), "integration")->valuestring,
                      "converged");
  print_message("%g of %g tri6 curved, worst ratio %.4f, max rule dependence %.3g, rule sensitive %g\n", curved, nel,
                worst, tu_json_number(r, "curvature.max_rule_dependence"),
                tu_json_number(r, "curvature.rule_sensitive"));
  int ierr = 0;
  tu_gmsh_begin();
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  tu_view v;
  assert_int_equal(tu_view_read("curvature", &v), 0);
  assert_int_equal((double)v.n, nel);
  size_t below = 0;
  double lo = 1;
  for (size_t i = 0; i < v.n; i++) {
    assert_true(v.values[i] > 0 && v.values[i] <= 1 + 1e-12);
    below += v.values[i] < 1 - 1e-12;
    lo = fmin(lo, v.values[i]);
  }
  assert_true((double)below == curved);
  assert_true(fabs(lo - worst) <= 1e-12);
  tu_view_free(&v);
  tu_gmsh_end();
  cJSON_Delete(r);
}

static void test_full(void **state) {
  (void)state;
  char out[512], rep[512];
  cJSON *r = run(" integration=\"full\"", out, rep);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(r, "curvature"), "integration")->valuestring, "full");
  cJSON_Delete(r);
}

/* One tri6 (tag 3) of the unit right triangle with the middle of edge 0-1
 * moved to (0.5, -0.12): y = v - 0.48 u (1 - u - v), so det J = 1 + 0.48 u
 * and min/max over the element = 1/1.48 (det J is linear: the Bernstein
 * bound is exact), node offset 0.12. Its step moves by 2.4e-3 between the
 * rules: one rule-sensitive element, warned on stderr and in the report. */
static void test_warning(void **state) {
  (void)state;
  char path[512], scene[512], rep[512], out[512], *log = NULL;
  snprintf(path, sizeof path, "%s/one.msh", tu_tmpdir());
  tu_write(path, "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"plate\"\n$EndPhysicalNames\n"
                 "$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0.5 -0.12 0\n5 0.5 0.5 0\n6 0 0.5 0\n$EndNodes\n"
                 "$Elements\n1\n3 9 2 1 1 1 2 3 4 5 6\n$EndElements\n");
  snprintf(scene, sizeof scene, "%s/one.xml", tu_tmpdir());
  tu_write(scene, "<dtmap-scene version=\"1\">\n  <mesh file=\"one.msh\"/>\n"
                  "  <material name=\"steel\" groups=\"plate\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                  "  <effects><elastic/></effects>\n</dtmap-scene>\n");
  snprintf(rep, sizeof rep, "%s/one.json", tu_tmpdir());
  snprintf(out, sizeof out, "%s/one-out.msh", tu_tmpdir());
  assert_int_equal(tu_run(&log, "%s run %s -q -o %s --report %s", tu_cli(), scene, out, rep), 0);
  assert_non_null(strstr(log, "warning: 1 curved element has a step that changes by more than 1e-3"));
  free(log);
  cJSON *r = tu_json_load(rep);
  assert_true(fabs(tu_json_number(r, "curvature.worst_jacobian_ratio") - 1 / 1.48) <= 1e-12);
  assert_true(fabs(tu_json_number(r, "curvature.max_node_offset") - 0.12) <= 1e-12);
  assert_true(tu_json_number(r, "curvature.rule_sensitive") == 1);
  assert_true(tu_json_number(r, "curvature.worst.element") == 3);
  assert_non_null(strstr(cJSON_GetArrayItem(cJSON_GetObjectItem(r, "warnings"), 0)->valuestring, "integration rule"));
  cJSON_Delete(r);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_converged),
      cmocka_unit_test(test_full),
      cmocka_unit_test(test_warning),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
