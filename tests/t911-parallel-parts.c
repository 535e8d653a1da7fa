/* The distributed run against the serial one, on a real mesh: Gmsh meshes
 * the bundled box (tets) and splits it with METIS into 4 part files
 * (Gmsh's API, in this process); `mpirun -n 4 dtmap run` reads the parts
 * (<mesh partitions="4">), `dtmap run` the whole mesh. Every element view
 * of the parts, merged by Gmsh as a user opens them, is bit-identical to
 * the serial one element by element; the node views (sums over the parts'
 * elements in another order) agree to 1e-14, and so do the element views
 * that read them (each element's own safe step below the target, the mass
 * the nodes add); the report's figures are the
 * serial ones; the global estimate (SLEPc on the distributed operator)
 * agrees with the serial Lanczos within 1e-6 and stays on its safe side.
 * The target (4e-7 s) lies above the nodal-bound basis and below the global
 * one: the runs without --posterior have elements below it, the runs with
 * it have none, and add no mass, serial and distributed alike. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parts.h"

#define NP 4

static char dir[512];
static cJSON *ser, *par, *ser_global, *par_global, *par_default;

static const char scene_fmt[] = "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n  %s\n"
                                "  <material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
                                "  <effects><elastic formulation=\"3d\"/></effects>\n"
                                "  <time safety=\"0.9\" target=\"4e-7\" duration=\"1e-4\"/>\n</dtmap-scene>\n";

static void write_scene(const char *name, const char *source) {
  char path[1024], text[2048];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  snprintf(text, sizeof text, scene_fmt, source);
  tu_write(path, text);
}

static cJSON *load(const char *name) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  return tu_json_load(path);
}

static int run_logged(int rc, int mpi, const char *scene, const char *out, const char *options) {
  char *log = NULL;
  int r =
      mpi ? tu_mpirun(&log, NP, "sh -c 'cd %s && %s run %s -o %s.msh --report %s.json %s'", dir, tu_cli(), scene, out,
                      out, options)
          : tu_run(&log, "cd %s && %s run %s -o %s.msh --report %s.json %s", dir, tu_cli(), scene, out, out, options);
  if (r) fprintf(stderr, "%s", log);
  free(log);
  return rc | r;
}

/* The serial reference, with the global estimate at a tight tolerance (its
 * theta is lambda_max to about 1e-15), the distributed run, with the
 * estimate at 1e-8 and at the default 1e-4. */
static int setup(void **state) {
  (void)state;
  snprintf(dir, sizeof dir, "%s", tu_tmpdir());
  tu_gmsh_begin();
  tu_mesh_and_split("box.geo", 3, 8e-3, dir, "box", NP);
  write_scene("serial.xml", "<mesh file=\"box.msh\"/>");
  write_scene("parts.xml", "<mesh file=\"box_parts.msh\" partitions=\"4\"/>");
  int rc = run_logged(0, 0, "serial.xml", "ser", "-q");
  rc = run_logged(rc, 1, "parts.xml", "par", "");
  rc = run_logged(rc, 0, "serial.xml", "serg", "--posterior --tol 1e-10 -q");
  rc = run_logged(rc, 1, "parts.xml", "parg", "--posterior --tol 1e-8 -q");
  rc = run_logged(rc, 1, "parts.xml", "def", "--posterior -q");
  ser = load("ser.json"), par = load("par.json"), par_default = load("def.json");
  ser_global = load("serg.json"), par_global = load("parg.json");
  return rc || !ser || !par || !par_default || !ser_global || !par_global;
}

static int teardown(void **state) {
  (void)state;
  cJSON_Delete(ser), cJSON_Delete(par), cJSON_Delete(par_default), cJSON_Delete(ser_global), cJSON_Delete(par_global);
  tu_gmsh_end();
  return 0;
}

/* tol bounds |b - a| / |a| per value; scaled, when positive, bounds
 * |b - a| / max |a| instead. */
static void compare_view_ex(const char *name, double tol, double scaled) {
  char whole[1024], parts[1024];
  tu_view a, b;
  tu_view_diff d;
  snprintf(whole, sizeof whole, "%s/ser.msh", dir);
  snprintf(parts, sizeof parts, "%s/par.msh", dir);
  assert_int_equal(tu_view_pair(whole, parts, NP, name, &a, &b), 0);
  tu_view_compare(&a, &b, &d);
  int bad = scaled > 0 ? d.scaled > scaled : d.worst > tol;
  if (d.missing || bad)
    fprintf(stderr, "view '%s': %zu missing, worst %g, scaled %g\n", name, d.missing, d.worst, d.scaled);
  assert_true(a.n > 0);
  assert_int_equal(d.missing, 0);
  if (tol == 0 && scaled <= 0) assert_int_equal(d.bitequal, a.n);
  assert_false(bad);
  tu_view_free(&a), tu_view_free(&b);
}

static void compare_view(const char *name, double tol) { compare_view_ex(name, tol, 0.0); }

/* Per-element results come from the same kernels on the same coordinates
 * (Gmsh writes the parts' nodes exactly as the whole mesh's): identical. */
static void element_views_identical(void **state) {
  (void)state;
  static const char *const names[] = {"dt", "characteristic length", "limiting effect", "dt elastic",
                                      "subcycling level"};
  for (size_t i = 0; i < sizeof names / sizeof *names; i++) compare_view(names[i], 0.0);
}

/* Node values sum the same element contributions in another order (each
 * part, then across parts): a few roundings of 1.1e-16 each, so 1e-14. */
