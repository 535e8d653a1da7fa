/* The cohesive effect against hand computations:
 * - R = (pi/8) E' Gc / strength^2 with E' = E/(1-nu^2) (plane strain, 3D)
 *   and E (plane stress); hmax = R/N; resolution = R / mean edge;
 * - the spring limit 2/sqrt(k (1/m1 + 1/m2)) on a bar and a right triangle;
 * - without stiffness, exactly 1/30 of the elastic element step;
 * - elements outside the cohesive groups are not limited. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "fixtures.h"

extern const dtm_effect_class dtm_effect_cohesive, dtm_effect_elastic;

static void *make(tu_effect_fixture *f, int dim, const char *const *attrs) {
  void *s = NULL;
  tu_fixture_init(f, "cohesive", dim, attrs);
  assert_int_equal(dtm_effect_cohesive.create(&f->args, &s), 0);
  return s;
}

static const double tri[3][3] = {{0, 0, 0}, {1e-3, 0, 0}, {0, 1e-3, 0}};

/* Closed form, 1e-14 relative (a few roundings). */
static void zone_length(void **unused) {
  tu_effect_fixture f;
  dtm_material m;
  tu_material(&m, "granite", "E", 60e9, "nu", 0.25, "rho", 2700.0, "fracture-energy", 50.0, "strength", 10e6, NULL);
  const dtm_material *mats[1] = {&m};
  dtm_batch b = tu_batch1(DTM_TRI3, &tri[0][0], mats);
  const double R_strain = 3.14159265358979323846 / 8 * 60e9 / (1 - 0.0625) * 50 / 1e14; /* 0.0094248 m */
  const double mean_edge = (2e-3 + sqrt(2) * 1e-3) / 3;
  double hmax, res;
  void *s = make(&f, 2, (const char *const[]){"groups", "rock", "elements-per-zone", "8", NULL});
  assert_int_equal(dtm_effect_cohesive.accuracy(s, &b, &hmax, &res), 0);
  assert_true(fabs(hmax - R_strain / 8) <= 1e-14 * hmax);
  assert_true(fabs(res - R_strain / mean_edge) <= 1e-14 * res);
  dtm_effect_cohesive.destroy(&s);
  s = make(&f, 2, (const char *const[]){"groups", "rock", "formulation", "plane-stress", NULL});
  assert_int_equal(dtm_effect_cohesive.accuracy(s, &b, &hmax, &res), 0);
  assert_true(fabs(hmax - R_strain * (1 - 0.0625) / 5) <= 1e-14 * hmax); /* E' = E, N = 5 default */
  dtm_effect_cohesive.destroy(&s);
  (void)unused;
}

/* Right triangle, legs a: lumped mass rho (a^2/2)/3 per node; the springs
 * on the hypotenuse k = K a sqrt(2)/2 per node are the stiffest, so
 * dt = 2/sqrt(k (2/m)). 1e-14 relative. */
static void spring_limit(void **unused) {
  tu_effect_fixture f;
  dtm_material m;
  tu_material(&m, "granite", "E", 60e9, "nu", 0.25, "rho", 2700.0, NULL);
  const dtm_material *mats[1] = {&m};
  dtm_batch b = tu_batch1(DTM_TRI3, &tri[0][0], mats);
  const double a = 1e-3, K = 1e14, mass = 2700.0 * a * a / 2 / 3, k = K * a * sqrt(2) / 2;
  double dt, len;
  void *s = make(&f, 2, (const char *const[]){"groups", "rock", "stiffness", "1e14", NULL});
  assert_int_equal(dtm_effect_cohesive.element_dt(s, &b, &dt, &len), 0);
  assert_true(fabs(dt - 2 / sqrt(k * 2 / mass)) <= 1e-14 * dt);
  dtm_effect_cohesive.destroy(&s);
  (void)unused;
}

