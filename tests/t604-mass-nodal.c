/* Mass scaling at the nodes (the nodal-bound basis) on hand-built bars,
 * elastic in the bar formulation: bars L and 2L (nodes 0, 1, 2), steel,
 * c = sqrt(E/rho), lambda_e = 4 c^2/L_e^2, lumped node masses rho L_e/2.
 * Node steps: node 0 (bar L only) L/c; node 1 (num = 4c^2/L^2 rho L/2 +
 * c^2/L^2 rho L = 3 c^2 rho/L, mass 3 rho L/2) lambda = 2 c^2/L^2, so
 * sqrt(2) L/c; node 2 (bar 2L only) 2L/c. For the target 1.5 L/c node 0
 * needs (1.5^2 - 1) rho L/2 = 0.625 rho L, node 1 (1.5^2/2 - 1) 3 rho L/2 =
 * 0.1875 rho L, node 2 none; node 1's mass goes 1/3 to bar 0 and 2/3 to
 * bar 1: bar 0 gets 0.6875 rho L, bar 1 0.125 rho L. The element-by-element
 * form needs 1.25 rho L for bar 0 alone: the nodal form needs less. The
 * same mass at the nodes: 0.625, 0.1875 and 0 rho L. With
 * only bar 1 selected, only nodes 1 and 2 count: 0.1875 rho L in all.
 * Tolerance 1e-12 relative: the kernel's steps are within a few eps of the
 * closed forms, squared and summed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixtures.h"
#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "effect-impl.h"

#define L 0.5
#define RHO 8000.0 /* tu_bar_scene's steel */
#define E 200e9

static const double len[2] = {L, 2 * L};

static dtm_analysis *bars(dtm_scene *s, dtm_scene_effect *se, dtm_scene_material *sm, double target) {
  tu_bar_scene(s, se, sm, target);
  return tu_bar_analysis(s, 2, len, NULL, 0);
}

static void close_to(double got, double want) {
  if (!(fabs(got - want) <= 1e-12 * fabs(want))) fail_msg("got %.17g, want %.17g", got, want);
}

static void nodal_closed_form(void **unused) {
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  dtm_analysis *a = bars(&s, &se, &sm, 0);
  const double c = sqrt(E / RHO), target = 1.5 * L / c;
  const double *nd = dtm_analysis_nodal(a);
  close_to(nd[0], L / c), close_to(nd[1], sqrt(2.0) * L / c), close_to(nd[2], 2 * L / c);
  dtm_mass_scaling ms, el;
  assert_int_equal(dtm_mass_scaling_nodal(a, target, NULL, &ms), 0);
  assert_true(ms.nodal == 1);
  close_to(ms.added[0], 0.6875 * RHO * L), close_to(ms.added[1], 0.125 * RHO * L);
  close_to(ms.total_added, 0.8125 * RHO * L), close_to(ms.total_mass, 3 * RHO * L);
  assert_int_equal(ms.scaled, 2);
  close_to(ms.node_added[0], 0.625 * RHO * L), close_to(ms.node_added[1], 0.1875 * RHO * L);
  assert_true(ms.node_added[2] == 0.0 && ms.nodes == 2);
  assert_int_equal(dtm_mass_scaling_compute(a, target, &el), 0);
  assert_null(el.node_added);
  close_to(el.added[0], 1.25 * RHO * L);
  assert_true(el.added[1] == 0.0 && ms.total_added < el.total_added);
  dtm_mass_scaling_free(&ms), dtm_mass_scaling_free(&el);
  dtm_analysis_destroy(&a);
  (void)unused;
}

static void nodal_only(void **unused) {
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  dtm_analysis *a = bars(&s, &se, &sm, 0);
  const double c = sqrt(E / RHO);
  const unsigned char only[2] = {0, 1};
  dtm_mass_scaling ms;
  assert_int_equal(dtm_mass_scaling_nodal(a, 1.5 * L / c, only, &ms), 0);
  close_to(ms.total_added, 0.1875 * RHO * L);
  close_to(ms.added[0], 0.0625 * RHO * L), close_to(ms.added[1], 0.125 * RHO * L);
  assert_true(ms.node_added[0] == 0.0 && ms.node_added[2] == 0.0); /* node 0 is not selected; node 2 needs none */
  close_to(ms.node_added[1], 0.1875 * RHO * L);
  dtm_mass_scaling_free(&ms);
  assert_int_equal(dtm_mass_scaling_nodal(a, -1.0, NULL, &ms), DTM_ERR_INPUT); /* bad target, safe to free */
  dtm_mass_scaling_free(&ms);
  dtm_analysis_destroy(&a);
  (void)unused;
}

/* The cost object aims at the scene's target from the basis: the nodal
 * bound here, so it scales at the nodes, to target / safety. */
static void cost_uses_basis(void **unused) {
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  dtm_analysis *a = bars(&s, &se, &sm, 0.9 * 1.5 * L / sqrt(E / RHO));
  assert_string_equal(dtm_analysis_basis(a), "nodal bound");
  dtm_cost *cost = NULL;
  assert_int_equal(dtm_cost_create(a, &cost), 0);
  assert_true(cost->mass && cost->mass->nodal == 1);
  close_to(cost->mass->total_added, 0.8125 * RHO * L);
  assert_true(cost->basis == dtm_analysis_recommended(a));
  dtm_cost_destroy(&cost);
  dtm_analysis_destroy(&a);
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(nodal_closed_form), cmocka_unit_test(nodal_only),
                                     cmocka_unit_test(cost_uses_basis)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
