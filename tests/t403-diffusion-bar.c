/* The diffusion effects on a 2-node bar with lumped capacity: C = (h/2) I,
 * K = (D/h) [1 -1; -1 1], so lambda_max(C^-1 K) = 4D/h^2 and the forward
 * Euler limit is dt = 2/lambda = h^2/(2D), with characteristic length h.
 * Thermal uses D = k/(rho c), hydraulic D = permeability/(viscosity storage);
 * both share one kernel. Also: halving h quarters dt (exponent 2). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "fixtures.h"

extern const dtm_effect_class dtm_effect_thermal, dtm_effect_hydraulic;

static void bar_dt(const dtm_effect_class *c, const dtm_material *m, double h, double *dt, double *len) {
  const double x[2][3] = {{0.3, 0.0, 0.0}, {0.3 + h, 0.0, 0.0}};
  const dtm_material *mats[1] = {m};
  dtm_batch b = tu_batch1(DTM_LINE2, &x[0][0], mats);
  tu_effect_fixture f;
  void *state = NULL;
  tu_fixture_init(&f, c->name, 1, NULL);
  assert_int_equal(c->create(&f.args, &state), 0);
  assert_int_equal(c->element_dt(state, &b, dt, len), 0);
  c->destroy(&state);
}

/* 1 when class c declares material property name as required. */
static int needs(const dtm_effect_class *c, const char *name) {
  for (const dtm_property *p = c->properties; p && p->name; p++)
    if (!strcmp(p->name, name)) return p->required;
  return 0;
}

/* Tolerance 1e-13 relative: a handful of roundings in the kernel and here. */
static void thermal_bar(void **unused) {
  dtm_material m;
  tu_material(&m, "granite", "conductivity", 3.0, "heat-capacity", 790.0, "rho", 2700.0, NULL);
  const double D = 3.0 / (2700.0 * 790.0), h = 2e-3;
  double dt, len;
  bar_dt(&dtm_effect_thermal, &m, h, &dt, &len);
  assert_true(fabs(dt - h * h / (2 * D)) <= 1e-13 * dt);
  assert_true(fabs(len - h) <= 1e-13 * h);
  double dt2, len2;
  bar_dt(&dtm_effect_thermal, &m, h / 2, &dt2, &len2);
  assert_true(fabs(dt2 - dt / 4) <= 1e-13 * dt);
  (void)unused;
}

static void hydraulic_bar(void **unused) {
  dtm_material m;
  tu_material(&m, "granite", "permeability", 1e-15, "viscosity", 1e-3, "storage", 1e-9, NULL);
  const double D = 1e-15 / (1e-3 * 1e-9), h = 0.01;
  double dt, len;
  bar_dt(&dtm_effect_hydraulic, &m, h, &dt, &len);
  assert_true(fabs(dt - h * h / (2 * D)) <= 1e-13 * dt);
  (void)unused;
}

/* Effects declare their scaling exponents and needs. */
static void declarations(void **unused) {
  assert_true(dtm_effect_thermal.exponent == 2.0 && dtm_effect_hydraulic.exponent == 2.0);
  assert_true(needs(&dtm_effect_thermal, "conductivity"));
  assert_false(needs(&dtm_effect_thermal, "E"));
  assert_true(needs(&dtm_effect_hydraulic, "permeability"));
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(thermal_bar), cmocka_unit_test(hydraulic_bar),
                                     cmocka_unit_test(declarations)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