/* 2-node bar, unit cross-section: m = rho L/2 per node, k = K:
 * dt = 2/sqrt(K 2/m) = sqrt(2m/K) = sqrt(rho L/K). */
static void spring_limit_bar(void **unused) {
  tu_effect_fixture f;
  dtm_material m;
  tu_material(&m, "steel", "E", 210e9, "rho", 7850.0, "nu", 0.3, NULL);
  const dtm_material *mats[1] = {&m};
  const double x[2][3] = {{0, 0, 0}, {0.01, 0, 0}};
  dtm_batch b = tu_batch1(DTM_LINE2, &x[0][0], mats);
  double dt, len;
  void *s = make(&f, 1, (const char *const[]){"groups", "rock", "stiffness", "1e12", NULL});
  assert_int_equal(dtm_effect_cohesive.element_dt(s, &b, &dt, &len), 0);
  assert_true(fabs(dt - sqrt(7850.0 * 0.01 / 1e12)) <= 1e-14 * dt);
  dtm_effect_cohesive.destroy(&s);
  (void)unused;
}

static void literature_rule(void **unused) {
  tu_effect_fixture f, fe;
  dtm_material m;
  tu_material(&m, "granite", "E", 60e9, "nu", 0.25, "rho", 2700.0, NULL);
  const dtm_material *mats[1] = {&m};
  dtm_batch b = tu_batch1(DTM_TRI3, &tri[0][0], mats);
  double dt, len, dte, lene;
  void *s = make(&f, 2, (const char *const[]){"groups", "rock", NULL}), *se = NULL;
  tu_fixture_init(&fe, "elastic", 2, (const char *const[]){"formulation", "plane-strain", NULL});
  assert_int_equal(dtm_effect_elastic.create(&fe.args, &se), 0);
  assert_int_equal(dtm_effect_cohesive.element_dt(s, &b, &dt, &len), 0);
  assert_int_equal(dtm_effect_elastic.element_dt(se, &b, &dte, &lene), 0);
  assert_true(fabs(dt - dte / 30) <= 1e-14 * dt);
  dtm_effect_cohesive.destroy(&s);
  dtm_effect_elastic.destroy(&se);
  (void)unused;
}

static void outside_groups(void **unused) {
  tu_effect_fixture f;
  dtm_material m;
  tu_material(&m, "granite", "E", 60e9, "nu", 0.25, "rho", 2700.0, NULL);
  const dtm_material *mats[1] = {&m};
  dtm_batch b = tu_batch1(DTM_TRI3, &tri[0][0], mats);
  static const int nogroup = -1;
  b.group = &nogroup;
  double dt, len, hmax, res;
  void *s = make(&f, 2, (const char *const[]){"groups", "rock", NULL});
  assert_int_equal(dtm_effect_cohesive.element_dt(s, &b, &dt, &len), 0);
  assert_true(isinf(dt));
  assert_int_equal(dtm_effect_cohesive.accuracy(s, &b, &hmax, &res), 0);
  assert_true(isinf(hmax) && isnan(res));
  dtm_effect_cohesive.destroy(&s);
  (void)unused;
}

static void unknown_group(void **unused) {
  tu_effect_fixture f;
  void *s = NULL;
  tu_fixture_init(&f, "cohesive", 2, (const char *const[]){"groups", "shale", NULL});
  assert_int_equal(dtm_effect_cohesive.create(&f.args, &s), DTM_ERR_INPUT);
  assert_non_null(strstr(dtm_error_message(), "fixture.xml:7"));
  assert_non_null(strstr(dtm_error_message(), "'shale'"));
  assert_non_null(strstr(dtm_error_message(), "'rock'"));
  dtm_error_clear();
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(zone_length),      cmocka_unit_test(spring_limit),
                                     cmocka_unit_test(spring_limit_bar), cmocka_unit_test(literature_rule),
                                     cmocka_unit_test(outside_groups),   cmocka_unit_test(unknown_group)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
