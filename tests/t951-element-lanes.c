/* The element bounds solved four at a time in vector lanes
 * (dtm_kernel_elastic_lambda_lanes, dtm_eig_sym_max_tridiag_lanes: issue 46)
 * against the one-element path they replace in the element map
 * (dtm_kernel_elastic_lambda_at, dtm_eig_sym_max_tridiag):
 *  - the tridiagonal reduction and Laguerre's search of four matrices side
 *    by side, each lane against the scalar path on its matrix alone, with
 *    a zero matrix, a NaN, a diagonal matrix (every reflection skipped, the
 *    first pivot zero), a multiple top (the bisection's end) and short
 *    groups in the other lanes, n from 13 to 81;
 *  - groups of 1 to 4 random elements of every type the lanes take (tet10
 *    straight and curved side by side, whose groups go straight into the
 *    packed lanes, hex8, prism6, pyr5, quad8) whose sizes (1e-3 to
 *    1e3 m), materials and Poisson ratios differ wildly side by side, with
 *    their levels kept or searched; an element that fails in the middle of
 *    a group;
 *  - the elastic effect's grouping: batches of 1 to 11 tet10 of two
 *    materials against the kernel's one-element bound of each element;
 *  - whole analyses, the lanes on and off (dtm_kernel_lanes_off: the
 *    one-element path, the code before them), compared element by element
 *    and effect by effect: tet10 meshes from real Gmsh geometries (a
 *    straight box, a curved ball whose straight and curved elements sit side
 *    by side), the notched beam at order 2, and every bundled example as it
 *    is.
 * Tolerance 1e-12 relative everywhere (what issue 46 allows the dt map to
 * move); each lane does the scalar operations in the scalar order, so the
 * differences are expected to be zero and the largest is printed. The
 * random groups also check that the elements of a group have bounds
 * differing by far more than 1e-12: a lane handed another lane's matrix or
 * result would fail. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/analysis.h"
#include "dtmap/error.h"
#include "dtmap/gmsh.h"
#include "dtmap/kernel.h"
#include "dtmap/scene.h"
#include "fixtures.h"
#include "kernel-impl.h"
#include "testutil.h"

#define TOL 1e-12

extern const dtm_effect_class dtm_effect_elastic;

static uint64_t seed = 0x2545f4914f6cdd1du;

static double urand(void) { /* uniform in [-1, 1) */
  seed = seed * 6364136223846793005u + 1442695040888963407u;
  return (double)(seed >> 11) / 4503599627370496.0 - 1;
}

static double worst;

static void same(double got, double want, const char *what, int k) {
  double rel = got == want ? 0 : fabs(got - want) / fmax(fabs(got), fabs(want));
  if (rel > worst) worst = rel;
  if (!(rel <= TOL) && !(isnan(got) && isnan(want)))
    fail_msg("%s, lane %d: lanes %.17g, one by one %.17g (rel %.3g)", what, k, got, want, rel);
}

/* A random symmetric n x n matrix with entries of size about scale. */
static void random_sym(int n, double scale, double *a) {
  for (int i = 0; i < n; i++)
    for (int j = 0; j <= i; j++) a[i * n + j] = a[j * n + i] = scale * urand() + (i == j ? 2 * scale : 0);
}

