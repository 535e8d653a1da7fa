/* The accuracy measures and the run time of an analysis (src/cost/).
 * - Bar chain of 8 equal steel bars (L = 0.1 m, c = 5000 m/s): the
 *   recommended step is 0.9 L/c (nodal bound = element bound on a uniform
 *   chain), so the phase error at f-max is the 1D closed form
 *   2 asin(r sin(kh/2)) / (r kh) - 1 with r = 0.9. f = c/(8 L) puts kh on
 *   a node of the table (pi/4), so it agrees to round-off (1e-9).
 * - Without f-max: the mesh's default c/(10 L) = 5000 Hz, said in the note,
 *   and 10 elements per wavelength at it.
 * - f-max above what the mesh carries (1.5 cells per wavelength): every
 *   element unresolved, the worst NaN, outside the band.
 * - Hours: element-steps x the scene's cost-per-element-step / 3600, to
 *   1e-15, with the scene's file and line as the source; without one,
 *   dtmap's calibration (positive, named).
 * - Subcycling levels double an element's step: at level 1 the bar's
 *   Courant number is 1.8 > 1, unstable: NaN, never a number.
 * - Diffusion (thermal, bar chain): elements across sqrt(alpha t) =
 *   sqrt(alpha t) / L exactly; without a duration a note and NaN.
 * - Cohesive: one measure per group with cohesive elements, smallest and
 *   median R/h over that group only.
 * - Bad input: f-max and cost-per-element-step zero, negative or not
 *   finite fail with DTM_ERR_INPUT naming the scene file and the line. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dtmap/analysis.h"
#include "dtmap/cost.h"
#include "dtmap/error.h"
#include "fixtures.h"
#include "testutil.h"

#define N 8
#define L 0.1
#define C 5000.0 /* sqrt(200e9 / 8000) */
#define PI 3.14159265358979323846

static const double len[N] = {L, L, L, L, L, L, L, L};

static const dtm_measure *phase_of(const dtm_measures *m) {
  for (int k = 0; k < m->n; k++)
    if (m->m[k].kind == DTM_MEASURE_PHASE) return &m->m[k];
  fail_msg("no phase measure");
  return NULL;
}

static void bar_closed_form(void **state) {
  (void)state;
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  tu_bar_scene(&s, &se, &sm, 0);
  s.f_max = C / (8 * L);
  dtm_analysis *a = tu_bar_analysis(&s, N, len, NULL, 0);
  double r = dtm_analysis_recommended(a) * C / L, kh = PI / 4;
  assert_true(fabs(r - 0.9) < 1e-12);
  dtm_measures *m = NULL;
  assert_int_equal(dtm_measures_compute(a, 0, NULL, &m), DTM_OK);
  const dtm_measure *p = phase_of(m);
  double exact = 2 * asin(r * sin(kh / 2)) / (r * kh) - 1;
  /* the median is signed as the worst is (a lag, negative: issue 37) */
  assert_true(exact < 0 && fabs(p->worst - exact) < 1e-9 && fabs(p->median - exact) < 1e-9);
  assert_true(p->elements == N && !p->unresolved && !p->f_default && p->f == s.f_max);
  assert_int_equal(p->in_band, fabs(exact) <= DTM_BAND_PHASE);
  dtm_measures_destroy(&m);
  /* subcycling level 1 everywhere: Courant 1.8, unstable */
  int level[N] = {1, 1, 1, 1, 1, 1, 1, 1};
  dtm_measure_step st = {level, 0, NULL};
  assert_int_equal(dtm_measures_compute(a, 0, &st, &m), DTM_OK);
  assert_true(isnan(phase_of(m)->worst) && phase_of(m)->unresolved == N);
  dtm_measures_destroy(&m);
  dtm_analysis_destroy(&a);
}

