/* Two numeric helpers of the summaries, each a pass over a million values
 * that must not cost like one:
 * - the k-th smallest of an array by Hoare's selection, O(n) on average:
 *   the 1 % quantile of the element steps and the medians of the accuracy
 *   measures, where a full sort of a million values took a tenth of a
 *   second. The pivot is the median of three, so sorted or reversed input
 *   stays linear;
 * - the octave of a value, floor(log2(q)), as log2 gives it, from the
 *   value's bits: the summary's histogram of the steps (a third of the
 *   summary's time went to log2). */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "dtmap/util.h"

double dtm_select_kth(double *a, size_t n, size_t k) {
  ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, want = (ptrdiff_t)k;
  while (lo < hi) {
    ptrdiff_t i = lo, j = hi;
    double x = a[lo], y = a[lo + (hi - lo) / 2], z = a[hi];
    double pivot = x < y ? (y < z ? y : x < z ? z : x) : (x < z ? x : y < z ? z : y);
    while (i <= j) {
      while (a[i] < pivot) i++;
      while (a[j] > pivot) j--;
      if (i <= j) {
        double t = a[i];
        a[i++] = a[j], a[j--] = t;
      }
    }
    if (want <= j)
      hi = j;
    else if (want >= i)
      lo = i;
    else
      return a[want]; /* between the parts: equal to the pivot */
  }
  return a[want];
}

/* Where q lies within 2^14 units in the last place of a power of two,
 * log2's rounding (its result within 1 unit in its own last place) may
 * reach the integer, and log2 itself decides; as for q subnormal, zero,
 * infinite or NaN. One in 2^37 of uniformly spread values takes the call. */
int dtm_octave(double q) {
  uint64_t b;
  memcpy(&b, &q, sizeof b);
  uint64_t e = b >> 52 & 0x7ff, frac = b & ((UINT64_C(1) << 52) - 1), near = UINT64_C(1) << 14;
  if (e == 0 || e == 0x7ff || (b >> 63) || frac < near || frac > (UINT64_C(1) << 52) - near) return (int)floor(log2(q));
  return (int)e - 1023;
}
