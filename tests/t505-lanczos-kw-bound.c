/* The arithmetic of the probable bound (src/spectral/lanczos.c,
 * dtm_lanczos_kw_eps and dtm_lanczos_kw_steps): the Kuczynski-Wozniakowski
 * bound for Lanczos from a start uniform on the sphere,
 * P((lambda_max - theta_k) / lambda_max >= eps) <= 1.648 sqrt(n)
 * exp(-sqrt(eps) (2k - 1)), solved for eps at a failure probability p:
 * eps_k = (ln(1.648 sqrt(n) / p) / (2k - 1))^2, and for k at a given eps.
 *
 * Hand values. n = 6e5, p = 1e-12: ln(1.648) + ln(6e5)/2 + 12 ln(10) =
 * 0.4995 + 6.6514 + 27.6310 = 34.782, so eps = 0.19 (safety 0.9) needs
 * 2k - 1 >= 34.782 / 0.43589 = 79.80, k >= 40.40: 41 steps (issue 45's
 * figure). n = 1e5, k = 60: ln(1.648e-12^-1 sqrt(1e5)) = 0.4995 + 5.7565 +
 * 27.6310 = 33.887, eps = (33.887 / 119)^2 = 0.08109.
 * Tolerances: the hand values above to their printed digits (1e-3
 * relative); the round trips (the bound at eps_k is p, the step count is
 * the smallest that reaches eps) to 1e-12 relative, a few roundings of
 * log, exp and sqrt. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "dtmap/operator.h"

#define P 1e-12

static double bound(double n, int k, double eps) { return 1.648 * sqrt(n) * exp(-sqrt(eps) * (2.0 * k - 1)); }

static void test_hand_values(void **state) {
  (void)state;
  assert_int_equal(dtm_lanczos_kw_steps(6e5, 0.19, P), 41);
  assert_true(fabs(dtm_lanczos_kw_eps(1e5, 60, P) / 0.08109 - 1) < 1e-3);
  assert_true(DTM_LANCZOS_FAILURE == P);
}

/* At eps_k the bound is exactly p; k steps reach eps and k - 1 do not. */
static void test_round_trips(void **state) {
  (void)state;
  const double ns[] = {1e3, 3.3e4, 1e5, 6e5, 3.6e6, 3e7};
  const double eps[] = {0.19, 0.0975, 0.01, 0.5};
  for (int i = 0; i < 6; i++) {
    for (int k = 20; k <= 400; k += 19) {
      double e = dtm_lanczos_kw_eps(ns[i], k, P);
      assert_true(e > 0 && e < 1);
      assert_true(fabs(bound(ns[i], k, e) / P - 1) < 1e-12);
      assert_true(dtm_lanczos_kw_eps(ns[i], k + 1, P) < e); /* more steps, a tighter bound */
    }
    for (int j = 0; j < 4; j++) {
      int k = dtm_lanczos_kw_steps(ns[i], eps[j], P);
      assert_true(dtm_lanczos_kw_eps(ns[i], k, P) <= eps[j]);
      assert_true(k == 1 || dtm_lanczos_kw_eps(ns[i], k - 1, P) > eps[j]);
    }
  }
}

/* No information: no steps, or a bound that cannot reach p below eps = 1;
 * nothing to bound: a logarithm <= 0 (p above 1.648 sqrt(n)). */
static void test_limits(void **state) {
  (void)state;
  assert_true(dtm_lanczos_kw_eps(1e5, 0, P) == 1);
  assert_true(dtm_lanczos_kw_eps(1e5, 1, P) == 1);  /* one step: ln(...) = 33.9 > 1 */
  assert_true(dtm_lanczos_kw_eps(1e5, 17, P) == 1); /* 2k - 1 = 33 < 33.89 */
  assert_true(dtm_lanczos_kw_eps(1e5, 18, P) < 1);
  assert_true(dtm_lanczos_kw_eps(1, 5, 2.0) == 0);
  assert_int_equal(dtm_lanczos_kw_steps(1, 0.1, 2.0), 1);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_hand_values), cmocka_unit_test(test_round_trips),
                                     cmocka_unit_test(test_limits)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
