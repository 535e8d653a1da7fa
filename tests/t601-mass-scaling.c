/* Mass scaling on hand-built 1D meshes: bars along x, elastic in the bar
 * formulation, so an element's wave step is dt_e = L_e/c (c = sqrt(E/rho))
 * and its mass rho L_e (per unit cross-section). To reach dt_t an element
 * with dt_e < dt_t gets rho L_e ((dt_t/dt_e)^2 - 1); the others get 0.
 * Checked per element, per group (last slot: no group) and in total; with
 * constant damping xi, whose factor 1/(sqrt(1+xi^2)+xi) multiplies every
 * dt_e; and with a thermal-only scene, where no mass is ever added. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "fixtures.h"
#include "dtmap/cost.h"
#include "dtmap/error.h"

#define NB 4
/* Bar lengths (m), groups (-1: none) and materials of the four elements. */
static const double len[NB] = {0.5, 1.0, 2.0, 4.0};
static const int grp[NB] = {0, 0, 1, -1};
static const int mat[NB] = {0, 0, 1, 0};

static dtm_mesh *bars(void) {
  dtm_mesh *m = tu_bar_mesh(NB, len, grp, mat);
  m->ngroups = 2;
  m->groups = calloc(2, sizeof *m->groups);
  m->groups[0] = (dtm_group){1, 1, strdup("a")}, m->groups[1] = (dtm_group){1, 2, strdup("b")};
  return m;
}

/* steel (0) and aluminium (1), with thermal properties too */
static const double E[2] = {200e9, 70e9}, rho[2] = {8000, 2700};
static dtm_scene_material mats[2];
static char *el_keys[] = {"formulation"}, *el_vals[] = {"bar"};
static char *dp_keys[] = {"xi"}, *dp_vals[] = {"0.1"};

static void scene_init(dtm_scene *s, dtm_scene_effect *se, int neffects) {
  for (int i = 0; i < 2; i++) {
    mats[i] = (dtm_scene_material){0};
    dtm_material *m = &mats[i].m;
    tu_material(m, i ? "alu" : "steel", "E", E[i], "rho", rho[i], "conductivity", 50.0, "heat-capacity", 500.0, NULL);
    m->file = "mem.xml", m->line = 3 + i;
    mats[i].is_default = i == 0;
  }
  *s = (dtm_scene){0};
  tu_scene_catalogue(s);
  s->path = "mem.xml", s->nmaterials = 2, s->materials = mats, s->neffects = neffects, s->effects = se;
  s->safety = 0.9;
}

static dtm_analysis *analyse(const dtm_scene *s) {
  dtm_mesh *m = bars();
  dtm_effect *ef = NULL;
  int ne = 0;
  assert_int_equal(dtm_effects_create(s, m, &ef, &ne), 0);
  dtm_analysis *a = NULL;
  assert_int_equal(dtm_analysis_compute(s, m, ef, ne, &a), 0);
  return a;
}

/* Closed forms with wave factor f on every dt_e; target = 1.5 m / c_steel
 * x f, so elements 0 and 1 (steel, 0.5 m and 1 m) are below it and get
 * (3^2 - 1) and (1.5^2 - 1) times their mass, element 2 (aluminium, 2 m,
 * dt = 2/c_alu > 1.5/c_steel) and element 3 (steel, 4 m) none.
 * Tolerance 1e-13 relative: the kernel's dt_e is within a few eps of L/c,
 * and (t/dt)^2 - 1 amplifies a relative error by 2r^2/(r^2-1) < 4 here. */
