/* An effect that fails on one element is named by the core: the element's
 * tag, type, physical group and centroid, the effect's name and its own
 * message, in the scene's name, although the effect sees only a batch of
 * coordinates and tags. The mesh is three bars of lengths L, l, L on the x
 * axis in a group "rock"; the effect is the elastic bar with element_dt
 * wrapped to fail on element 2, whose centroid is at x = L + l/2 exactly
 * in binary for the lengths below (0.5 + 0.125 / 2). A failure that an
 * element-at-a-time rerun does not reproduce keeps the batch's message. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "analysis-impl.h"
#include "fixtures.h"

static int (*real_dt)(void *, const dtm_batch *, double *, double *);
static int calls, fail_batches_only;

/* The real bound, except on element 2 (or, with fail_batches_only, on any
 * batch of more than one element). */
static int failing_dt(void *st, const dtm_batch *b, double *dt, double *len) {
  calls++;
  for (size_t e = 0; e < b->n; e++)
    if ((!fail_batches_only && b->tags[e] == 2) || (fail_batches_only && b->n > 1))
      return DTM_ERR(DTM_ERR_INPUT, "element %zu: the test's failure", b->tags[e]);
  return real_dt(st, b, dt, len);
}

static dtm_group rock = {1, 5, "rock"};

static int analyse_failing(char *msg, size_t len) {
  const double lens[3] = {0.5, 0.125, 0.5};
  const int group[3] = {0, 0, 0};
  static char *keys[] = {"formulation"}, *vals[] = {"bar"};
  dtm_scene_effect se = {"elastic", NULL, 5, 1, keys, vals};
  dtm_scene_material sm = {0};
  tu_material(&sm.m, "steel", "E", 200e9, "rho", 8000.0, NULL);
  sm.is_default = 1;
  dtm_scene s = {0};
  tu_scene_catalogue(&s);
  s.path = "bars.xml", s.nmaterials = 1, s.materials = &sm, s.neffects = 1, s.effects = &se, s.safety = 0.9;
  dtm_mesh *m = tu_bar_mesh(3, lens, group, NULL);
  m->ngroups = 1, m->groups = malloc(sizeof *m->groups);
  m->groups[0] = rock, m->groups[0].name = strdup(rock.name);
  dtm_effect *ef = NULL;
  int ne = 0;
  assert_int_equal(dtm_effects_create(&s, m, &ef, &ne), 0);
  static dtm_effect_class wrapped;
  wrapped = *ef[0].cls, real_dt = wrapped.element_dt, wrapped.element_dt = failing_dt;
  ef[0].cls = &wrapped;
  dtm_analysis *a = NULL;
  dtm_error_clear();
  calls = 0;
  int r = dtm_analysis_compute(&s, m, ef, ne, &a);
  snprintf(msg, len, "%s", dtm_error_message());
  dtm_error_clear();
  dtm_analysis_destroy(&a);
  return r;
}

static void names_the_element(void **unused) {
  char msg[1024];
  fail_batches_only = 0;
  assert_int_equal(analyse_failing(msg, sizeof msg), DTM_ERR_INPUT);
  fprintf(stderr, "%s\n", msg);
  assert_non_null(strstr(msg, "bars.xml: effect 'elastic' on element 2 (line2) in group 'rock' at (0.5625, 0, 0)"));
  assert_non_null(strstr(msg, "element 2: the test's failure"));
  assert_true(calls >= 3); /* the batch, then element 1 (passes) and element 2 (fails) */
  (void)unused;
}

static void keeps_the_batch_message(void **unused) {
  char msg[1024];
  fail_batches_only = 1;
  assert_int_equal(analyse_failing(msg, sizeof msg), DTM_ERR_INPUT);
  assert_non_null(strstr(msg, "bars.xml: effect 'elastic': element 1: the test's failure"));
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(names_the_element), cmocka_unit_test(keeps_the_batch_message)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
