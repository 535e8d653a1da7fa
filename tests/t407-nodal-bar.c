/* The nodal bound through the whole pipeline on a hand-built 1D mesh: three
 * bars of lengths L, l, L (l << L), one material. Element bounds
 * lambda_e = 4E/(rho L_e^2), lumped masses rho L_e/2 per node. At an inner
 * node: (lambda_1 rho L/2 + lambda_2 rho l/2) / (rho (L + l)/2)
 *       = (4E/rho) (1/L + 1/l) / (L + l) = 4E/(rho L l),
 * so dt_nodal = sqrt(rho L l / E), sqrt(L/l) times the element bound l/c.
 * At the end nodes the bound is the big bars' own 4E/(rho L^2), smaller. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "fixtures.h"

static dtm_mesh *three_bars(double L, double l) {
  const double len[3] = {L, l, L};
  return tu_bar_mesh(3, len, NULL, NULL);
}

static void nodal_three_bars(void **unused) {
  const double E = 200e9, rho = 8000, L = 0.1, l = 0.001, c = sqrt(E / rho);
  static char *keys[] = {"formulation"}, *vals[] = {"bar"};
  dtm_scene_effect se = {"elastic", NULL, 5, 1, keys, vals};
  dtm_scene_material sm = {0};
  tu_material(&sm.m, "steel", "E", E, "rho", rho, NULL);
  sm.is_default = 1;
  dtm_scene s = {0};
  tu_scene_catalogue(&s);
  s.path = "mem.xml", s.nmaterials = 1, s.materials = &sm, s.neffects = 1, s.effects = &se, s.safety = 0.9;
  dtm_mesh *m = three_bars(L, l);
  dtm_effect *ef = NULL;
  int ne = 0;
  assert_int_equal(dtm_effects_create(&s, m, &ef, &ne), 0);
  dtm_analysis *a = NULL;
  assert_int_equal(dtm_analysis_compute(&s, m, ef, ne, &a), 0);
  /* closed forms; 1e-13 relative covers the kernel's and the scatter's roundings */
  assert_true(fabs(a->dt_min - l / c) <= 1e-13 * a->dt_min);
  assert_true(fabs(a->dt_nodal - sqrt(rho * L * l / E)) <= 1e-13 * a->dt_nodal);
  assert_true(fabs(a->nodal_node[0] - L / c) <= 1e-13 * L / c);
  assert_true(fabs(a->recommended - 0.9 * a->dt_nodal) <= 1e-15 * a->dt_nodal);
  assert_string_equal(a->basis, "nodal bound");
  dtm_analysis_destroy(&a);
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(nodal_three_bars)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
