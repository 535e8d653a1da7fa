/* Subcycling levels on a hand-built mesh of bars (elastic, bar
 * formulation, dt_e = L_e/c): lengths L, 2L, 2L, 4L, 5L give levels 0, 1, 1,
 * 2, 2 and the ideal speed-up N / sum_k N_k 2^-k = 5/(1 + 2/2 + 2/4) = 2.
 * L = 0.25 m and integer node positions keep every length exact, so the
 * steps scale by exact powers of two and the 2L and 4L bars sit exactly on
 * a level boundary. Then the level rule itself, on hand-set steps: a step
 * exactly dt_min 2^k is on level k, one ulp below is on level k - 1,
 * infinite steps join the highest finite level, and levels clamp at
 * DTM_MAX_LEVELS - 1. Then the basis: on bars 2L, L, 2L the middle bar's
 * own safe step is the smallest nodal bound at its nodes, sqrt(2) L/c,
 * above its element bound L/c, and that is also dt.recommended / safety:
 * every level is 0 and the speed-up exactly 1; a step below the basis
 * (possible only with the global estimate as the basis) stays on level 0. */
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

#define NB 5
static const double mult[NB] = {1, 2, 2, 4, 5};

static dtm_mesh *bars(double L) {
  double len[NB];
  for (int e = 0; e < NB; e++) len[e] = mult[e] * L;
  return tu_bar_mesh(NB, len, NULL, NULL);
}

static dtm_analysis *analyse(dtm_scene *s, dtm_scene_effect *se, dtm_scene_material *sm) {
  static char *keys[] = {"formulation"}, *vals[] = {"bar"};
  *se = (dtm_scene_effect){"elastic", NULL, 5, 1, keys, vals};
  *sm = (dtm_scene_material){0};
  tu_material(&sm->m, "steel", "E", 200e9, "rho", 8000.0, NULL);
  sm->is_default = 1;
  *s = (dtm_scene){0};
  tu_scene_catalogue(s);
  s->path = "mem.xml", s->nmaterials = 1, s->materials = sm, s->neffects = 1, s->effects = se, s->safety = 0.9;
  dtm_mesh *m = bars(0.25);
  dtm_effect *ef = NULL;
  int ne = 0;
  assert_int_equal(dtm_effects_create(s, m, &ef, &ne), 0);
  dtm_analysis *a = NULL;
  assert_int_equal(dtm_analysis_compute(s, m, ef, ne, &a), 0);
  return a;
}

static void bar_levels(void **unused) {
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  dtm_analysis *a = analyse(&s, &se, &sm);
  dtm_subcycling sc;
  assert_int_equal(dtm_subcycling_compute(a, &sc), 0);
  const int want[NB] = {0, 1, 1, 2, 2};
  for (int e = 0; e < NB; e++) assert_int_equal(sc.level[e], want[e]);
  assert_int_equal(sc.nlevels, 3);
  assert_int_equal(sc.count[0], 1);
  assert_int_equal(sc.count[1], 2);
  assert_int_equal(sc.count[2], 2);
  /* 5 / 2.5: dyadic sums and one division, exact; 1e-15 relative as asked */
  assert_true(fabs(sc.speedup - 2.0) <= 1e-15 * 2.0);
  dtm_subcycling_free(&sc);
  assert_null(sc.level);
  dtm_analysis_destroy(&a);
  (void)unused;
}

/* The level rule on chosen own steps against the basis d. */
static void level_rule(void **unused) {
  const double d = 3.1e-7; /* not a power of two: ldexp(d, k) is still exact */
  const double dt[NB] = {d, 2 * d, nextafter(2 * d, 0), 8 * d * (1 + 0x1p-52), INFINITY};
  dtm_subcycling sc;
  assert_int_equal(dtm_subcycling_levels(dt, NB, d, &sc), 0);
  const int want[NB] = {0, 1, 0, 3, 3};
  for (int e = 0; e < NB; e++) assert_int_equal(sc.level[e], want[e]);
  assert_int_equal(sc.nlevels, 4);
  /* N / (2 + 1/2 + 2/8) = 5/2.75: 1e-15 relative covers the one rounding */
  assert_true(fabs(sc.speedup - 5.0 / 2.75) <= 1e-15 * sc.speedup);
  dtm_subcycling_free(&sc);
  const double far[NB] = {d, d, d, ldexp(d, 70), ldexp(d, 63)};
  assert_int_equal(dtm_subcycling_levels(far, NB, d, &sc), 0);
  assert_int_equal(sc.level[3], DTM_MAX_LEVELS - 1);
  assert_int_equal(sc.level[4], DTM_MAX_LEVELS - 1);
  assert_int_equal(sc.nlevels, DTM_MAX_LEVELS);
  assert_int_equal(sc.count[DTM_MAX_LEVELS - 1], 2);
  dtm_subcycling_free(&sc);
  (void)unused;
}

/* Bars 2L, L, 2L (nodes 0..3). lambda_e = 4 c^2 / L_e^2, lumped masses
 * rho L_e / 2 per node. Inner node: (4c^2/(4L^2) rho L + 4c^2/L^2 rho L/2) /
 * (rho L + rho L/2) = 2 c^2/L^2, dt = 2/sqrt(lambda) = sqrt(2) L/c; end
 * nodes: c^2/L^2, dt = 2L/c. Own steps: outer bars max(2L, sqrt2 L)/c =
 * 2L/c, middle bar max(L, sqrt2 L)/c = sqrt2 L/c. Tolerance 1e-12
 * relative: a few roundings in the kernel and the nodal sums. */
static void basis_levels(void **unused) {
  const double L = 0.25, len[3] = {2 * L, L, 2 * L}, c = sqrt(200e9 / 8000);
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  tu_bar_scene(&s, &se, &sm, 0);
  dtm_analysis *a = tu_bar_analysis(&s, 3, len, NULL, 0);
  const double *own = dtm_analysis_local_step(a), want[3] = {2 * L / c, sqrt(2.0) * L / c, 2 * L / c};
  for (int e = 0; e < 3; e++) assert_true(fabs(own[e] - want[e]) <= 1e-12 * want[e]);
  assert_true(fabs(dtm_analysis_recommended(a) - 0.9 * want[1]) <= 1e-12 * want[1]);
  dtm_subcycling sc;
  assert_int_equal(dtm_subcycling_compute(a, &sc), 0);
  for (int e = 0; e < 3; e++) assert_int_equal(sc.level[e], 0);
  assert_true(sc.speedup == 1.0 && sc.basis == dtm_analysis_recommended(a));
  dtm_subcycling_free(&sc);
  const double below[2] = {0.5, 1.0};
  assert_int_equal(dtm_subcycling_levels(below, 2, 1.0, &sc), 0);
  assert_true(sc.level[0] == 0 && sc.level[1] == 0 && sc.speedup == 1.0);
  dtm_subcycling_free(&sc);
  dtm_analysis_destroy(&a);
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(bar_levels), cmocka_unit_test(level_rule),
                                     cmocka_unit_test(basis_levels)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