static void default_and_unresolved(void **state) {
  (void)state;
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  tu_bar_scene(&s, &se, &sm, 0);
  dtm_analysis *a = tu_bar_analysis(&s, N, len, NULL, 0);
  dtm_measures *m = NULL;
  assert_int_equal(dtm_measures_compute(a, 0, NULL, &m), DTM_OK);
  const dtm_measure *p = phase_of(m);
  assert_true(p->f_default && fabs(p->f - C / (10 * L)) < 1e-9 * p->f);
  assert_non_null(strstr(p->note, "no <time f-max>"));
  assert_true(fabs(p->per_wavelength - 10) < 1e-9); /* c / (f L) at the default */
  assert_true(isfinite(p->worst));
  dtm_measures_destroy(&m);
  assert_int_equal(dtm_measures_compute(a, C / (1.5 * L), NULL, &m), DTM_OK);
  p = phase_of(m);
  assert_true(isnan(p->worst) && p->unresolved == N && !p->in_band);
  dtm_measures_destroy(&m);
  dtm_analysis_destroy(&a);
}

static void hours(void **state) {
  (void)state;
  dtm_scene s;
  dtm_scene_effect se;
  dtm_scene_material sm;
  tu_bar_scene(&s, &se, &sm, 0);
  s.duration = 1e-3, s.cost_per_element_step = 2e-6, s.time_line = 7;
  dtm_analysis *a = tu_bar_analysis(&s, N, len, NULL, 0);
  dtm_cost *c = NULL;
  assert_int_equal(dtm_cost_create(a, &c), DTM_OK);
  double want = N * ceil(1e-3 / dtm_analysis_recommended(a)) * 2e-6 / 3600;
  assert_true(fabs(c->hours - want) <= 1e-15 * want);
  assert_true(c->hours_subcycled <= c->hours * (1 + 1e-15));
  assert_non_null(strstr(c->per_element_step_source, "mem.xml:7"));
  assert_non_null(c->measures);
  dtm_cost_destroy(&c);
  s.cost_per_element_step = 0;
  assert_int_equal(dtm_cost_create(a, &c), DTM_OK);
  assert_true(c->per_element_step > 0 && isfinite(c->hours));
  assert_non_null(strstr(c->per_element_step_source, "bench/ccx_cost.py")); /* the measured CalculiX table */
  dtm_cost_destroy(&c);
  dtm_analysis_destroy(&a);
}

static void diffusion(void **state) {
  (void)state;
  dtm_scene s;
  dtm_scene_effect se = {"thermal", NULL, 5, 0, NULL, NULL};
  dtm_scene_material sm = {0};
  tu_material(&sm.m, "rock", "conductivity", 3.0, "rho", 2700.0, "heat-capacity", 790.0, NULL);
  sm.is_default = 1;
  s = (dtm_scene){0};
  tu_scene_catalogue(&s);
  s.path = "mem.xml", s.nmaterials = 1, s.materials = &sm, s.neffects = 1, s.effects = &se;
  s.safety = 0.9, s.duration = 100;
  dtm_analysis *a = tu_bar_analysis(&s, N, len, NULL, 0);
  dtm_measures *m = NULL;
  assert_int_equal(dtm_measures_compute(a, 0, NULL, &m), DTM_OK);
  assert_int_equal(m->n, 1);
  double want = sqrt(3.0 / (2700.0 * 790.0) * 100) / L;
  assert_int_equal(m->m[0].kind, DTM_MEASURE_DIFFUSION);
  assert_true(fabs(m->m[0].worst - want) < 1e-12 * want && fabs(m->m[0].median - want) < 1e-12 * want);
  assert_int_equal(m->m[0].in_band, want >= DTM_BAND_DIFFUSION);
  dtm_measures_destroy(&m);
  dtm_analysis_destroy(&a);
  s.duration = 0;
  a = tu_bar_analysis(&s, N, len, NULL, 0);
  assert_int_equal(dtm_measures_compute(a, 0, NULL, &m), DTM_OK);
  assert_true(isnan(m->m[0].worst) && strstr(m->m[0].note, "no <time duration>"));
  dtm_measures_destroy(&m);
  dtm_analysis_destroy(&a);
}

/* Cohesive on group "a" of a chain whose first four bars are in "a"
 * (lengths L, L, 2L, 2L) and the rest in "b": one measure, for "a", over
 * its four elements; the smallest is R/(2L) and the median the mean of R/L
 * and R/(2L), R read back from the first element's R/L. */
