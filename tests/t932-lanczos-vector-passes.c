/* The global Lanczos run's vector passes (src/spectral/lzvec.c) against
 * their definition: every sum is the chunks' sums (DTM_VCHUNK unknowns
 * each) added in the chunks' order, each chunk's in eight interleaved
 * partial sums added pairwise. The passes share the chunks among OpenMP's
 * threads above 16 chunks; the definition is written here serially, so
 * equal bits (not a tolerance) show that the result does not depend on how
 * the chunks were shared, on vectors of 100,003 unknowns (25 chunks, the
 * last partial; the threaded path) and 20,011 (5 chunks; the serial one).
 * The updates are elementwise and must match bit for bit too. Each sum is
 * also checked against a long double sum to 1e-13 relative (a sum of 1e5
 * products of values in [-1, 1]: the fixed order's rounding is far below,
 * about 1e-16 sqrt(n) for random signs, 1e-14 at worst here). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "spectral.h"

#define NV 5      /* basis vectors */
#define REL 1e-13 /* against long double */
#define LANES 8   /* the definition's partial sums per chunk */

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uniform(void) { /* in [-1, 1) */
  rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
  return (double)(rng >> 11) * 0x1.0p-52 - 1.0;
}

static double *random_vec(size_t n) {
  double *v = malloc(n * sizeof *v);
  for (size_t i = 0; i < n; i++) v[i] = uniform();
  return v;
}

/* The definition: chunk by chunk, eight lanes, pairwise, then in order. */
static double def_dot(size_t n, const double *x, const double *y) {
  double s = 0;
  for (size_t lo = 0; lo < n; lo += DTM_VCHUNK) {
    size_t m = n - lo < DTM_VCHUNK ? n - lo : DTM_VCHUNK, i = 0;
    double p[LANES] = {0};
    for (; i + LANES <= m; i += LANES)
      for (int l = 0; l < LANES; l++) p[l] += x[lo + i + l] * y[lo + i + l];
    for (; i < m; i++) p[0] += x[lo + i] * y[lo + i];
    s += ((p[0] + p[1]) + (p[2] + p[3])) + ((p[4] + p[5]) + (p[6] + p[7]));
  }
  return s;
}

static long double exact_dot(size_t n, const double *x, const double *y) {
  long double s = 0;
  for (size_t i = 0; i < n; i++) s += (long double)x[i] * y[i];
  return s;
}

static void near(double got, long double want, double scale) {
  assert_true(fabsl((long double)got - want) <= REL * scale);
}

static void check_size(size_t n) {
  double *w = random_vec(n), *x = random_vec(n), *y = random_vec(n), *ref = malloc(n * sizeof *ref);
  double *V[NV], sc[NV], c[NV], cref[NV], d[2];
  double *part = malloc(dtm_vchunks(n) * (NV + 2) * sizeof *part);
  for (int j = 0; j < NV; j++) V[j] = random_vec(n), sc[j] = 0.5 + 0.25 * j;
  /* dtm_vstep: w = s w - t x; w . y; w . w */
  const double s = 0.75, t = -1.25;
  for (size_t i = 0; i < n; i++) ref[i] = s * w[i] - t * x[i];
  dtm_vstep(n, w, s, t, x, y, part, d);
  assert_memory_equal(w, ref, n * sizeof *w);
  assert_true(d[0] == def_dot(n, ref, y) && d[1] == def_dot(n, ref, ref));
  near(d[0], exact_dot(n, ref, y), (double)n), near(d[1], exact_dot(n, ref, ref), (double)n);
  /* dtm_vproject: c_j = sc_j (w . V_j) */
  dtm_vproject(n, w, V, sc, NV, part, c);
  for (int j = 0; j < NV; j++) {
    cref[j] = sc[j] * def_dot(n, w, V[j]);
    assert_true(c[j] == cref[j]);
    near(c[j], sc[j] * exact_dot(n, w, V[j]), (double)n);
  }
  /* dtm_vsubtract: w -= sum_j c_j sc_j V_j, in j's order; |w|^2 */
  for (size_t i = 0; i < n; i++)
    for (int j = 0; j < NV; j++) ref[i] -= cref[j] * sc[j] * V[j][i];
  double ww = dtm_vsubtract(n, w, V, sc, c, NV, part);
  assert_memory_equal(w, ref, n * sizeof *w);
  assert_true(ww == def_dot(n, ref, ref));
  /* dtm_vcombine: y = sum_j c_j sc_j V_j */
  for (size_t i = 0; i < n; i++) {
    ref[i] = 0;
    for (int j = 0; j < NV; j++) ref[i] += cref[j] * sc[j] * V[j][i];
  }
  dtm_vcombine(n, y, V, sc, c, NV);
  assert_memory_equal(y, ref, n * sizeof *y);
  for (int j = 0; j < NV; j++) free(V[j]);
  free(w), free(x), free(y), free(ref), free(part);
}

static void threaded(void **state) {
  (void)state;
  check_size(100003);
}

static void serial(void **state) {
  (void)state;
  check_size(20011);
}

int main(void) {
  assert_int_equal(dtm_vchunks(100003), 25);
  const struct CMUnitTest tests[] = {cmocka_unit_test(threaded), cmocka_unit_test(serial)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