static void check_bars(const dtm_analysis *a, double f) {
  const double c[2] = {sqrt(E[0] / rho[0]), sqrt(E[1] / rho[1])}, target = 1.5 / c[0] * f;
  dtm_mass_scaling ms;
  assert_int_equal(dtm_mass_scaling_compute(a, target, &ms), 0);
  double want[NB], mass[NB], gm[3] = {0}, ga[3] = {0}, tm = 0, ta = 0;
  for (int e = 0; e < NB; e++) {
    double dt = len[e] / c[mat[e]] * f, r = target / dt;
    mass[e] = rho[mat[e]] * len[e];
    want[e] = dt < target ? mass[e] * (r * r - 1) : 0.0;
    int g = grp[e] < 0 ? 2 : grp[e];
    gm[g] += mass[e], ga[g] += want[e], tm += mass[e], ta += want[e];
  }
  assert_true(fabs(want[0] - 8 * rho[0] * 0.5) <= 1e-13 * want[0]);
  assert_true(fabs(want[1] - 1.25 * rho[0]) <= 1e-13 * want[1]);
  for (int e = 0; e < NB; e++) assert_true(fabs(ms.added[e] - want[e]) <= 1e-13 * want[e]);
  assert_true(ms.added[2] == 0.0 && ms.added[3] == 0.0); /* above the target: exactly none */
  assert_int_equal(ms.scaled, 2);
  assert_int_equal(ms.ngroups, 3);
  for (int g = 0; g < 3; g++) {
    assert_true(fabs(ms.group_mass[g] - gm[g]) <= 1e-13 * gm[g]);
    assert_true(fabs(ms.group_added[g] - ga[g]) <= 1e-13 * ga[g]);
  }
  assert_true(fabs(ms.total_mass - tm) <= 1e-13 * tm);
  assert_true(fabs(ms.total_added - ta) <= 1e-13 * ta);
  assert_true(ms.target == target);
  dtm_mass_scaling_free(&ms);
  assert_null(ms.added);
}

static void elastic_bars(void **unused) {
  dtm_scene s;
  dtm_scene_effect se[1] = {{"elastic", NULL, 5, 1, el_keys, el_vals}};
  scene_init(&s, se, 1);
  dtm_analysis *a = analyse(&s);
  check_bars(a, 1.0);
  dtm_analysis_destroy(&a);
  (void)unused;
}

/* Constant xi: every wave step is multiplied by 1/(sqrt(1+xi^2)+xi), and
 * the mass scaling must use the damped step. */
static void damped_bars(void **unused) {
  dtm_scene s;
  dtm_scene_effect se[2] = {{"elastic", NULL, 5, 1, el_keys, el_vals}, {"damping", NULL, 6, 1, dp_keys, dp_vals}};
  scene_init(&s, se, 2);
  dtm_analysis *a = analyse(&s);
  check_bars(a, 1.0 / (sqrt(1.0 + 0.01) + 0.1));
  dtm_analysis_destroy(&a);
  (void)unused;
}

/* Mass does not change a diffusion limit: a thermal-only scene gets no
 * added mass even for a target far above every step; the masses are still
 * counted (exact sums of rho L in binary: 1e-15 relative for the sum). */
static void thermal_only(void **unused) {
  dtm_scene s;
  dtm_scene_effect se[1] = {{"thermal", NULL, 5, 0, NULL, NULL}};
  scene_init(&s, se, 1);
  dtm_analysis *a = analyse(&s);
  dtm_mass_scaling ms;
  assert_int_equal(dtm_mass_scaling_compute(a, 1e9, &ms), 0);
  for (int e = 0; e < NB; e++) assert_true(ms.added[e] == 0.0);
  assert_int_equal(ms.scaled, 0);
  assert_true(ms.total_added == 0.0);
  double tm = 0;
  for (int e = 0; e < NB; e++) tm += rho[mat[e]] * len[e];
  assert_true(fabs(ms.total_mass - tm) <= 1e-15 * tm);
  dtm_mass_scaling_free(&ms);
  dtm_analysis_destroy(&a);
  (void)unused;
}

/* A target that is not a positive finite step is bad input, and the
 * result stays safe to free. */
static void bad_target(void **unused) {
  dtm_scene s;
  dtm_scene_effect se[1] = {{"elastic", NULL, 5, 1, el_keys, el_vals}};
  scene_init(&s, se, 1);
  dtm_analysis *a = analyse(&s);
  const double bad[] = {0.0, -1e-6, NAN, INFINITY};
  for (int i = 0; i < 4; i++) {
    dtm_mass_scaling ms;
    dtm_error_clear();
    assert_int_equal(dtm_mass_scaling_compute(a, bad[i], &ms), DTM_ERR_INPUT);
    assert_non_null(strstr(dtm_error_message(), "target step"));
    dtm_mass_scaling_free(&ms);
  }
  dtm_error_clear();
  dtm_analysis_destroy(&a);
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(elastic_bars), cmocka_unit_test(damped_bars),
                                     cmocka_unit_test(thermal_only), cmocka_unit_test(bad_target)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