static void zones(void **state) {
  (void)state;
  static char *ek[] = {"formulation"}, *ev[] = {"bar"}, *ck[] = {"groups"}, *cv[] = {"a"};
  dtm_scene_effect se[2] = {{"elastic", NULL, 5, 1, ek, ev}, {"cohesive", NULL, 6, 1, ck, cv}};
  dtm_scene_material sm = {0};
  tu_material(&sm.m, "steel", "E", 200e9, "nu", 0.3, "rho", 8000.0, "fracture-energy", 100.0, "strength", 3e6, NULL);
  sm.is_default = 1;
  dtm_scene s = {0};
  tu_scene_catalogue(&s);
  s.path = "mem.xml", s.nmaterials = 1, s.materials = &sm, s.neffects = 2, s.effects = se, s.safety = 0.9;
  const double lens[N] = {L, L, 2 * L, 2 * L, L, L, L, L};
  const int group[N] = {0, 0, 0, 0, 1, 1, 1, 1};
  dtm_analysis *a = tu_bar_analysis(&s, N, lens, group, 2);
  dtm_measures *m = NULL;
  assert_int_equal(dtm_measures_compute(a, 0, NULL, &m), DTM_OK);
  const dtm_measure *z = NULL;
  for (int k = 0; k < m->n; k++)
    if (m->m[k].kind == DTM_MEASURE_ZONE) assert_null(z), z = &m->m[k];
  assert_non_null(z);
  double R = dtm_analysis_resolution(a, 1)[0] * L;
  assert_true(z->group == 0 && z->elements == 4 && z->band_lo == 5 && z->band_hi == 10);
  assert_true(fabs(z->worst - R / (2 * L)) < 1e-12 * z->worst);
  assert_true(fabs(z->median - 0.5 * (R / L + R / (2 * L))) < 1e-12 * z->median);
  assert_int_equal(z->in_band, z->worst >= 5);
  dtm_measures_destroy(&m);
  dtm_analysis_destroy(&a);
}

static void bad_input(void **state) {
  (void)state;
  static const char *attrs[] = {"f-max=\"0\"",
                                "f-max=\"-5\"",
                                "f-max=\"INF\"",
                                "f-max=\"NaN\"",
                                "cost-per-element-step=\"0\"",
                                "cost-per-element-step=\"-1e-9\"",
                                "cost-per-element-step=\"INF\""};
  char geo[600], xml[600], text[1024];
  snprintf(geo, sizeof geo, "%s/m.geo", tu_tmpdir());
  snprintf(xml, sizeof xml, "%s/m.xml", tu_tmpdir());
  tu_write(geo, "Point(1) = {0, 0, 0};\n");
  for (size_t i = 0; i < sizeof attrs / sizeof *attrs; i++) {
    snprintf(text, sizeof text,
             "<?xml version=\"1.0\"?>\n<dtmap-scene version=\"1\">\n  <geometry file=\"m.geo\"/>\n"
             "  <material name=\"steel\" default=\"true\" E=\"210e9\" nu=\"0.3\" rho=\"7850\"/>\n"
             "  <effects>\n    <elastic/>\n  </effects>\n  <time %s/>\n</dtmap-scene>\n",
             attrs[i]);
    tu_write(xml, text);
    dtm_scene *s = NULL;
    assert_int_equal(dtm_scene_load(xml, &s), DTM_ERR_INPUT);
    char where[700];
    snprintf(where, sizeof where, "%s:8:", xml);
    if (!strstr(dtm_error_message(), where)) fail_msg("%s: %s", attrs[i], dtm_error_message());
    dtm_error_clear();
  }
}

int main(int argc, char **argv) {
  tu_init(argc, argv);
  const struct CMUnitTest tests[] = {cmocka_unit_test(bar_closed_form), cmocka_unit_test(default_and_unresolved),
                                     cmocka_unit_test(hours),           cmocka_unit_test(diffusion),
                                     cmocka_unit_test(zones),           cmocka_unit_test(bad_input)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
