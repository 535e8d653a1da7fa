/* The damping effect against closed forms and a single degree of freedom.
 * - factor(xi) = sqrt(1+xi^2) - xi for constant xi, and Rayleigh xi(omega) =
 *   alpha/(2 omega) + beta omega/2 taken at the element's own omega;
 * - a material's own xi replaces the global one;
 * - an SDOF oscillator integrated by central differences with the damping
 *   force on the lagged velocity stays bounded at 0.99 x the damped limit and
 *   grows at 1.01 x it, for xi from 0 to 10 (Rayleigh, large beta). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>

#include "fixtures.h"

extern const dtm_effect_class dtm_effect_damping;

static double factor_of(const char *const *attrs, const dtm_material *m, double omega) {
  tu_effect_fixture f;
  void *state = NULL;
  double fac = NAN;
  tu_fixture_init(&f, "damping", 3, attrs);
  assert_int_equal(dtm_effect_damping.create(&f.args, &state), 0);
  assert_int_equal(dtm_effect_damping.wave_factor(state, m, omega, &fac), 0);
  dtm_effect_damping.destroy(&state);
  assert_null(state);
  return fac;
}

/* Closed forms in double precision: 1e-14 relative covers a few roundings. */
static void constant_xi(void **unused) {
  dtm_material m;
  tu_material(&m, "rock", NULL);
  for (double xi = 0; xi <= 1.0; xi += 0.25) {
    char v[32];
    snprintf(v, sizeof v, "%.17g", xi);
    double f = factor_of((const char *const[]){"xi", v, NULL}, &m, 1e6);
    assert_true(fabs(f - (sqrt(1 + xi * xi) - xi)) <= 1e-14);
  }
  (void)unused;
}

static void rayleigh_at_element_omega(void **unused) {
  dtm_material m;
  tu_material(&m, "rock", NULL);
  const double alpha = 50.0, beta = 2e-6, omega = 4e6; /* xi = 6.25e-6 + 4 = 4.00000625 */
  double xi = alpha / (2 * omega) + beta * omega / 2;
  double f = factor_of((const char *const[]){"alpha", "50", "beta", "2e-6", NULL}, &m, omega);
  assert_true(fabs(f - (sqrt(1 + xi * xi) - xi)) <= 1e-12 * f);
  (void)unused;
}

static void material_overrides(void **unused) {
  dtm_material m;
  tu_material(&m, "soft", "xi", 0.5, NULL);
  double f = factor_of((const char *const[]){"xi", "0.05", NULL}, &m, 1e3);
  assert_true(fabs(f - (sqrt(1.25) - 0.5)) <= 1e-14);
  (void)unused;
}

/* Amplitude after n central-difference steps of x'' + 2 xi w v_{n-1/2} + w^2 x = 0. */
static double sdof_amplitude(double w, double xi, double dt, int n) {
  double x0 = 1.0, x1 = 1.0, peak = 0;
  for (int i = 0; i < n; i++) {
    double v = (x1 - x0) / dt, x2 = 2 * x1 - x0 - dt * dt * (w * w * x1 + 2 * xi * w * v);
    x0 = x1, x1 = x2;
    peak = fmax(peak, fabs(x1));
  }
  return peak;
}

static void sdof_stability(void **unused) {
  static const double xis[] = {0.0, 0.05, 0.3, 1.0, 10.0};
  dtm_material m;
  tu_material(&m, "rock", NULL);
  const double w = 1e5; /* rad/s */
  for (int i = 0; i < 5; i++) {
    /* Rayleigh with beta only: xi(w) = beta w / 2 */
    char beta[32];
    snprintf(beta, sizeof beta, "%.17g", 2 * xis[i] / w);
    double dt = 2.0 / w * factor_of((const char *const[]){"beta", beta, NULL}, &m, w);
    /* bounded: the start amplitude 1 is never exceeded by more than the
     * transient of an undamped oscillator at 0.99 of its limit (< 10) */
    assert_true(sdof_amplitude(w, xis[i], 0.99 * dt, 20000) < 10.0);
    /* unstable: growth beyond 1e6 within 20000 steps at 1.01 x */
    assert_true(sdof_amplitude(w, xis[i], 1.01 * dt, 20000) > 1e6);
  }
  (void)unused;
}

int main(int argc, char **argv) {
  (void)argc, (void)argv;
  const struct CMUnitTest tests[] = {cmocka_unit_test(constant_xi), cmocka_unit_test(rayleigh_at_element_omega),
                                     cmocka_unit_test(material_overrides), cmocka_unit_test(sdof_stability)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