static void tridiagonal_lanes(void **state) {
  (void)state;
  static double a[4][DTM_K_DOF * DTM_K_DOF], b[DTM_K_DOF * DTM_K_DOF];
  worst = 0;
  for (int r = 0; r < 120; r++) {
    int n = 13 + r % 69, count = 1 + r % 4;
    for (int l = 0; l < 4; l++) random_sym(n, pow(10, 8 * urand()), a[l]);
    if (r % 5 == 1) memset(a[r % count], 0, sizeof a[0]); /* the zero matrix: 0 */
    if (r % 5 == 2) a[r % count][3 * n + 1] = NAN;        /* NaN */
    if (r % 5 == 3)                                       /* diagonal: every column already zero */
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) a[r % count][i * n + j] = i == j ? urand() : 0;
    if (r % 5 == 4) { /* one random 3 x 3 block repeated along the diagonal: a multiple top (bisection's end) */
      double blk[9];
      random_sym(3, 1, blk);
      memset(a[r % count], 0, sizeof a[0]);
      for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
          if (i / 3 == j / 3 && i / 3 < n / 3) a[r % count][i * n + j] = blk[(i % 3) * 3 + j % 3];
    }
    double *p[4] = {a[0], a[1], a[2], a[3]}, got[4], want;
    dtm_eig_sym_max_tridiag_lanes(n, p, count, got);
    for (int l = 0; l < count; l++) {
      memcpy(b, a[l], sizeof(double) * (size_t)(n * n));
      want = dtm_eig_sym_max_tridiag(n, b);
      same(got[l], want, "tridiagonal", l);
    }
  }
  print_message("tridiagonal lanes against one by one: largest relative difference %.3g\n", worst);
}

/* A random element of type at scale h: the regular element's corners moved
 * by up to 15 %, the other nodes where the parent's map puts them, moved by
 * up to curve h; shifted away from the origin; 2D elements in the xy plane. */
static void shape(int type, double h, double curve, double *x) {
  int d, nn;
  dtm_elem_info(type, &d, &nn);
  assert_int_equal(tu_random_element(type, curve, urand, x), DTM_OK);
  for (int i = 0; i < 3 * nn; i++) x[i] = h * (x[i] + (d == 2 && i % 3 == 2 ? 0 : 3));
}

static void group(int type, int count, int fail_at) {
  double x[4][3 * DTM_K_NODES], got[4] = {NAN, NAN, NAN, NAN}, want[4];
  dtm_elastic_moduli mod[4];
  const dtm_elastic_moduli *m[4];
  const double *xp[4];
  int level[4], d, failed = -1;
  dtm_elem_info(type, &d, NULL);
  for (int k = 0; k < count; k++) {
    double h = pow(10, 3 * urand()), nu = 0.45 * urand(), E = 1e9 * pow(10, 2 * urand()), rho = 1000 * (2 + urand());
    shape(type, h, dtm_elem_parent(type) != type && urand() > 0 ? 0.08 : 0, x[k]);
    assert_int_equal(dtm_elastic_moduli_init(d == 3 ? DTM_FORM_3D : DTM_FORM_PLANE_STRESS, E, nu, rho, &mod[k]), 0);
    mod[k].integration = urand() > -0.6 ? DTM_INTEGRATION_CONVERGED : DTM_INTEGRATION_FULL;
    dtm_qrule q;
    level[k] = urand() > 0 ? dtm_ref_rule_elem(type, x[k], mod[k].integration, &q) : -1;
    if (mod[k].integration != DTM_INTEGRATION_CONVERGED && level[k] > 0) level[k] = 0;
    m[k] = &mod[k], xp[k] = x[k];
  }
  if (fail_at >= 0) /* flat: every node on a plane (or line) */
    for (int a = 0; a < DTM_K_NODES; a++) x[fail_at][3 * a + (d == 3 ? 2 : 1)] = 0;
  int r = dtm_kernel_elastic_lambda_lanes(type, count, m, xp, level, got, &failed);
  if (fail_at >= 0) {
    assert_int_not_equal(r, DTM_OK);
    assert_int_equal(failed, fail_at);
    dtm_error_clear();
  } else if (r)
    fail_msg("%s: %s", dtm_elem_name(type), dtm_error_message());
  int n = fail_at >= 0 ? fail_at : count;
  for (int k = 0; k < n; k++) {
    assert_int_equal(dtm_kernel_elastic_lambda_at(type, m[k], xp[k], level[k], &want[k]), DTM_OK);
    same(got[k], want[k], dtm_elem_name(type), k);
    for (int j = 0; j < k; j++) /* the lanes hold different problems: mixing them would show */
      if (!(fabs(want[j] / want[k] - 1) > 1e-9))
        fail_msg("%s: lanes %d and %d have the same bound %.17g", dtm_elem_name(type), j, k, want[k]);
  }
}