static void node_views_agree(void **state) {
  (void)state;
  compare_view("nodal dt", 1e-14);
  compare_view("size suggestion", 1e-14);
  /* safety x the element's own step, the larger of its element bound and
   * the smallest nodal bound at its nodes */
  compare_view("below target [s]", 1e-14);
  /* m_a ((target/dt_a)^2 - 1) shared out by mass: node sums in another
   * order, and the subtraction loses digits where dt_a is near the target,
   * so against the largest addition */
  compare_view_ex("added mass", 0.0, 1e-13);
}

static double rel(double a, double b) { return fabs(a - b) / fabs(a); }

static void report_figures(void **state) {
  (void)state;
  double n = tu_json_number(ser, "mesh.elements"), sum = 0;
  assert_true(n > 5000);
  assert_true(tu_json_number(par, "mesh.elements") == n);
  assert_true(tu_json_number(par, "mesh.nodes") == tu_json_number(ser, "mesh.nodes"));
  assert_true(tu_json_number(par, "parallel.ranks") == NP);
  const cJSON *el = cJSON_GetObjectItem(cJSON_GetObjectItem(par, "parallel"), "elements");
  assert_int_equal(cJSON_GetArraySize(el), NP);
  for (int k = 0; k < NP; k++) sum += cJSON_GetArrayItem(el, k)->valuedouble;
  assert_true(sum == n);
  assert_true(tu_json_number(par, "dt.min") == tu_json_number(ser, "dt.min"));
  assert_true(tu_json_number(par, "dt.element") == tu_json_number(ser, "dt.element"));
  assert_true(rel(tu_json_number(ser, "dt.nodal"), tu_json_number(par, "dt.nodal")) <= 1e-14);
  /* subcycling: the same level for every element, so the same counts */
  const cJSON *ls = cJSON_GetObjectItem(cJSON_GetObjectItem(ser, "subcycling"), "levels");
  const cJSON *lp = cJSON_GetObjectItem(cJSON_GetObjectItem(par, "subcycling"), "levels");
  assert_int_equal(cJSON_GetArraySize(ls), cJSON_GetArraySize(lp));
  for (int k = 0; k < cJSON_GetArraySize(ls); k++)
    assert_true(cJSON_GetArrayItem(ls, k)->valuedouble == cJSON_GetArrayItem(lp, k)->valuedouble);
  /* mass sums of ~1e4 positive terms in another order: within 1e-12 */
  assert_true(rel(tu_json_number(ser, "mass_scaling.total_mass"), tu_json_number(par, "mass_scaling.total_mass")) <=
              1e-12);
  assert_true(rel(tu_json_number(ser, "mass_scaling.total_added"), tu_json_number(par, "mass_scaling.total_added")) <=
              1e-12);
  assert_true(tu_json_number(ser, "mass_scaling.elements_scaled") ==
              tu_json_number(par, "mass_scaling.elements_scaled"));
}

/* The exact step lies below 2/sqrt(theta) of any Ritz value theta; the
 * serial run at 1e-10 puts that bound within about 1e-15 of it. */
static double exact_step_bound(void) {
  const cJSON *m = cJSON_GetArrayItem(cJSON_GetObjectItem(ser_global, "effect_minima"), 0);
  const cJSON *br = cJSON_GetObjectItem(cJSON_GetObjectItem(m, "lanczos"), "dt_bracket");
  return cJSON_GetArrayItem(br, 1)->valuedouble;
}

static void global_estimate(void **state) {
  (void)state;
  double s = tu_json_number(ser_global, "dt.global"), p = tu_json_number(par_global, "dt.global");
  double d = tu_json_number(par_default, "dt.global"), exact = exact_step_bound();
  assert_true(isfinite(s) && isfinite(p) && isfinite(d));
  /* both converged to a residual of at most 1e-8 theta: within 1e-6 */
  assert_true(rel(s, p) <= 1e-6);
  /* safe side: theta + residual, never above the exact step */
  assert_true(p <= exact && d <= exact);
  /* at the default tolerance 1e-4 the step is within it of the exact one */
  assert_true(rel(exact, d) <= 1e-4);
  assert_string_equal(cJSON_GetObjectItem(cJSON_GetObjectItem(par_global, "dt"), "basis")->valuestring,
                      "global estimate");
  assert_true(rel(tu_json_number(par_global, "dt.recommended"), 0.9 * p) <= 1e-15);
}

/* The target lies between the two bases: below it on the nodal bound,
 * met on the global estimate, where no element is advised to change and
 * no mass is added, serial and distributed alike. */
static void global_basis_advice(void **state) {
  (void)state;
  const double target = 4e-7;
  assert_true(tu_json_number(ser, "dt.recommended") < target && tu_json_number(ser, "below_target") > 0);
  assert_true(tu_json_number(par, "below_target") == tu_json_number(ser, "below_target"));
  cJSON *g[2] = {ser_global, par_global};
  for (int k = 0; k < 2; k++) {
    assert_true(tu_json_number(g[k], "dt.recommended") >= target);
    assert_true(tu_json_number(g[k], "below_target") == 0);
    assert_true(tu_json_number(g[k], "mass_scaling.total_added") == 0);
  }
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(element_views_identical), cmocka_unit_test(node_views_agree),
      cmocka_unit_test(report_figures),          cmocka_unit_test(global_estimate),
      cmocka_unit_test(global_basis_advice),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
