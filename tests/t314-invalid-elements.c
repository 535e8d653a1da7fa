/* dtmap's invalid-element policy end to end, through the CLI and the real
 * Gmsh reader, on two unit hexahedra sharing a face (tags 11 and 12, group
 * "rock"). Node 1 of hex 11 is moved to (a, a, a):
 *  - a = 0.4: inverted at that corner only, valid at every Gauss point
 *    (t111 derives the bounds). The run succeeds; stderr warns naming the
 *    element, its group, centroid and scaled Jacobian; the output mesh has
 *    the view "invalid elements" with that element alone and the value
 *    (1 - 3a)/((1-a)^2 + 2a^2)^(3/2); the report lists it with its group,
 *    centroid, worst node and value; its dt is finite and positive.
 *  - a = 0.6: inverted at a Gauss point: exit 2 naming element 11, its
 *    group and centroid, and no output written.
 *  - sweep warns about the flagged element at every size.
 * Tolerance 1e-12 relative on the scaled Jacobian: the closed form against
 * the kernel's value after a round trip through the report's and Gmsh's
 * text (17 significant digits). */
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

static void write_mesh(const char *path, double a) {
  char text[2048];
  snprintf(text, sizeof text,
           "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 1 \"rock\"\n$EndPhysicalNames\n"
           "$Nodes\n12\n1 %.17g %.17g %.17g\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n"
           "9 2 0 0\n10 2 1 0\n11 2 0 1\n12 2 1 1\n$EndNodes\n"
           "$Elements\n2\n11 5 2 1 1 1 2 3 4 5 6 7 8\n12 5 2 1 1 2 9 10 3 6 11 12 7\n$EndElements\n",
           a, a, a);
  tu_write(path, text);
}

static void write_scene(const char *path) {
  tu_write(path, "<dtmap-scene version=\"1\">\n  <mesh file=\"hexes.msh\"/>\n"
                 "  <material name=\"steel\" groups=\"rock\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                 "  <effects><elastic/></effects>\n</dtmap-scene>\n");
}

static double closed_form(double a) { return (1 - 3 * a) / pow((1 - a) * (1 - a) + 2 * a * a, 1.5); }

static void near(double got, double want, const char *what) {
  if (!(fabs(got - want) <= 1e-12 * fabs(want))) fail_msg("%s: got %.17g, want %.17g", what, got, want);
}

static void check_report(const char *path, double want) {
  cJSON *r = tu_json_load(path);
  assert_non_null(r);
  assert_true(tu_json_number(r, "invalid_elements.count") == 1);
  const cJSON *list = cJSON_GetObjectItem(cJSON_GetObjectItem(r, "invalid_elements"), "elements");
  const cJSON *e = cJSON_GetArrayItem(list, 0);
  assert_non_null(e);
  assert_true(tu_json_number(e, "element") == 11);
  assert_true(tu_json_number(e, "node") == 1);
  assert_string_equal(cJSON_GetObjectItem(e, "group")->valuestring, "rock");
  near(tu_json_number(e, "min_scaled_jacobian"), want, "report");
  near(cJSON_GetArrayItem(cJSON_GetObjectItem(e, "centroid"), 0)->valuedouble, (4 + 0.4) / 8, "centroid x");
  assert_true(tu_json_number(r, "mesh.elements") == 2);
  cJSON_Delete(r);
}

static void check_views(const char *out, double want) {
  int ierr = 0;
  tu_gmsh_begin();
  gmshOpen(out, &ierr);
  assert_int_equal(ierr, 0);
  tu_view v;
  assert_int_equal(tu_view_read("invalid elements", &v), 0);
  assert_string_equal(v.type, "ElementData");
  assert_int_equal(v.n, 1);
  assert_int_equal(v.tags[0], 11);
  near(v.values[0], want, "view");
  tu_view_free(&v);
  assert_int_equal(tu_view_read("dt", &v), 0);
  assert_int_equal(v.n, 2);
  for (size_t i = 0; i < v.n; i++) assert_true(isfinite(v.values[i]) && v.values[i] > 0);
  tu_view_free(&v);
  tu_gmsh_end();
}

static void test_corner_flagged(void **state) {
  (void)state;
  char msh[512], scene[512], out[512], rep[512], *log = NULL;
  snprintf(msh, sizeof msh, "%s/hexes.msh", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/hexes.xml", tu_tmpdir());
  snprintf(out, sizeof out, "%s/out.msh", tu_tmpdir());
  snprintf(rep, sizeof rep, "%s/out.json", tu_tmpdir());
  write_mesh(msh, 0.4);
  write_scene(scene);
  int code = tu_run(&log, "%s run %s -q -o %s --report %s", tu_cli(), scene, out, rep);
  if (code) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 0);
  assert_non_null(strstr(log, "warning: 1 element is inverted at a node"));
  assert_non_null(
      strstr(log, "element 11 (hex8) in group 'rock' at (0.55, 0.55, 0.55) m: smallest scaled Jacobian -0.357"));
  free(log);
  check_report(rep, closed_form(0.4));
  check_views(out, closed_form(0.4));
}

static void test_gauss_refused(void **state) {
  (void)state;
  char msh[512], scene[512], out[512], *log = NULL;
  snprintf(msh, sizeof msh, "%s/hexes.msh", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/hexes.xml", tu_tmpdir());
  snprintf(out, sizeof out, "%s/refused.msh", tu_tmpdir());
  write_mesh(msh, 0.6);
  write_scene(scene);
  int code = tu_run(&log, "%s run %s -q -o %s", tu_cli(), scene, out);
  assert_int_equal(code, 2);
  assert_non_null(strstr(log, "hexes.msh: 1 element cannot be analysed"));
  assert_non_null(strstr(log, "element 11 (hex8) in group 'rock' at (0.575, 0.575, 0.575) m: inverted or folded"));
  assert_false(tu_exists(out));
  free(log);
}

/* sweep warns too, per size, even with -q: a .geo that merges the mesh
 * (Gmsh keeps a merged mesh of discrete entities at every size). */
static void test_sweep_warns(void **state) {
  (void)state;
  char msh[512], geo[512], scene[512], csv[512], png[512], *log = NULL;
  snprintf(msh, sizeof msh, "%s/hexes.msh", tu_tmpdir());
  snprintf(geo, sizeof geo, "%s/hexes.geo", tu_tmpdir());
  snprintf(scene, sizeof scene, "%s/sweep.xml", tu_tmpdir());
  snprintf(csv, sizeof csv, "%s/sweep.csv", tu_tmpdir());
  snprintf(png, sizeof png, "%s/sweep.png", tu_tmpdir());
  write_mesh(msh, 0.4);
  tu_write(geo, "Merge \"hexes.msh\";\n");
  tu_write(scene, "<dtmap-scene version=\"1\">\n  <geometry file=\"hexes.geo\"/>\n"
                  "  <material name=\"steel\" groups=\"rock\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                  "  <effects><elastic/></effects>\n</dtmap-scene>\n");
  int code = tu_run(&log, "%s sweep %s -q --sizes 0.5,0.25 --csv %s --plot %s", tu_cli(), scene, csv, png);
  if (code) fprintf(stderr, "%s\n", log);
  assert_int_equal(code, 0);
  assert_non_null(strstr(log, "warning: at size 0.5 m, 1 element is inverted at a node"));
  assert_non_null(strstr(log, "warning: at size 0.25 m, 1 element is inverted at a node"));
  free(log);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_corner_flagged),
      cmocka_unit_test(test_gauss_refused),
      cmocka_unit_test(test_sweep_warns),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