static void element_lanes(void **state) {
  (void)state;
  static const int types[] = {DTM_TET10, DTM_HEX8, DTM_PRISM6, DTM_PYR5, DTM_QUAD8};
  worst = 0;
  for (size_t t = 0; t < sizeof types / sizeof types[0]; t++)
    for (int r = 0; r < 60; r++) group(types[t], 1 + r % 4, -1);
  group(DTM_TET10, 4, 2);
  group(DTM_HEX8, 3, 1);
  print_message("element lanes against one by one: largest relative difference %.3g\n", worst);
}

/* The elastic effect groups its elements four by four: a batch of n = 4 q
 * + r tet10 (r = 0..3) of two materials, straight and curved, sizes from
 * 1e-3 to 1e3 m, levels kept, against the kernel's one-element bound of
 * each element (equality: the lanes give it bitwise). */
static void effect_groups(void **state) {
  (void)state;
  enum { NMAX = 11 };
  static double x[NMAX][30];
  dtm_material mat[2];
  static const double E[2] = {210e9, 2e6}, nu[2] = {0.3, 0.45}, rho[2] = {7850, 1100};
  tu_material(&mat[0], "steel", "E", E[0], "nu", nu[0], "rho", rho[0], NULL);
  tu_material(&mat[1], "rubbery", "E", E[1], "nu", nu[1], "rho", rho[1], NULL);
  const dtm_material *mats[NMAX];
  size_t tags[NMAX];
  int groups[NMAX];
  unsigned char level[NMAX];
  tu_effect_fixture f;
  void *st = NULL;
  tu_fixture_init(&f, "elastic", 3, NULL);
  assert_int_equal(dtm_effect_elastic.create(&f.args, &st), DTM_OK);
  for (int n = 1; n <= NMAX; n++) {
    for (int e = 0; e < n; e++) {
      shape(DTM_TET10, pow(10, 3 * urand()), e % 3 ? 0.08 : 0, x[e]);
      mats[e] = &mat[e % 2], tags[e] = (size_t)e + 1, groups[e] = 0;
      dtm_qrule q;
      level[e] = (unsigned char)dtm_ref_rule_elem(DTM_TET10, x[e], DTM_INTEGRATION_CONVERGED, &q);
    }
    dtm_batch b = {DTM_TET10, 3, 10, (size_t)n, &x[0][0], tags, groups, NULL, mats, NULL, level};
    double dt[NMAX], len[NMAX];
    assert_int_equal(dtm_effect_elastic.element_dt(st, &b, dt, len), DTM_OK);
    for (int e = 0; e < n; e++) {
      dtm_elastic_moduli m;
      double lambda;
      assert_int_equal(dtm_elastic_moduli_init(DTM_FORM_3D, E[e % 2], nu[e % 2], rho[e % 2], &m), DTM_OK);
      assert_int_equal(dtm_kernel_elastic_lambda_at(DTM_TET10, &m, x[e], level[e], &lambda), DTM_OK);
      if (!(dt[e] == 2 / sqrt(lambda) && len[e] == m.cd * dt[e]))
        fail_msg("batch of %d, element %d: effect %.17g, kernel %.17g", n, e, dt[e], 2 / sqrt(lambda));
    }
  }
  dtm_effect_elastic.destroy(&st);
}

/* Every element's step of every effect of the scene at path, the lanes on
 * against off; returns the number of elements, its curved ones into
 * *curved. */
