/* The seeded random generator behind the Lanczos start vector and the
 * random part of `dtmap verify`'s initial field: splitmix64 (Steele, Lea and
 * Flood), which is fast, passes BigCrush, and needs one word of state, so a
 * seed reproduces a run exactly. */
#include "base.h"

uint64_t dtm_rng_next(uint64_t *state) {
  uint64_t z = (*state += 0x9e3779b97f4a7c15u);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
  return z ^ (z >> 31);
}

double dtm_rng_uniform(uint64_t *state, double lo, double hi) {
  return lo + (hi - lo) * ((double)(dtm_rng_next(state) >> 11) * 0x1.0p-53);
}
