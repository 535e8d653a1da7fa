/* The numeric helpers of the summaries (src/base/numbers.c):
 *   - dtm_octave(q) is the integer floor(log2(q)) gives, for random values
 *     over the whole exponent range, for the values within 2^15 units in
 *     the last place on either side of powers of two (where log2's rounding
 *     may reach the integer and the bits alone would say one less), and for
 *     subnormals;
 *   - dtm_select_kth(a, n, k) returns the value at position k of the sorted
 *     array and leaves a partitioned around it (every value before k at
 *     most it, every one after at least it: the accuracy medians read the
 *     values before k), on random arrays, arrays with many equal values,
 *     sorted and reversed ones, one value, and every k of small arrays.
 * Tolerance: none; both are exact (an integer, and one of the array's own
 * values). */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "dtmap/util.h"

static uint64_t state = 0x9e3779b97f4a7c15ull;

static uint64_t next(void) { /* xorshift64*: reproducible, independent of libc */
  state ^= state >> 12, state ^= state << 25, state ^= state >> 27;
  return state * 0x2545f4914f6cdd1dull;
}

static void octave_is_log2(double q) {
  int want = (int)floor(log2(q)), got = dtm_octave(q);
  if (want != got) fail_msg("dtm_octave(%a) = %d, floor(log2) = %d", q, got, want);
}

static void test_octave_random(void **st) {
  (void)st;
  for (int i = 0; i < 2000000; i++) {
    uint64_t b = next() & 0x7fffffffffffffffull; /* positive */
    double q;
    memcpy(&q, &b, sizeof q);
    if (isfinite(q) && q > 0) octave_is_log2(q);
  }
  for (int i = 0; i < 1000000; i++) octave_is_log2(ldexp(0.5 + 0.5 * (double)(next() >> 11) * 0x1p-53, i % 80 - 40));
}

/* Within 2^15 units in the last place either side of 2^e, e from -1022 to
 * 1023 in steps (each value checked), and a denser walk near the steps'
 * usual range (a step map's ratios lie between 2^-40 and 2^40). */
static void test_octave_near_powers(void **st) {
  (void)st;
  for (int e = -1021; e <= 1023; e += (e > -60 && e < 60) ? 1 : 37) {
    double p = ldexp(1.0, e), up = p, down = p;
    octave_is_log2(p);
    for (int k = 0; k < (1 << 15); k++) {
      up = nextafter(up, INFINITY), down = nextafter(down, 0.0);
      octave_is_log2(up);
      octave_is_log2(down);
    }
  }
}

static void test_octave_subnormal(void **st) {
  (void)st;
  for (double q = 0x1p-1074; q < 0x1p-1020; q *= 1.7) octave_is_log2(q);
  octave_is_log2(DBL_MIN);
  octave_is_log2(nextafter(DBL_MIN, 0.0));
  octave_is_log2(DBL_MAX);
}

static int by_value(const void *x, const void *y) {
  double a = *(const double *)x, b = *(const double *)y;
  return (a > b) - (a < b);
}

/* dtm_select_kth on a copy of v[n] at k: the sorted array's value, and the
 * copy partitioned around position k. */
static void check_select(const double *v, size_t n, size_t k) {
  double *a = malloc(n * sizeof *a), *s = malloc(n * sizeof *s);
  assert_non_null(a);
  assert_non_null(s);
  memcpy(a, v, n * sizeof *a), memcpy(s, v, n * sizeof *s);
  qsort(s, n, sizeof *s, by_value);
  double got = dtm_select_kth(a, n, k);
  assert_true(got == s[k]);
  assert_true(a[k] == got);
  for (size_t i = 0; i < k; i++) assert_true(a[i] <= got);
  for (size_t i = k + 1; i < n; i++) assert_true(a[i] >= got);
  qsort(a, n, sizeof *a, by_value); /* a permutation of v */
  assert_memory_equal(a, s, n * sizeof *a);
  free(a), free(s);
}

static void test_select(void **st) {
  (void)st;
  enum { N = 100001 };
  double *v = malloc(N * sizeof *v);
  assert_non_null(v);
  for (size_t i = 0; i < N; i++) v[i] = (double)(next() >> 11) * 0x1p-53;
  check_select(v, N, (N - 1) / 100), check_select(v, N, N / 2), check_select(v, N, 0), check_select(v, N, N - 1);
  for (size_t i = 0; i < N; i++) v[i] = (double)(next() % 7); /* many equal values */
  check_select(v, N, (N - 1) / 100), check_select(v, N, N / 2);
  for (size_t i = 0; i < N; i++) v[i] = (double)i; /* sorted, then reversed */
  check_select(v, N, N / 3);
  for (size_t i = 0; i < N; i++) v[i] = (double)(N - i);
  check_select(v, N, N / 3);
  v[0] = 4.25;
  check_select(v, 1, 0);
  for (size_t n = 2; n <= 9; n++)
    for (size_t k = 0; k < n; k++) {
      for (size_t i = 0; i < n; i++) v[i] = (double)(next() % 4);
      check_select(v, n, k);
    }
  free(v);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_octave_random),
      cmocka_unit_test(test_octave_near_powers),
      cmocka_unit_test(test_octave_subnormal),
      cmocka_unit_test(test_select),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