static size_t analyses(const char *path, size_t *curved) {
  dtm_scene *s = NULL;
  dtm_analysis *a[2] = {NULL, NULL};
  if (dtm_scene_load(path, &s)) fail_msg("%s: %s", path, dtm_error_message());
  for (int off = 0; off < 2; off++) {
    dtm_kernel_lanes_off = off;
    if (dtm_analysis_run(s, &a[off])) fail_msg("%s: %s", path, dtm_error_message());
  }
  dtm_kernel_lanes_off = 0;
  size_t n = dtm_analysis_nelements(a[0]);
  assert_int_equal(n, dtm_analysis_nelements(a[1]));
  const dtm_curvature_summary *c = dtm_analysis_curvature(a[0]);
  *curved = c ? c->curved : 0;
  for (int k = 0; k < dtm_analysis_neffects(a[0]); k++) {
    const double *on = dtm_analysis_effect_dt(a[0], k), *one = dtm_analysis_effect_dt(a[1], k);
    for (size_t i = 0; on && i < n; i++)
      if (!(on[i] == one[i]) && !(isinf(on[i]) && isinf(one[i]))) same(on[i], one[i], path, (int)(i % 4));
  }
  const double *on = dtm_analysis_dt(a[0]), *one = dtm_analysis_dt(a[1]);
  for (size_t i = 0; i < n; i++)
    if (!(on[i] == one[i]) && !(isinf(on[i]) && isinf(one[i]))) same(on[i], one[i], path, (int)(i % 4));
  dtm_analysis_destroy(&a[0]);
  dtm_analysis_destroy(&a[1]);
  dtm_scene_destroy(&s);
  return n;
}

static void scene_file(const char *name, const char *geo, const char *meshing, const char *mat) {
  char path[600], text[2048];
  snprintf(text, sizeof text,
           "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n<geometry file=\"%s\"/>\n<meshing %s/>\n%s\n"
           "<effects><elastic/></effects>\n</dtmap-scene>\n",
           geo, meshing, mat);
  snprintf(path, sizeof path, "%s/%s.xml", tu_tmpdir(), name);
  tu_write(path, text);
}

static void meshes(void **state) {
  (void)state;
  static const char steel[] = "<material name=\"steel\" groups=\"block\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>";
  char path[600], geo[700];
  worst = 0;
  tu_cube_geo("cube.geo", "");
  snprintf(path, sizeof path, "%s/ball.geo", tu_tmpdir());
  tu_write(path, "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0, 0, 0, 1};\nPhysical Volume(\"block\") = {1};\n");
  scene_file("box10", "cube.geo", "size=\"0.15\" order=\"2\" dim=\"3\"", steel);
  scene_file("ball10", "ball.geo", "size=\"0.3\" order=\"2\" dim=\"3\"", steel);
  snprintf(geo, sizeof geo, "%s/geometries/notched_beam.geo", tu_src());
  scene_file("beam10", geo, "size=\"2e-2\" min-size=\"5e-3\" order=\"2\" dim=\"3\"",
             "<material name=\"concrete\" groups=\"beam\" E=\"30e9\" nu=\"0.2\" rho=\"2400\"/>");
  static const char *const ours[] = {"box10", "ball10", "beam10"};
  int odd = 0;
  for (int k = 0; k < 3; k++) {
    snprintf(path, sizeof path, "%s/%s.xml", tu_tmpdir(), ours[k]);
    size_t curved, n = analyses(path, &curved);
    print_message("%s: %zu tet10 (%zu mod 4), %zu curved\n", ours[k], n, n % 4, curved);
    odd += n % 4 != 0;
    if (k == 1) assert_true(curved > 0 && curved < n); /* curved and straight side by side */
  }
  assert_true(odd > 0); /* a short last group in some mesh */
  static const char *const bundled[] = {
      "box",          "brazilian_disc", "notched_beam", "plate_with_hole", "reinforced_block", "stiffened_panel",
      "tunnel_lining"};
  for (size_t k = 0; k < sizeof bundled / sizeof bundled[0]; k++) {
    snprintf(path, sizeof path, "%s/geometries/%s.xml", tu_src(), bundled[k]);
    size_t curved, n = analyses(path, &curved);
    print_message("%s: %zu elements\n", bundled[k], n);
  }
  print_message("analyses, lanes against one by one: largest relative difference %.3g\n", worst);
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  if (dtm_gmsh_start(0)) return 3;
  const struct CMUnitTest tests[] = {cmocka_unit_test(tridiagonal_lanes), cmocka_unit_test(element_lanes),
                                     cmocka_unit_test(effect_groups), cmocka_unit_test(meshes)};
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  dtm_gmsh_stop();
  return r;
}
